"""One exponential RK4 step (ETDRK4) of the vehicle model, on the integrator's 14-tuple state.

The model (``dynamics._rates``, paper eq. (1)-(7)) is split as ``y' = L y + N(y)`` with
``L = -diag(M^-1 D_lin)`` on the six body velocities (``params.P_LDIAG``; 0 on the position,
quaternion and heading rows) and N everything else (Coriolis, quadratic damping, the off-diagonal
part of M^-1 D_lin, restoring forces, thrust, current, kinematics). ``etd_step`` is Cox and
Matthews' (2002) ETDRK4 (Kassam and Trefethen 2005 notation), with z = -l h per velocity:

    a = E2 y + Q N(y)                 b = E2 y + Q N(a)
    c = E2 a + Q (2 N(b) - N(y))
    y+ = E y + f1 N(y) + 2 f2 (N(a) + N(b)) + f3 N(c)

    E = exp(z), E2 = exp(z/2), Q = h/2 phi1(z/2), f1 = h (phi1 - 3 phi2 + 4 phi3),
    f2 = h (phi2 - 2 phi3), f3 = h (4 phi3 - phi2), phi_k(z) = (exp(z) - sum_{j<k} z^j/j!) / z^k

Why: with its linear damping solved exactly the step is stable however fast that damping is (UUV
Simulator's BlueROV2 damps roll at 92 1/s: classic RK4 at h = 0.05 s, h |lambda| = 4.6, blows up
beyond its limit of 2.8), so the environments keep 4 substeps per 0.2 s for both vehicles. Unlike
the Lawson (integrating-factor) form, ETD keeps every equilibrium of the ODE a fixed point of the
step (N(y*) = -L y* makes every stage equal y*), so steady speeds (the 1.0 m/s cruise, steady turn
rates) carry no step-size error, and a stiff velocity driven by a slowly varying force follows its
quasi-steady value instead of lagging. Where l = 0 the formulas reduce exactly (in exact
arithmetic) to classic RK4, which is what the position, quaternion and heading rows run; Wu's set
(l <= 0.26 1/s) runs a step within O(h^5) of classic RK4. Accuracy is checked against scipy's
``solve_ivp`` in tests/physics/test_integration.py for both presets.

The coefficients depend on (l, h) only: they are computed (``etd_coefficients``, six velocities,
one expm1 each, about 65 ns) once per block and call by the integrator's API, once per task by
the environments (kept in the task array, ``kernel.C_ETD``), never per vehicle. For
|z| < 0.5, phi3 comes from its series and phi2, phi1 from ``phi_k = 1/k! + z phi_{k+1}`` (no
cancellation); otherwise from the closed forms.
"""

from __future__ import annotations

import math

from numba import njit

from rov_envs.physics.dynamics import _rates
from rov_envs.physics.params import P_LDIAG

__all__ = ["ETD_SIZE", "etd_coefficients", "etd_step", "phi_functions", "unpack_coefficients"]

#: float64 values of one set of coefficients flattened (``np.ravel`` of ``etd_coefficients``)
ETD_SIZE = 36


# 1 / (k + 3)!, k = 0..12: the series of phi3 (|z| < 0.5: the first term left out is below
# 0.5^13 / 16! = 6e-18 of phi3)
_S = tuple(1.0 / math.factorial(k + 3) for k in range(13))


@njit(cache=True, inline="always")
def _phi(z, em1):
    """(phi1, phi2, phi3)(z), given em1 = exp(z) - 1 computed without cancellation."""
    if abs(z) < 0.5:
        phi3 = _S[0] + z * (_S[1] + z * (_S[2] + z * (_S[3] + z * (_S[4] + z * (_S[5] + z * (
            _S[6] + z * (_S[7] + z * (_S[8] + z * (_S[9] + z * (_S[10] + z * (
                _S[11] + z * _S[12])))))))))))  # fmt: skip
        phi2 = 0.5 + z * phi3
        return 1.0 + z * phi2, phi2, phi3
    return em1 / z, (em1 - z) / (z * z), (em1 - z - 0.5 * z * z) / (z * z * z)


@njit(cache=True)
def phi_functions(z):
    """(phi1, phi2, phi3)(z) for real z, accurate to about 1e-14 relative for every z <= 0."""
    return _phi(z, math.expm1(z))


@njit(cache=True, inline="always")
def _coefficients(lam, h):
    """(E, E2, Q, f1, f2, f3) of one velocity with decay rate lam (1/s) for a step h (s)."""
    z = -lam * h
    hz = 0.5 * z
    em = math.expm1(hz)  # exp(z/2) - 1
    e2 = em + 1.0
    q = 0.5 * h * (em / hz) if hz != 0.0 else 0.5 * h  # h/2 phi1(z/2)
    p1, p2, p3 = _phi(z, em * (em + 2.0))  # exp(z) - 1 = (e2 - 1)(e2 + 1)
    return (
        e2 * e2,
        e2,
        q,
        h * (p1 - 3.0 * p2 + 4.0 * p3),
        h * (p2 - 2.0 * p3),
        h * (4.0 * p3 - p2),
    )


@njit(cache=True, inline="always")
def etd_coefficients(P, h):
    """The ETDRK4 coefficients of the six velocities for step h: a 6-tuple (one per velocity
    u, v, w, p, q, r) of (E, E2, Q, f1, f2, f3)."""
    return (
        _coefficients(P[P_LDIAG], h),
        _coefficients(P[P_LDIAG + 1], h),
        _coefficients(P[P_LDIAG + 2], h),
        _coefficients(P[P_LDIAG + 3], h),
        _coefficients(P[P_LDIAG + 4], h),
        _coefficients(P[P_LDIAG + 5], h),
    )


