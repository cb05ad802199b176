"""Behaviour of both vehicle models: calibration, Table 1 turns, thruster lag, buoyancy, current."""

from __future__ import annotations

import math

import numpy as np
import pytest
from physics_helpers import ReferenceModel
from scipy.integrate import solve_ivp

from rov_envs.physics import ACTION_TABLE, BlueROV2Params
from rov_envs.physics.integrator import advance
from rov_envs.physics.params import VEHICLES, vehicle_params

ZERO = np.zeros(3)
PARAMS = {name: vehicle_params(name).to_array() for name in VEHICLES}
#: a pure yaw moment: the diagonal pairs against each other (X = Y = K = M = 0, N > 0)
PURE_YAW = np.array([-4000.0, 4000.0, 4000.0, -4000.0, 0.0, 0.0])


def _run(cmd, seconds, vehicle, state=None, current=ZERO, params=None):
    s = np.zeros(18) if state is None else state
    p = PARAMS[vehicle] if params is None else params
    for _ in range(round(seconds / 0.2)):
        advance(s, np.asarray(cmd, dtype=np.float64), p, current, 0.2, 4)
    return s


def _root(linear: float, quadratic: float, force: float) -> float:
    """The positive root of linear x + quadratic x|x| = force."""
    if quadratic == 0.0:
        return force / linear
    return (-linear + math.sqrt(linear**2 + 4 * quadratic * force)) / (2 * quadratic)


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_go_straight_settles_at_the_analytic_surge_root(vehicle):
    prm = vehicle_params(vehicle)
    # surge force from the thruster geometry: 4 thrusters, each cos(45 deg) of k n^2 along x
    x_force = 4.0 * prm.thrust_coefficient * 8000.0**2 * math.cos(math.pi / 4)
    root = _root(prm.linear_damping[0], prm.quadratic_damping[0], x_force)
    if vehicle == "uuv_simulator":
        assert root == pytest.approx(x_force / 11.7391, rel=1e-12)  # linear damping only
    s = _run(ACTION_TABLE[2], 120.0, vehicle)
    u, v, r = s[6], s[7], s[11]
    assert abs(root - 1.0) < 1e-9  # calibrated to 1.0 m/s
    # Wu's steady 8 deg pitch (module docstring of params) costs a little surge; UUV's is 1.7 deg
    assert abs(u - root) < (1e-3 if vehicle == "uuv_simulator" else 1e-2)
    assert abs(v) < 1e-9 and abs(r) < 1e-9 and abs(s[1]) < 1e-6 and abs(s[5]) < 1e-9
    assert abs(s[3]) < 1e-9  # roll
    assert abs(s[4]) < (0.05 if vehicle == "uuv_simulator" else 0.2)  # steady nose-up, no looping
    assert abs(s[10]) < 1e-3  # pitch rate has died out
    assert s[0] > 100.0  # it went forward


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_steady_yaw_rate_under_a_pure_yaw_moment_is_analytic(vehicle):
    prm = vehicle_params(vehicle)
    tau = prm.allocation_matrix() @ (prm.thrust_coefficient * np.abs(PURE_YAW) * PURE_YAW)
    np.testing.assert_allclose(tau[:5], 0.0, atol=1e-12)
    # spinning on the spot: no Coriolis term acts, so N_r r + N_r|r| r|r| = N
    r = _root(prm.linear_damping[5], prm.quadratic_damping[5], tau[5])
    s = _run(PURE_YAW, 30.0, vehicle)
    assert s[11] == pytest.approx(r, rel=1e-6)
    assert np.abs(s[6:11]).max() < 1e-9 and np.abs(s[:2]).max() < 1e-9
    if vehicle == "uuv_simulator":
        assert r == pytest.approx(tau[5] / 5.0, rel=1e-12)


