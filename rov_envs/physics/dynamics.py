"""Fossen 6-DOF model of the BlueROV2 (paper eq. (1)-(7)), numba kernels on float64 arrays.

Frames: world x along the straight path, y to its left, z up; Euler angles ZYX (roll phi, pitch
theta, heading psi), psi counter-clockwise from x (turning left raises psi). Body frame
forward-left-up. With both frames right-handed, Fossen's equations keep their form; only gravity
points along -z (restoring forces below) and a stable vehicle has its centre of buoyancy ABOVE its
centre of gravity (z_b > z_g in body z-up).

State (``STATE_DIM`` = 18): ``[x, y, z, phi, theta, psi, u, v, w, p, q, r, n1..n6]`` with n the
lagged thruster speeds in rev/min. Commands ``cmd`` (6,) are the commanded speeds T1..T6 in rev/min;
``current`` (3,) is the world-frame water velocity in m/s (irrotational, constant).

Equations (``derivative``):
  eq. (1)-(2)  eta_dot = J(eta) nu, J = diag(R(phi, theta, psi), T(phi, theta))  (ground velocity)
  eq. (3)-(6)  M nu_r_dot + C(nu_r) nu_r + D(nu_r) nu_r + g(eta) = tau,
               nu_r = nu - [R^T v_c; 0] (Fossen 2011, Property 8.1: with an irrotational constant
               current the rigid-body terms may be written in nu_r when C_RB is parametrised
               independently of the linear velocity, eq. 3.60),
               nu_dot = nu_r_dot - [omega x (R^T v_c); 0],
               M = M_RB + M_A (eq. 4), C = C_RB + C_A (eq. 5; C_A from Fossen 2011 eq. 6.43),
               D = D_lin + D_quad |nu_r| (eq. 6), g(eta) = [(W - B) e; (W r_g - B r_b) x e] with
               e = R^T [0, 0, 1].
  eq. (7)      tau = T f, f_i = k |n_i| n_i, n_dot = (n_cmd - n) / t_lag (first-order lag K(s)).
M^-1 is precomputed in the parameter array (``params.P_MINV``).

Integration: :mod:`rov_envs.physics.integrator` (``advance``, ``advance_batch`` and the SIMD
block kernel the environments use) runs a fixed-step exponential RK4 (:mod:`rov_envs.physics.etd`,
the linear damping solved exactly) on ``_rates``, the right-hand side above with the attitude
carried as a unit quaternion (Fossen 2011 eq. 2.86: the kinematics of eq. (2) without
trigonometry) and the heading psi integrated beside it. The result converges to the Euler-angle
ODE of ``derivative`` (tests/physics compare it with scipy's ``solve_ivp`` on an independent
numpy model, for both presets).

Control period: ``DEFAULT_CONTROL_PERIOD`` = 0.2 s with ``DEFAULT_SUBSTEPS`` = 4 (h = 0.05 s) for
both vehicles. UUV Simulator's set: the fast modes are its linear damping (roll 92 1/s, pitch
25 1/s, yaw 5.5 1/s), integrated exactly; what stays explicit (Coriolis terms ~ turn rate, the
roll/pitch righting coupling, about 10 rad/s in roll) keeps h |lambda| <= 0.6. Wu's set: the
stiffest modes are the yaw damping at full turn rate (dN/dr / (I_z + N_rdot) ~ 15 1/s), the
lightly damped roll/pitch righting oscillation (~4.4 rad/s at cruise for the 0.10 m metacentric
height) and the sway-yaw divergence (+4 1/s, see ``params``), h |lambda| <= 0.8, inside RK4's
stability limit (2.8). The thruster lag is integrated exactly. tests/physics/test_integration.py
bounds the error of the default against ``solve_ivp`` for both presets.

``derivative`` is numba-compiled (callable from Python and from other njit code); it checks array
shapes (ValueError) but not dtypes beyond numba's typing: pass float64 arrays.
"""

from __future__ import annotations

import math

from numba import njit

from rov_envs.physics.params import (
    P_ADDED,
    P_ALLOC,
    P_BUOYANCY,
    P_DLIN,
    P_DQUAD,
    P_INERTIA,
    P_INV_TAU,
    P_MASS,
    P_MINV,
    P_RB,
    P_RG,
    P_SIZE,
    P_THRUST_K,
    P_WEIGHT,
)

