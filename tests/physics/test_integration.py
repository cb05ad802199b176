"""The RK4 integrator (quaternion attitude inside) against solve_ivp on an independent model.

The reference is a straightforward numpy transcription of paper eq. (1)-(7) in matrix form, using
Fossen's other current formulation: M_RB nu_dot + C_RB(nu) nu + M_A nu_r_dot + C_A(nu_r) nu_r
+ D(nu_r) nu_r + g(eta) = tau (Fossen 2011 eq. 10.1-style), Euler-angle kinematics J(eta).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rov_envs.physics import ACTION_TABLE, BlueROV2Params
from rov_envs.physics.dynamics import DEFAULT_CONTROL_PERIOD, DEFAULT_SUBSTEPS, derivative
from rov_envs.physics.integrator import advance, advance_batch


def skew(a):
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


class ReferenceModel:
    """Matrix-form model built from the raw dataclass fields (not from to_array())."""

    def __init__(self, prm: BlueROV2Params):
        self.m = prm.mass
        self.W = prm.weight
        self.B = prm.buoyancy
        self.rg = np.array(prm.r_g)
        self.rb = np.array(prm.r_b)
        self.Io = np.diag(prm.inertia)
        m = self.m
        self.MRB = np.block([[m * np.eye(3), -m * skew(self.rg)], [m * skew(self.rg), self.Io]])
        self.MA = np.diag(prm.added_mass)
        self.Dl = np.diag(prm.linear_damping)
        self.Dq = np.array(prm.quadratic_damping)
        cols = []
        for pos, d in zip(prm.thruster_positions, prm.thruster_directions):
            d = np.array(d) / np.linalg.norm(d)
            cols.append(np.concatenate([d, np.cross(pos, d)]))
        self.T = np.array(cols).T
        self.k = prm.thrust_coefficient
        self.tau_lag = prm.thruster_time_constant

    @staticmethod
    def rotation(phi, theta, psi):
        cx, sx = math.cos(phi), math.sin(phi)
        cy, sy = math.cos(theta), math.sin(theta)
        cz, sz = math.cos(psi), math.sin(psi)
        rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
        ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
        rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
        return rz @ ry @ rx

    def c_rb(self, nu):
        n2 = nu[3:]
        m = self.m
        top = np.hstack([m * skew(n2), -m * skew(n2) @ skew(self.rg)])
        bot = np.hstack([m * skew(self.rg) @ skew(n2), -skew(self.Io @ n2)])
        return np.vstack([top, bot])

    def c_a(self, nur):
        a = self.MA @ nur
        z = np.zeros((3, 3))
        return np.block([[z, -skew(a[:3])], [-skew(a[:3]), -skew(a[3:])]])

    def rhs(self, t, y, cmd, current):
        eta, nu, n = y[:6], y[6:12], y[12:18]
        phi, theta, psi = eta[3:]
        R = self.rotation(phi, theta, psi)
        Tth = np.array(
            [
                [1, math.sin(phi) * math.tan(theta), math.cos(phi) * math.tan(theta)],
                [0, math.cos(phi), -math.sin(phi)],
                [0, math.sin(phi) / math.cos(theta), math.cos(phi) / math.cos(theta)],
            ]
        )
        eta_dot = np.concatenate([R @ nu[:3], Tth @ nu[3:]])
        nc = R.T @ current
        nur = nu - np.concatenate([nc, np.zeros(3)])
        nuc_dot = np.concatenate([-np.cross(nu[3:], nc), np.zeros(3)])
        f_g = R.T @ np.array([0.0, 0.0, -self.W])
        f_b = R.T @ np.array([0.0, 0.0, self.B])
        g = -np.concatenate([f_g + f_b, np.cross(self.rg, f_g) + np.cross(self.rb, f_b)])
        D = self.Dl + np.diag(self.Dq * np.abs(nur))
        tau = self.T @ (self.k * np.abs(n) * n)
        lhs_known = self.c_rb(nu) @ nu + self.c_a(nur) @ nur + D @ nur + g - self.MA @ nuc_dot
        nu_dot = np.linalg.solve(self.MRB + self.MA, tau - lhs_known)
        n_dot = (cmd - n) / self.tau_lag
        return np.concatenate([eta_dot, nu_dot, n_dot])


PRM = BlueROV2Params()
P = PRM.to_array()
REF = ReferenceModel(PRM)
CURRENT = np.array([0.25, -0.3, 0.05])


def _mixed_commands(n_steps: int) -> np.ndarray:
    rng = np.random.default_rng(7)
    cmds = ACTION_TABLE[rng.integers(0, 5, n_steps)].copy()
    cmds[:, 4:] = rng.uniform(-3000, 3000, (n_steps, 2))  # exercise heave/roll too
    return cmds


def _initial_state() -> np.ndarray:
    s = np.zeros(18)
    s[:6] = [1.0, -2.0, -0.5, 0.1, -0.05, 3.0]  # psi near pi: crosses it while turning
    s[6:12] = [0.4, 0.1, -0.05, 0.05, -0.02, 0.6]
    s[12:] = [2000.0, -1000.0, 500.0, 0.0, 300.0, -300.0]
    return s


def _reference_trajectory(s0, cmds, dt):
    y = s0.copy()
    out = [y.copy()]
    for cmd in cmds:
        sol = solve_ivp(
            REF.rhs, (0.0, dt), y, method="DOP853", rtol=1e-12, atol=1e-12, args=(cmd, CURRENT)
        )
        y = sol.y[:, -1]
        out.append(y.copy())
    return np.array(out)


@pytest.fixture(scope="module")
def reference():
    cmds = _mixed_commands(30)  # 6 s of mixed commands
    return cmds, _reference_trajectory(_initial_state(), cmds, DEFAULT_CONTROL_PERIOD)


def test_derivative_matches_reference_model():
    rng = np.random.default_rng(3)
    out = np.empty(18)
    for _ in range(20):
        s = _initial_state()
        s[3:6] = rng.uniform([-0.5, -0.5, -4], [0.5, 0.5, 4])
        s[6:12] = rng.uniform(-1, 1, 6)
        s[12:] = rng.uniform(-8000, 8000, 6)
        cmd = rng.uniform(-8000, 8000, 6)
        cur = rng.uniform(-0.5, 0.5, 3)
        derivative(s, cmd, P, cur, out)
        np.testing.assert_allclose(out, REF.rhs(0.0, s, cmd, cur), rtol=1e-9, atol=1e-9)


def test_rk4_converges_to_solve_ivp(reference):
    cmds, ref = reference
    s = _initial_state()
    traj = [s.copy()]
    for cmd in cmds:
        advance(s, cmd, P, CURRENT, DEFAULT_CONTROL_PERIOD, 100)
        traj.append(s.copy())
    traj = np.array(traj)
    assert abs(ref[-1, 5] - ref[0, 5]) > 0.5  # the run really turns (and crosses psi = pi)
    err = np.abs(traj - ref) / np.maximum(1.0, np.abs(ref))
    assert err.max() < 1e-7, err.max()


def test_default_substeps_are_accurate(reference):
    cmds, ref = reference
    s = _initial_state()
    for cmd in cmds:
        advance(s, cmd, P, CURRENT, DEFAULT_CONTROL_PERIOD, DEFAULT_SUBSTEPS)
    err = np.abs(s - ref[-1])
    assert err[:3].max() < 2e-3  # metres after 6 s
    assert err[3:6].max() < 2e-3  # radians
    assert err[6:12].max() < 5e-3
    assert err[12:].max() < 1.0  # rev/min out of thousands


def test_batch_is_bitwise_single():
    rng = np.random.default_rng(1)
    n = 5
    states = np.tile(_initial_state(), (n, 1))
    states[:, 5] += rng.uniform(-1, 1, n)
    cmds = ACTION_TABLE[rng.integers(0, 5, n)].copy()
    currents = rng.uniform(-0.3, 0.3, (n, 3))
    singles = states.copy()
    for _ in range(5):
        advance_batch(states, cmds, P, currents, 0.2, 4)
        for i in range(n):
            advance(singles[i], cmds[i], P, currents[i], 0.2, 4)
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