@pytest.mark.parametrize("action", [1, 3])
def test_uuv_steady_turn_matches_solve_ivp(action):
    """A Table 1 turn of UUV Simulator's vehicle, 40 s, against scipy on the reference model."""
    prm = vehicle_params("uuv_simulator")
    cmd = ACTION_TABLE[action].copy()
    s = _run(cmd, 40.0, "uuv_simulator")
    ref = solve_ivp(
        ReferenceModel(prm).rhs, (0.0, 40.0), np.zeros(18), method="DOP853", rtol=1e-11,
        atol=1e-11, args=(cmd, ZERO),
    ).y[:, -1]  # fmt: skip
    np.testing.assert_allclose(s[6:12], ref[6:12], atol=1e-6)  # steady velocities
    np.testing.assert_allclose(s[:2], ref[:2], atol=1e-3)  # 40 s of circling


@pytest.mark.parametrize("vehicle", VEHICLES)
@pytest.mark.parametrize(
    ("action", "sign"), [(0, 1.0), (1, 1.0), (3, -1.0), (4, -1.0)], ids=["L1", "L2", "R1", "R2"]
)
def test_turns_turn_the_way_their_names_say(vehicle, action, sign):
    s = _run(ACTION_TABLE[action], 2.0, vehicle)
    assert sign * s[5] > (0.15 if vehicle == "uuv_simulator" else 0.6)  # heading change
    assert sign * s[11] > (0.1 if vehicle == "uuv_simulator" else 0.5)  # yaw rate
    assert sign * s[1] > 0.0  # it moved to the side it turned to


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_turn_2_faster_than_turn_1_and_left_mirrors_right(vehicle):
    rates = {a: _run(ACTION_TABLE[a], 30.0, vehicle)[11] for a in range(5)}
    slowest = 0.15 if vehicle == "uuv_simulator" else 0.8
    assert rates[1] > rates[0] > slowest
    assert rates[4] < rates[3] < -slowest
    assert rates[0] == pytest.approx(-rates[3], rel=1e-9)
    assert rates[1] == pytest.approx(-rates[4], rel=1e-9)


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_thruster_lag_is_first_order(vehicle):
    t_lag = vehicle_params(vehicle).thruster_time_constant
    p = PARAMS[vehicle]
    s = np.zeros(18)
    cmd = np.array([8000.0, -6000.0, 0, 0, 0, 0])
    advance(s, cmd, p, ZERO, t_lag, 50)
    frac = 1.0 - math.exp(-1.0)  # 63.2 %
    assert s[12] == pytest.approx(8000.0 * frac, rel=1e-6)
    assert s[13] == pytest.approx(-6000.0 * frac, rel=1e-6)
    advance(s, cmd, p, ZERO, 4 * t_lag, 50)
    assert s[12] == pytest.approx(8000.0 * (1 - math.exp(-5.0)), rel=1e-6)


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_presets_are_neutral_and_their_published_buoyancy_rises(vehicle):
    s = _run(np.zeros(6), 10.0, vehicle)
    assert np.abs(s).max() < 1e-12
    buoyant = getattr(BlueROV2Params, vehicle)(neutrally_buoyant=False)
    assert buoyant.buoyancy > buoyant.weight
    s = _run(np.zeros(6), 10.0, vehicle, params=buoyant.to_array())
    assert s[2] > 1.0  # z up: positively buoyant vehicle rises
    assert abs(s[0]) < 1e-6 and abs(s[4]) < 1e-6


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_tilted_vehicle_rights_itself(vehicle):
    s = np.zeros(18)
    s[3] = 0.3
    s[4] = -0.2
    _run(np.zeros(6), 30.0, vehicle, state=s)
    assert abs(s[3]) < 0.01 and abs(s[4]) < 0.01