__all__ = [
    "STATE_DIM",
    "N_THRUSTERS",
    "DEFAULT_CONTROL_PERIOD",
    "DEFAULT_SUBSTEPS",
    "derivative",
]

STATE_DIM = 18
N_THRUSTERS = 6
DEFAULT_CONTROL_PERIOD = 0.2
"""Seconds between agent decisions (the env's control step)."""
DEFAULT_SUBSTEPS = 4
"""Integrator substeps per control period (h = 0.05 s at the default period)."""

# internal integrator state (``_rates``): 14-tuple (x, y, z, q0, q1, q2, q3, u, v, w, p, q, r, psi);
# the thruster speeds follow their first-order lag exactly (closed form), see ``integrator``.


@njit(cache=True, inline="always")
def _wrench(n0, n1, n2, n3, n4, n5, P):
    """tau = T f with f_i = k |n_i| n_i (eq. 7), as a 6-tuple."""
    k = P[P_THRUST_K]
    f0 = k * abs(n0) * n0
    f1 = k * abs(n1) * n1
    f2 = k * abs(n2) * n2
    f3 = k * abs(n3) * n3
    f4 = k * abs(n4) * n4
    f5 = k * abs(n5) * n5
    a = P_ALLOC
    t0 = P[a] * f0 + P[a + 1] * f1 + P[a + 2] * f2 + P[a + 3] * f3 + P[a + 4] * f4 + P[a + 5] * f5
    a += 6
    t1 = P[a] * f0 + P[a + 1] * f1 + P[a + 2] * f2 + P[a + 3] * f3 + P[a + 4] * f4 + P[a + 5] * f5
    a += 6
    t2 = P[a] * f0 + P[a + 1] * f1 + P[a + 2] * f2 + P[a + 3] * f3 + P[a + 4] * f4 + P[a + 5] * f5
    a += 6
    t3 = P[a] * f0 + P[a + 1] * f1 + P[a + 2] * f2 + P[a + 3] * f3 + P[a + 4] * f4 + P[a + 5] * f5
    a += 6
    t4 = P[a] * f0 + P[a + 1] * f1 + P[a + 2] * f2 + P[a + 3] * f3 + P[a + 4] * f4 + P[a + 5] * f5
    a += 6
    t5 = P[a] * f0 + P[a + 1] * f1 + P[a + 2] * f2 + P[a + 3] * f3 + P[a + 4] * f4 + P[a + 5] * f5
    return t0, t1, t2, t3, t4, t5


