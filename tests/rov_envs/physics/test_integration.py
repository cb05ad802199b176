"""The exponential RK4 integrator (quaternion attitude inside) against solve_ivp on an independent
model, for both vehicle presets.

The reference is :class:`physics_helpers.ReferenceModel`, an independent numpy transcription.
"""

from __future__ import annotations

import numpy as np
import pytest
from physics_helpers import ReferenceModel
from scipy.integrate import solve_ivp

from rov_envs.physics import ACTION_TABLE
from rov_envs.physics.dynamics import DEFAULT_CONTROL_PERIOD, DEFAULT_SUBSTEPS, derivative
from rov_envs.physics.integrator import advance, advance_batch
from rov_envs.physics.params import VEHICLES, vehicle_params

P = vehicle_params("wu2018").to_array()
CURRENT = np.array([0.25, -0.3, 0.05])


def _mixed_commands(n_steps: int, vehicle: str) -> np.ndarray:
    rng = np.random.default_rng(7)
    # UUV Simulator's vehicle turns slowly (0.16-0.27 rad/s): mostly left turns, so that the run
    # crosses psi = pi; Wu's pivots at 1.0-1.4 rad/s either way
    actions = (
        rng.integers(0, 5, n_steps) if vehicle == "wu2018" else rng.choice([0, 1, 1, 2], n_steps)
    )
    cmds = ACTION_TABLE[actions].copy()
    cmds[:, 4:] = rng.uniform(-3000, 3000, (n_steps, 2))  # exercise heave/roll too
    return cmds


def _initial_state() -> np.ndarray:
    s = np.zeros(18)
    s[:6] = [1.0, -2.0, -0.5, 0.1, -0.05, 3.0]  # psi near pi: crosses it while turning
    s[6:12] = [0.4, 0.1, -0.05, 0.05, -0.02, 0.6]
    s[12:] = [2000.0, -1000.0, 500.0, 0.0, 300.0, -300.0]
    return s


def _reference_trajectory(ref, s0, cmds, dt):
    y = s0.copy()
    out = [y.copy()]
    for cmd in cmds:
        sol = solve_ivp(
            ref.rhs, (0.0, dt), y, method="DOP853", rtol=1e-12, atol=1e-12, args=(cmd, CURRENT)
        )
        y = sol.y[:, -1]
        out.append(y.copy())
    return np.array(out)


@pytest.fixture(scope="module", params=VEHICLES)
def reference(request):
    """(vehicle, its parameter array, commands, solve_ivp trajectory) over 6 s."""
    prm = vehicle_params(request.param)
    cmds = _mixed_commands(30, request.param)
    traj = _reference_trajectory(
        ReferenceModel(prm), _initial_state(), cmds, DEFAULT_CONTROL_PERIOD
    )
    return request.param, prm.to_array(), cmds, traj


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_derivative_matches_reference_model(vehicle):
    prm = vehicle_params(vehicle)
    p, ref = prm.to_array(), ReferenceModel(prm)
    rng = np.random.default_rng(3)
    out = np.empty(18)
    for _ in range(20):
        s = _initial_state()
        s[3:6] = rng.uniform([-0.5, -0.5, -4], [0.5, 0.5, 4])
        s[6:12] = rng.uniform(-1, 1, 6)
        s[12:] = rng.uniform(-8000, 8000, 6)
        cmd = rng.uniform(-8000, 8000, 6)
        cur = rng.uniform(-0.5, 0.5, 3)
        derivative(s, cmd, p, cur, out)
        np.testing.assert_allclose(out, ref.rhs(0.0, s, cmd, cur), rtol=1e-9, atol=1e-9)


def test_integrator_converges_to_solve_ivp(reference):
    _, p, cmds, ref = reference
    s = _initial_state()
    traj = [s.copy()]
    for cmd in cmds:
        advance(s, cmd, p, CURRENT, DEFAULT_CONTROL_PERIOD, 100)
        traj.append(s.copy())
    traj = np.array(traj)
    assert abs(ref[-1, 5] - ref[0, 5]) > 0.5  # the run really turns
    err = np.abs(traj - ref) / np.maximum(1.0, np.abs(ref))
    assert err.max() < 1e-7, err.max()