@njit(cache=True, inline="always")
def _unpack6(a, k):
    return (a[k], a[k + 1], a[k + 2], a[k + 3], a[k + 4], a[k + 5])


@njit(cache=True, inline="always")
def unpack_coefficients(a, k):
    """``etd_coefficients`` from ``a[k : k + ETD_SIZE]``, where they were stored flattened
    (``np.ravel``): the environments keep them in their task array, computed once."""
    return (
        _unpack6(a, k), _unpack6(a, k + 6), _unpack6(a, k + 12), _unpack6(a, k + 18),
        _unpack6(a, k + 24), _unpack6(a, k + 30),
    )  # fmt: skip


@njit(cache=True, inline="always")
def _nonlinear(k, y, P):
    """N = f - L y on the velocity rows (7..12): the rates k with the exact part taken out."""
    return (
        k[7] + P[P_LDIAG] * y[7],
        k[8] + P[P_LDIAG + 1] * y[8],
        k[9] + P[P_LDIAG + 2] * y[9],
        k[10] + P[P_LDIAG + 3] * y[10],
        k[11] + P[P_LDIAG + 4] * y[11],
        k[12] + P[P_LDIAG + 5] * y[12],
    )


@njit(cache=True, inline="always")
def _stage(y, k, a, C, base, n):
    """Stage state: y + a k on the RK4 rows, E2 base + Q n on the velocity rows."""
    return (
        y[0] + a * k[0], y[1] + a * k[1], y[2] + a * k[2], y[3] + a * k[3], y[4] + a * k[4],
        y[5] + a * k[5], y[6] + a * k[6],
        C[0][1] * base[7] + C[0][2] * n[0],
        C[1][1] * base[8] + C[1][2] * n[1],
        C[2][1] * base[9] + C[2][2] * n[2],
        C[3][1] * base[10] + C[3][2] * n[3],
        C[4][1] * base[11] + C[4][2] * n[4],
        C[5][1] * base[12] + C[5][2] * n[5],
        y[13] + a * k[13],
    )  # fmt: skip


@njit(cache=True, inline="always")
def _velocity_update(y, C, n1, n2, n3, n4, j):
    """E y + f1 N1 + 2 f2 (N2 + N3) + f3 N4 for velocity j (row 7 + j)."""
    c = C[j]
    return c[0] * y[7 + j] + c[3] * n1[j] + 2.0 * c[4] * (n2[j] + n3[j]) + c[5] * n4[j]


@njit(cache=True, inline="always")
def _rk4_row(y, k1, k2, k3, k4, h6, j):
    return y[j] + h6 * (k1[j] + 2.0 * (k2[j] + k3[j]) + k4[j])


@njit(cache=True, inline="always")
def etd_step(y, ta, tm, tb, vcx, vcy, vcz, P, C, h):
    """One ETDRK4 step of length h from the 14-tuple y (module docstring).

    ta, tm, tb: the wrench at the step's start, middle and end; (vcx, vcy, vcz) the world-frame
    current; C = ``etd_coefficients(P, h)``. The quaternion is renormalised at the end.
    """
    h2 = 0.5 * h
    h6 = h / 6.0
    k1 = _rates(y, ta, vcx, vcy, vcz, P)
    n1 = _nonlinear(k1, y, P)
    a = _stage(y, k1, h2, C, y, n1)
    k2 = _rates(a, tm, vcx, vcy, vcz, P)
    n2 = _nonlinear(k2, a, P)
    b = _stage(y, k2, h2, C, y, n2)
    k3 = _rates(b, tm, vcx, vcy, vcz, P)
    n3 = _nonlinear(k3, b, P)
    m = (
        2.0 * n3[0] - n1[0], 2.0 * n3[1] - n1[1], 2.0 * n3[2] - n1[2], 2.0 * n3[3] - n1[3],
        2.0 * n3[4] - n1[4], 2.0 * n3[5] - n1[5],
    )  # fmt: skip
    c = _stage(y, k3, h, C, a, m)
    k4 = _rates(c, tb, vcx, vcy, vcz, P)
    n4 = _nonlinear(k4, c, P)
    q0 = _rk4_row(y, k1, k2, k3, k4, h6, 3)
    q1 = _rk4_row(y, k1, k2, k3, k4, h6, 4)
    q2 = _rk4_row(y, k1, k2, k3, k4, h6, 5)
    q3 = _rk4_row(y, k1, k2, k3, k4, h6, 6)
    qn = 1.0 / math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    return (
        _rk4_row(y, k1, k2, k3, k4, h6, 0),
        _rk4_row(y, k1, k2, k3, k4, h6, 1),
        _rk4_row(y, k1, k2, k3, k4, h6, 2),
        q0 * qn, q1 * qn, q2 * qn, q3 * qn,
        _velocity_update(y, C, n1, n2, n3, n4, 0),
        _velocity_update(y, C, n1, n2, n3, n4, 1),
        _velocity_update(y, C, n1, n2, n3, n4, 2),
        _velocity_update(y, C, n1, n2, n3, n4, 3),
        _velocity_update(y, C, n1, n2, n3, n4, 4),
        _velocity_update(y, C, n1, n2, n3, n4, 5),
        _rk4_row(y, k1, k2, k3, k4, h6, 13),
    )  # fmt: skip