@njit(cache=True, inline="always")
def _accelerations(
    r00, r01, r02, r10, r11, r12, r20, r21, r22,
    u, v, w, p, q, r,
    t0, t1, t2, t3, t4, t5,
    vcx, vcy, vcz, P,
):  # fmt: skip
    """Body accelerations nu_dot (eq. (3)-(6)) for rotation R (body -> world) and wrench tau."""
    # current in the body frame, nu_c = R^T v_c, and relative velocity nu_r
    ncx = r00 * vcx + r10 * vcy + r20 * vcz
    ncy = r01 * vcx + r11 * vcy + r21 * vcz
    ncz = r02 * vcx + r12 * vcy + r22 * vcz
    ur = u - ncx
    vr = v - ncy
    wr = w - ncz

    m = P[P_MASS]
    xg = P[P_RG]
    yg = P[P_RG + 1]
    zg = P[P_RG + 2]
    ix = P[P_INERTIA]
    iy = P[P_INERTIA + 1]
    iz = P[P_INERTIA + 2]

    # C_RB(nu_r) nu_r = [m w x v + m w x (w x r_g); m r_g x (w x v) + w x (I w)]  (eq. 3.60)
    ax = q * wr - r * vr
    ay = r * ur - p * wr
    az = p * vr - q * ur
    bx = q * zg - r * yg
    by = r * xg - p * zg
    bz = p * yg - q * xg
    c0 = m * (ax + q * bz - r * by)
    c1 = m * (ay + r * bx - p * bz)
    c2 = m * (az + p * by - q * bx)
    c3 = m * (yg * az - zg * ay) + (iz - iy) * q * r
    c4 = m * (zg * ax - xg * az) + (ix - iz) * r * p
    c5 = m * (xg * ay - yg * ax) + (iy - ix) * p * q

    # C_A(nu_r) nu_r = [w x a1; v_r x a1 + w x a2], a1 = A11 v_r, a2 = A22 w  (eq. 6.43)
    a1x = P[P_ADDED] * ur
    a1y = P[P_ADDED + 1] * vr
    a1z = P[P_ADDED + 2] * wr
    a2x = P[P_ADDED + 3] * p
    a2y = P[P_ADDED + 4] * q
    a2z = P[P_ADDED + 5] * r
    c0 += q * a1z - r * a1y
    c1 += r * a1x - p * a1z
    c2 += p * a1y - q * a1x
    c3 += vr * a1z - wr * a1y + q * a2z - r * a2y
    c4 += wr * a1x - ur * a1z + r * a2x - p * a2z
    c5 += ur * a1y - vr * a1x + p * a2y - q * a2x

    # D(nu_r) nu_r, linear + quadratic (eq. 6)
    c0 += (P[P_DLIN] + P[P_DQUAD] * abs(ur)) * ur
    c1 += (P[P_DLIN + 1] + P[P_DQUAD + 1] * abs(vr)) * vr
    c2 += (P[P_DLIN + 2] + P[P_DQUAD + 2] * abs(wr)) * wr
    c3 += (P[P_DLIN + 3] + P[P_DQUAD + 3] * abs(p)) * p
    c4 += (P[P_DLIN + 4] + P[P_DQUAD + 4] * abs(q)) * q
    c5 += (P[P_DLIN + 5] + P[P_DQUAD + 5] * abs(r)) * r

    # restoring g(eta) = [(W - B) e; (W r_g - B r_b) x e], e = R^T z_world
    wgt = P[P_WEIGHT]
    buo = P[P_BUOYANCY]
    hx = wgt * xg - buo * P[P_RB]
    hy = wgt * yg - buo * P[P_RB + 1]
    hz = wgt * zg - buo * P[P_RB + 2]
    wb = wgt - buo
    c0 += wb * r20
    c1 += wb * r21
    c2 += wb * r22
    c3 += hy * r22 - hz * r21
    c4 += hz * r20 - hx * r22
    c5 += hx * r21 - hy * r20

    h0 = t0 - c0
    h1 = t1 - c1
    h2 = t2 - c2
    h3 = t3 - c3
    h4 = t4 - c4
    h5 = t5 - c5
    b = P_MINV
    d0 = P[b] * h0 + P[b + 1] * h1 + P[b + 2] * h2 + P[b + 3] * h3 + P[b + 4] * h4 + P[b + 5] * h5
    b += 6
    d1 = P[b] * h0 + P[b + 1] * h1 + P[b + 2] * h2 + P[b + 3] * h3 + P[b + 4] * h4 + P[b + 5] * h5
    b += 6
    d2 = P[b] * h0 + P[b + 1] * h1 + P[b + 2] * h2 + P[b + 3] * h3 + P[b + 4] * h4 + P[b + 5] * h5
    b += 6
    d3 = P[b] * h0 + P[b + 1] * h1 + P[b + 2] * h2 + P[b + 3] * h3 + P[b + 4] * h4 + P[b + 5] * h5
    b += 6
    d4 = P[b] * h0 + P[b + 1] * h1 + P[b + 2] * h2 + P[b + 3] * h3 + P[b + 4] * h4 + P[b + 5] * h5
    b += 6
    d5 = P[b] * h0 + P[b + 1] * h1 + P[b + 2] * h2 + P[b + 3] * h3 + P[b + 4] * h4 + P[b + 5] * h5

    # nu_dot = nu_r_dot + d/dt(nu_c) = nu_r_dot - w x nu_c
    d0 -= q * ncz - r * ncy
    d1 -= r * ncx - p * ncz
    d2 -= p * ncy - q * ncx
    return d0, d1, d2, d3, d4, d5