def test_default_substeps_are_accurate(reference):
    _, p, cmds, ref = reference
    s = _initial_state()
    for cmd in cmds:
        advance(s, cmd, p, CURRENT, DEFAULT_CONTROL_PERIOD, DEFAULT_SUBSTEPS)
    err = np.abs(s - ref[-1])
    assert err[:3].max() < 2e-3  # metres after 6 s
    assert err[3:6].max() < 2e-3  # radians
    assert err[6:12].max() < 5e-3
    assert err[12:].max() < 1.0  # rev/min out of thousands


def test_uuv_roll_is_too_stiff_for_classic_rk4_but_stays_bounded():
    """UUV Simulator's roll damping (K_p / Ix = 92 1/s) is beyond classic RK4's stability limit
    at the environments' substep (h |lambda| > 2.8); the exponential integrator stays bounded
    over 10 minutes of random Table 1 actions and tracks solve_ivp on a roll/pitch upset."""
    prm = vehicle_params("uuv_simulator")
    p, h = prm.to_array(), DEFAULT_CONTROL_PERIOD / DEFAULT_SUBSTEPS
    assert h * prm.linear_decay_rates().max() > 2.8
    rng = np.random.default_rng(0)
    s = np.zeros(18)
    for a in rng.integers(0, 5, 3000):
        advance(s, ACTION_TABLE[a].copy(), p, CURRENT, DEFAULT_CONTROL_PERIOD, DEFAULT_SUBSTEPS)
        assert np.all(np.isfinite(s)) and abs(s[3]) < 0.1 and abs(s[4]) < 0.1
        assert np.abs(s[6:12]).max() < 2.0
    upset = _initial_state()
    upset[3:5] = [0.6, -0.4]  # 34 and 23 degrees
    upset[9:11] = [2.0, -1.5]  # fast roll and pitch rates
    cmd = ACTION_TABLE[1].copy()
    ref = _reference_trajectory(ReferenceModel(prm), upset, [cmd] * 5, DEFAULT_CONTROL_PERIOD)
    for nsub, tol in ((DEFAULT_SUBSTEPS, 5e-3), (2 * DEFAULT_SUBSTEPS, 5e-4)):  # converges
        s = upset.copy()
        for k in range(5):
            advance(s, cmd, p, CURRENT, DEFAULT_CONTROL_PERIOD, nsub)
            np.testing.assert_allclose(s[3:12], ref[k + 1, 3:12], atol=tol)


def test_batch_is_bitwise_single(reference):
    _, p, _, _ = reference
    rng = np.random.default_rng(1)
    n = 5
    states = np.tile(_initial_state(), (n, 1))
    states[:, 5] += rng.uniform(-1, 1, n)
    cmds = ACTION_TABLE[rng.integers(0, 5, n)].copy()
    currents = rng.uniform(-0.3, 0.3, (n, 3))
    singles = states.copy()
    for _ in range(5):
        advance_batch(states, cmds, p, currents, 0.2, 4)
        for i in range(n):
            advance(singles[i], cmds[i], p, currents[i], 0.2, 4)
    assert np.array_equal(states, singles)


def test_bad_shapes_are_refused():
    with pytest.raises(ValueError, match="state"):
        advance(np.zeros(17), np.zeros(6), P, np.zeros(3), 0.2, 4)
    with pytest.raises(ValueError, match="cmd"):
        advance(np.zeros(18), np.zeros(4), P, np.zeros(3), 0.2, 4)
    with pytest.raises(ValueError, match="dt"):
        advance(np.zeros(18), np.zeros(6), P, np.zeros(3), -0.2, 4)
    with pytest.raises(ValueError, match="n_substeps"):
        advance(np.zeros(18), np.zeros(6), P, np.zeros(3), 0.2, 0)
