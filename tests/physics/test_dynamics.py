"""Behaviour of the vehicle model: calibration, Table 1 turns, thruster lag, buoyancy, current."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rov_envs.physics import ACTION_TABLE, BlueROV2Params
from rov_envs.physics.integrator import advance

P = BlueROV2Params().to_array()
ZERO = np.zeros(3)


def _run(cmd, seconds, state=None, current=ZERO, params=P):
    s = np.zeros(18) if state is None else state
    for _ in range(round(seconds / 0.2)):
        advance(s, np.asarray(cmd, dtype=np.float64), params, current, 0.2, 4)
    return s


def test_go_straight_settles_at_the_analytic_surge_root():
    prm = BlueROV2Params()
    # surge force from the thruster geometry: 4 thrusters, each cos(45 deg) of k n^2 along x
    thrust = prm.thrust_coefficient * 8000.0**2
    x_force = 4.0 * thrust * math.cos(math.pi / 4)
    root = (-4.03 + math.sqrt(4.03**2 + 4 * 18.18 * x_force)) / (2 * 18.18)
    s = _run(ACTION_TABLE[2], 120.0)
    u, v, r = s[6], s[7], s[11]
    assert abs(u - root) / root < 0.01
    assert abs(root - 1.0) < 1e-9  # calibrated to 1.0 m/s
    assert abs(v) < 1e-9 and abs(r) < 1e-9 and abs(s[1]) < 1e-6 and abs(s[5]) < 1e-9
    assert abs(s[3]) < 1e-9  # roll
    assert abs(s[4]) < 0.2  # steady nose-up pitch of ~8 deg from the low thrusters, no looping
    assert abs(s[10]) < 1e-3  # pitch rate has died out
    assert s[0] > 100.0  # it went forward


@pytest.mark.parametrize(
    ("action", "sign"), [(0, 1.0), (1, 1.0), (3, -1.0), (4, -1.0)], ids=["L1", "L2", "R1", "R2"]
)
def test_turns_turn_the_way_their_names_say(action, sign):
    s = _run(ACTION_TABLE[action], 1.0)
    assert sign * s[5] > 0.3  # heading change after 1 s
    assert sign * s[11] > 0.5  # yaw rate


def test_turn_2_faster_than_turn_1_and_left_mirrors_right():
    rates = {}
    for a in range(5):
        rates[a] = _run(ACTION_TABLE[a], 20.0)[11]
    assert rates[1] > rates[0] > 0.8
    assert rates[4] < rates[3] < -0.8
    assert rates[0] == pytest.approx(-rates[3], rel=1e-9)
    assert rates[1] == pytest.approx(-rates[4], rel=1e-9)


def test_thruster_lag_is_first_order():
    prm = BlueROV2Params()
    s = np.zeros(18)
    cmd = np.array([8000.0, -6000.0, 0, 0, 0, 0])
    advance(s, cmd, P, ZERO, prm.thruster_time_constant, 50)
    frac = 1.0 - math.exp(-1.0)  # 63.2 %
    assert s[12] == pytest.approx(8000.0 * frac, rel=1e-6)
    assert s[13] == pytest.approx(-6000.0 * frac, rel=1e-6)
    advance(s, cmd, P, ZERO, 4 * prm.thruster_time_constant, 50)
    assert s[12] == pytest.approx(8000.0 * (1 - math.exp(-5.0)), rel=1e-6)


def test_neutral_by_default_and_wu_buoyancy_rises():
    s = _run(np.zeros(6), 10.0)
    assert np.abs(s).max() < 1e-12
    s = _run(np.zeros(6), 10.0, params=BlueROV2Params.wu2018().to_array())
    assert s[2] > 1.0  # z up: positively buoyant vehicle rises
    assert abs(s[0]) < 1e-6 and abs(s[4]) < 1e-6


def test_tilted_vehicle_rights_itself():
    s = np.zeros(18)
    s[3] = 0.3
    s[4] = -0.2
    _run(np.zeros(6), 30.0, state=s)
    assert abs(s[3]) < 0.01 and abs(s[4]) < 0.01


@pytest.mark.parametrize("psi", [0.0, 1.0, -2.5])
def test_current_carries_a_vehicle_at_rest_along_it(psi):
    current = np.array([0.4, -0.3, 0.0])
    s = np.zeros(18)
    s[5] = psi
    _run(np.zeros(6), 60.0, state=s, current=current)
    before = s[:2].copy()
    _run(np.zeros(6), 1.0, state=s, current=current)
    np.testing.assert_allclose(s[:2] - before, current[:2], atol=2e-3)


def test_current_along_the_heading_does_not_turn_the_vehicle():
    # (a current at an angle does turn it: the Munk moment u_r v_r (Y_vdot - X_udot) of C_A)
    psi = 0.7
    current = 0.5 * np.array([math.cos(psi), math.sin(psi), 0.0])
    s = np.zeros(18)
    s[5] = psi
    _run(np.zeros(6), 30.0, state=s, current=current)
    assert abs(s[5] - psi) < 1e-5 and abs(s[11]) < 1e-5  # an unstable equilibrium: round-off
    assert s[0] == pytest.approx(s[1] / math.tan(psi), rel=1e-6)  # drifted along the current


def test_surge_through_a_head_current_is_relative():
    # water moving at -0.3 m/s along x: the vehicle keeps 1 m/s through the water
    s = _run(ACTION_TABLE[2], 120.0, current=np.array([-0.3, 0.0, 0.0]))
    theta = s[4]
    assert s[6] - (-0.3 * math.cos(theta)) == pytest.approx(1.0, rel=1e-3)


def test_bad_parameters_are_refused():
    with pytest.raises(ValueError, match="mass"):
        BlueROV2Params(mass=-1.0)
    with pytest.raises(ValueError, match="added_mass"):
        BlueROV2Params(added_mass=(1.0, 2.0))
    with pytest.raises(ValueError, match="buoyancy"):
        BlueROV2Params(buoyancy=float("nan"))
