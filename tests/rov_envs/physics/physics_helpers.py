"""An independent numpy model of paper eq. (1)-(7), the reference of the integrator tests.

A straightforward transcription in matrix form, using Fossen's other current formulation:
M_RB nu_dot + C_RB(nu) nu + M_A nu_r_dot + C_A(nu_r) nu_r + D(nu_r) nu_r + g(eta) = tau (Fossen
2011 eq. 10.1-style), Euler-angle kinematics J(eta), built from the raw dataclass fields of
``BlueROV2Params`` (not from ``to_array()``).
"""

from __future__ import annotations

import math

import numpy as np

from rov_envs.physics import BlueROV2Params


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