@njit(cache=True)
def _derivative_euler(state, cmd, P, current, out):
    """d(state)/dt for the 18-dim Euler-angle state (eq. (1)-(7)); writes ``out`` (18,)."""
    phi = state[3]
    theta = state[4]
    psi = state[5]
    cf = math.cos(phi)
    sf = math.sin(phi)
    ct = math.cos(theta)
    st = math.sin(theta)
    cp = math.cos(psi)
    sp = math.sin(psi)
    r00 = cp * ct
    r01 = -sp * cf + cp * st * sf
    r02 = sp * sf + cp * cf * st
    r10 = sp * ct
    r11 = cp * cf + sf * st * sp
    r12 = -cp * sf + st * sp * cf
    r20 = -st
    r21 = ct * sf
    r22 = ct * cf
    u = state[6]
    v = state[7]
    w = state[8]
    p = state[9]
    q = state[10]
    r = state[11]
    out[0] = r00 * u + r01 * v + r02 * w
    out[1] = r10 * u + r11 * v + r12 * w
    out[2] = r20 * u + r21 * v + r22 * w
    s = q * sf + r * cf
    out[3] = p + s * st / ct
    out[4] = q * cf - r * sf
    out[5] = s / ct
    t0, t1, t2, t3, t4, t5 = _wrench(
        state[12], state[13], state[14], state[15], state[16], state[17], P
    )
    d0, d1, d2, d3, d4, d5 = _accelerations(
        r00, r01, r02, r10, r11, r12, r20, r21, r22,
        u, v, w, p, q, r,
        t0, t1, t2, t3, t4, t5,
        current[0], current[1], current[2], P,
    )  # fmt: skip
    out[6] = d0
    out[7] = d1
    out[8] = d2
    out[9] = d3
    out[10] = d4
    out[11] = d5
    inv_tau = P[P_INV_TAU]
    for i in range(N_THRUSTERS):
        out[12 + i] = (cmd[i] - state[12 + i]) * inv_tau


@njit(cache=True, inline="always")
def _rates(y, tau, vcx, vcy, vcz, P):
    """Derivative of the internal 14-tuple y = (x, y, z, q0..q3, u, v, w, p, q, r, psi)."""
    x, yy, z, q0, q1, q2, q3, u, v, w, p, q, r, psi = y
    t0, t1, t2, t3, t4, t5 = tau
    r00 = 1.0 - 2.0 * (q2 * q2 + q3 * q3)
    r01 = 2.0 * (q1 * q2 - q0 * q3)
    r02 = 2.0 * (q1 * q3 + q0 * q2)
    r10 = 2.0 * (q1 * q2 + q0 * q3)
    r11 = 1.0 - 2.0 * (q1 * q1 + q3 * q3)
    r12 = 2.0 * (q2 * q3 - q0 * q1)
    r20 = 2.0 * (q1 * q3 - q0 * q2)
    r21 = 2.0 * (q2 * q3 + q0 * q1)
    r22 = 1.0 - 2.0 * (q1 * q1 + q2 * q2)
    d0, d1, d2, d3, d4, d5 = _accelerations(
        r00, r01, r02, r10, r11, r12, r20, r21, r22,
        u, v, w, p, q, r,
        t0, t1, t2, t3, t4, t5,
        vcx, vcy, vcz, P,
    )  # fmt: skip
    return (
        r00 * u + r01 * v + r02 * w,
        r10 * u + r11 * v + r12 * w,
        r20 * u + r21 * v + r22 * w,
        0.5 * (-q1 * p - q2 * q - q3 * r),
        0.5 * (q0 * p + q2 * r - q3 * q),
        0.5 * (q0 * q - q1 * r + q3 * p),
        0.5 * (q0 * r + q1 * q - q2 * p),
        d0, d1, d2, d3, d4, d5,
        # psi_dot = (q sin(phi) + r cos(phi)) / cos(theta) = (q r21 + r r22) / cos(theta)^2
        (q * r21 + r * r22) / (r21 * r21 + r22 * r22),
    )  # fmt: skip


@njit(cache=True)
def _check_shapes(state, cmd, P, current):
    if state.shape[0] != STATE_DIM:
        raise ValueError("state must be a float64 array of shape (18,)")
    if cmd.shape[0] != N_THRUSTERS:
        raise ValueError("cmd must be a float64 array of shape (6,) (rev/min, T1..T6)")
    if P.shape[0] != P_SIZE:
        raise ValueError("p must be BlueROV2Params.to_array() (shape (P_SIZE,))")
    if current.shape[0] != 3:
        raise ValueError("current must be a float64 array of shape (3,) (world m/s)")


@njit(cache=True)
def derivative(state, cmd, p, current, out):
    """Write d(state)/dt (eq. (1)-(7)) into ``out`` (18,).

    state (18,), cmd (6,) rev/min, p = ``BlueROV2Params.to_array()``, current (3,) world m/s.
    Numba-compiled: callable from Python and from other njit code.
    """
    _check_shapes(state, cmd, p, current)
    if out.shape[0] != STATE_DIM:
        raise ValueError("out must be a float64 array of shape (18,)")
    _derivative_euler(state, cmd, p, current, out)