@pytest.mark.parametrize("vehicle", VEHICLES)
@pytest.mark.parametrize("psi", [0.0, 1.0, -2.5])
def test_current_carries_a_vehicle_at_rest_along_it(vehicle, psi):
    current = np.array([0.4, -0.3, 0.0])
    s = np.zeros(18)
    s[5] = psi
    _run(np.zeros(6), 60.0, vehicle, state=s, current=current)
    before = s[:2].copy()
    _run(np.zeros(6), 1.0, vehicle, state=s, current=current)
    np.testing.assert_allclose(s[:2] - before, current[:2], atol=2e-3)


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_current_along_the_heading_does_not_turn_the_vehicle(vehicle):
    # (a current at an angle does turn it: the Munk moment u_r v_r (Y_vdot - X_udot) of C_A)
    psi = 0.7
    current = 0.5 * np.array([math.cos(psi), math.sin(psi), 0.0])
    s = np.zeros(18)
    s[5] = psi
    _run(np.zeros(6), 30.0, vehicle, state=s, current=current)
    assert abs(s[5] - psi) < 1e-5 and abs(s[11]) < 1e-5  # (Wu: an unstable equilibrium)
    assert s[0] == pytest.approx(s[1] / math.tan(psi), rel=1e-6)  # drifted along the current


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_surge_through_a_head_current_is_relative(vehicle):
    # water moving at -0.3 m/s along x: the vehicle keeps 1 m/s through the water
    s = _run(ACTION_TABLE[2], 120.0, vehicle, current=np.array([-0.3, 0.0, 0.0]))
    theta = s[4]
    assert s[6] - (-0.3 * math.cos(theta)) == pytest.approx(1.0, rel=1e-3)


def test_presets_by_name():
    assert BlueROV2Params() == BlueROV2Params.uuv_simulator() == vehicle_params("uuv_simulator")
    assert vehicle_params("wu2018") == BlueROV2Params.wu2018()
    uuv = BlueROV2Params.uuv_simulator()
    assert uuv.mass == 10.0 and uuv.r_g == (0.0, 0.0, 0.0) and uuv.metacentric_height == 0.3
    np.testing.assert_allclose(
        uuv.inertia,
        [2 * (0.2384**2 + 0.28066**2), 2 * (0.448**2 + 0.28066**2), 2 * (0.448**2 + 0.2384**2)],
    )
    assert uuv.added_mass == (1.7182, 0.0, 5.468, 0.0, 1.2481, 0.4006)
    assert uuv.linear_damping == (11.7391, 20.0, 31.8678, 25.0, 44.9085, 5.0)
    assert uuv.quadratic_damping == (0.0,) * 6 and uuv.thruster_time_constant == 0.05
    wu = BlueROV2Params.wu2018()
    assert wu.mass == 11.5 and wu.weight == wu.buoyancy and wu.thruster_time_constant == 0.1
    assert BlueROV2Params.wu2018(neutrally_buoyant=False).buoyancy == 114.8
    assert BlueROV2Params.uuv_simulator(neutrally_buoyant=False).buoyancy == pytest.approx(
        1028 * 0.011054 * 9.81
    )


@pytest.mark.parametrize("bad", ["uuv", "Wu2018", "", None, 0])
def test_unknown_vehicle_names_are_refused(bad):
    with pytest.raises(ValueError, match=r"vehicle=.* is not allowed: expected one of \['uuv_simu"):
        vehicle_params(bad)


def test_bad_parameters_are_refused():
    with pytest.raises(ValueError, match="mass"):
        BlueROV2Params(mass=-1.0)
    with pytest.raises(ValueError, match="added_mass"):
        BlueROV2Params(added_mass=(1.0, 2.0))
    with pytest.raises(ValueError, match="buoyancy"):
        BlueROV2Params(buoyancy=float("nan"))


def test_uuv_is_directionally_stable_and_wu_is_not():
    """After 5 s of Turn left 2, "Go straight" straightens UUV Simulator's vehicle out; Wu's
    settles into its steady spin (params docstring)."""
    results = {}
    for vehicle in VEHICLES:
        s = _run(ACTION_TABLE[1], 5.0, vehicle)
        results[vehicle] = _run(ACTION_TABLE[2], 30.0, vehicle, state=s)
    uuv, wu = results["uuv_simulator"], results["wu2018"]
    assert abs(uuv[11]) < 1e-4 and abs(uuv[7]) < 1e-4 and uuv[6] == pytest.approx(1.0, abs=1e-3)
    assert wu[11] == pytest.approx(1.14, abs=0.02) and wu[7] == pytest.approx(-0.55, abs=0.02)
