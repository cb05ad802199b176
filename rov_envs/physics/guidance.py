"""Line-of-sight (LOS) guidance for the paper's two paths (Fossen; paper eq. (16)), numba.

For the path point closest to the vehicle, (x_p, y_p) with tangent angle gamma_p:
  cross-track  e = -(x - x_p) sin(gamma_p) + (y - y_p) cos(gamma_p)   (positive = vehicle LEFT)
  course       chi_d = gamma_p - atan(e / lookahead)
  deviation    a_c = wrap(psi - chi_d) in (-pi, pi]                    (paper eq. (16))
Every LOS function writes ``out`` (3,) = ``[a_c, e, progress]`` where progress is the x of the
closest point (the env compares it with the path length to detect reaching the target); for the
sine, ``out[2]`` is read first as the Newton warm start (set it to NaN at reset). All functions
are numba-compiled (callable from Python and from other njit code); lookahead and wavelength must
be positive (the env layer validates them). Paths are evaluated on
their natural extension beyond [0, L] (the line y = 0, the sine continued), so progress can leave
[0, L].

Paths (world frame x along the straight path, y left):
* straight: y = 0, x in [0, ``STRAIGHT_PATH_LENGTH`` = 200 m] (paper 4.2.1).
* sine: y = A sin(2 pi x / wavelength), x in [0, ``SINE_PATH_LENGTH`` = 120 m], with defaults
  A = ``SINE_AMPLITUDE`` = 15 m and wavelength = ``SINE_WAVELENGTH`` = 120 m (one period from the
  start (0, 0) to the target (120, 0)). The paper gives no shape; this one is read off its layout:
  the planning obstacles (30, 17.5) and (90, -12.5) then sit 2.5 m outside the crest (30, 15) and
  2.5 m inside the trough (90, -15), exactly as the straight task's obstacles (66, -2.5) and
  (132, 2.5) sit 2.5 m off its line; and the path plus the cross-track limit d_L = 15 m spans
  |y| <= 30 m, the paper's task area. (A smaller sine, e.g. A = 5 m, would leave both obstacles
  10-15 m off the path, where they never matter.) Its smallest radius of curvature is
  wavelength^2 / (4 pi^2 A) = 24.3 m: at 1 m/s that needs only 0.04 rad/s of yaw rate, far below
  the ~1 rad/s the Table 1 turns give.
* ``DEFAULT_LOOKAHEAD`` = 5 m: about five vehicle-seconds ahead at the 1 m/s cruise, so a 1 m
  offset asks for an 11 deg intercept and the 30 m straight-path limit for 80 deg.

Closest point on the sine: Newton's method on d/ds |(s, A sin(ks)) - (x, y)|^2 = 0 from a warm
start (the previous progress), accepted only when it converges to a local minimum no farther than
the vertical offset; otherwise (and with no warm start, ``s_warm`` = NaN) a global search samples
every s within |y| + A of x and refines the best sample by golden section and Newton.
"""

from __future__ import annotations

import math

from numba import njit

__all__ = [
    "PATH_STRAIGHT",
    "PATH_SINE",
    "STRAIGHT_PATH_LENGTH",
    "SINE_PATH_LENGTH",
    "SINE_AMPLITUDE",
    "SINE_WAVELENGTH",
    "DEFAULT_LOOKAHEAD",
    "LOOKAHEAD_RANGE",
    "wrap_to_pi",
    "los_from_closest_point",
    "los_straight",
    "sine_closest_point",
    "los_sine",
    "los_guidance",
    "los_tuple",
]

PATH_STRAIGHT = 0
PATH_SINE = 1
STRAIGHT_PATH_LENGTH = 200.0
SINE_PATH_LENGTH = 120.0
SINE_AMPLITUDE = 15.0
SINE_WAVELENGTH = 120.0
DEFAULT_LOOKAHEAD = 5.0
#: The lookaheads (m) the tasks accept: ``los_lookahead`` in [low, high].
LOOKAHEAD_RANGE = (0.5, 100.0)

_TWO_PI = 2.0 * math.pi
_GOLDEN = 0.5 * (math.sqrt(5.0) - 1.0)


@njit(cache=True, inline="always")
def wrap_to_pi(angle):
    """Wrap an angle (rad) to (-pi, pi]."""
    return angle - _TWO_PI * math.ceil((angle - math.pi) / _TWO_PI)


@njit(cache=True)
def los_from_closest_point(x, y, psi, xp, yp, gamma_p, lookahead):
    """(a_c, e) from the closest path point (xp, yp) with tangent gamma_p (eq. (16))."""
    e = -(x - xp) * math.sin(gamma_p) + (y - yp) * math.cos(gamma_p)
    chi_d = gamma_p - math.atan(e / lookahead)
    return wrap_to_pi(psi - chi_d), e


@njit(cache=True, inline="always")
def _grad(s, x, y, amp, k):
    """g(s) = 0.5 d/ds D(s) and g'(s) for D(s) = (s - x)^2 + (A sin(ks) - y)^2."""
    sn = math.sin(k * s)
    cs = math.cos(k * s)
    off = amp * sn - y
    g = (s - x) + amp * k * cs * off
    dg = 1.0 + amp * amp * k * k * cs * cs - amp * k * k * sn * off
    return g, dg


@njit(cache=True, inline="always")
def _dist2(s, x, y, amp, k):
    dy = amp * math.sin(k * s) - y
    return (s - x) * (s - x) + dy * dy


@njit(cache=True)
def _sine_closest_global(x, y, amp, k):
    window = abs(y) + abs(amp) + 1e-9
    h = min(0.5, _TWO_PI / k / 64.0)
    n = int(math.ceil(2.0 * window / h))
    s0 = x - window
    best_s = x
    best_d = _dist2(x, x, y, amp, k)
    for i in range(n + 1):
        s = s0 + i * h
        d = _dist2(s, x, y, amp, k)
        if d < best_d:
            best_d = d
            best_s = s
    # golden-section refine on [best_s - h, best_s + h]
    lo = best_s - h
    hi = best_s + h
    c = hi - _GOLDEN * (hi - lo)
    d = lo + _GOLDEN * (hi - lo)
    fc = _dist2(c, x, y, amp, k)
    fd = _dist2(d, x, y, amp, k)
    for _ in range(60):
        if fc < fd:
            hi = d
            d = c
            fd = fc
            c = hi - _GOLDEN * (hi - lo)
            fc = _dist2(c, x, y, amp, k)
        else:
            lo = c
            c = d
            fc = fd
            d = lo + _GOLDEN * (hi - lo)
            fd = _dist2(d, x, y, amp, k)
        if hi - lo < 1e-9:
            break
    s = 0.5 * (lo + hi)
    # Newton polish (kept only if it improves and stays in the bracket)
    for _ in range(3):
        g, dg = _grad(s, x, y, amp, k)
        if dg <= 0.0:
            break
        sn = s - g / dg
        if abs(sn - s) > h or _dist2(sn, x, y, amp, k) > _dist2(s, x, y, amp, k):
            break
        s = sn
    return s


@njit(cache=True, inline="always")
def _sine_closest_warm(x, y, amp, k, s_warm, max_step):
    """Newton from s_warm: (s, sin(ks), cos(ks)), or s = NaN when it fails (caller falls back).

    Stops once a step is below 1e-7 (1 + |s|): convergence is quadratic, so the point is then
    exact to about 1e-13 m.
    """
    s = s_warm
    for _ in range(12):
        g, dg = _grad(s, x, y, amp, k)
        if not dg > 0.0:  # also catches NaN
            return math.nan, 0.0, 0.0
        step = g / dg
        if not abs(step) <= max_step:
            return math.nan, 0.0, 0.0
        s -= step
        if abs(step) <= 1e-7 * (1.0 + abs(s)):
            sn = math.sin(k * s)
            cs = math.cos(k * s)
            # accept only a point no farther than the one straight above/below the vehicle
            vert = amp * math.sin(k * x) - y
            dy = amp * sn - y
            if (s - x) * (s - x) + dy * dy <= vert * vert * (1.0 + 1e-12) + 1e-18:
                return s, sn, cs
            return math.nan, 0.0, 0.0
    return math.nan, 0.0, 0.0


@njit(cache=True, inline="always")
def _sine_closest(x, y, amp, k, s_warm, max_step):
    """(s, sin(ks), cos(ks)) for the closest point: warm Newton, else the global search."""
    if amp == 0.0:
        return x, math.sin(k * x), math.cos(k * x)
    if s_warm == s_warm:
        s, sn, cs = _sine_closest_warm(x, y, amp, k, s_warm, max_step)
        if s == s:
            return s, sn, cs
    s = _sine_closest_global(x, y, amp, k)
    return s, math.sin(k * s), math.cos(k * s)


@njit(cache=True)
def sine_closest_point(x, y, amplitude, wavelength, s_warm):
    """x-coordinate s of the point of y = A sin(2 pi s / wavelength) closest to (x, y).

    ``s_warm``: previous closest point for a Newton warm start, or NaN for a global search.
    """
    k = _TWO_PI / wavelength
    return _sine_closest(x, y, amplitude, k, s_warm, 0.125 * wavelength)[0]


@njit(cache=True, inline="always")
def _los_sine(x, y, psi, amplitude, wavelength, lookahead, s_warm):
    """(a_c, e, progress) on the sinusoid, warm-started at ``s_warm`` (NaN = global search)."""
    k = _TWO_PI / wavelength
    s, sn, cs = _sine_closest(x, y, amplitude, k, s_warm, 0.125 * wavelength)
    yp = amplitude * sn
    slope = amplitude * k * cs  # tan(gamma_p)
    inv = 1.0 / math.sqrt(1.0 + slope * slope)  # cos(gamma_p)
    # e = -(x - x_p) sin(gamma_p) + (y - y_p) cos(gamma_p)
    e = ((y - yp) - (x - s) * slope) * inv
    chi_d = math.atan(slope) - math.atan(e / lookahead)
    return wrap_to_pi(psi - chi_d), e, s


@njit(cache=True)
def los_sine(x, y, psi, amplitude, wavelength, lookahead, out):
    """LOS on y = A sin(2 pi x / wavelength): out (3,) <- [a_c, e, progress].

    out[2] is READ first as the closest-point warm start (the previous progress; NaN = global
    search, e.g. right after reset), then overwritten with the new progress (closest-point x).
    """
    out[0], out[1], out[2] = _los_sine(x, y, psi, amplitude, wavelength, lookahead, out[2])


@njit(cache=True, inline="always")
def los_tuple(path_kind, x, y, psi, amplitude, wavelength, lookahead, s_warm):
    """``los_guidance`` returning (a_c, e, progress); ``s_warm`` is the sine warm start."""
    if path_kind == PATH_SINE:
        return _los_sine(x, y, psi, amplitude, wavelength, lookahead, s_warm)
    # straight line y = 0: closest point (x, 0), tangent 0, e = y (eq. 16)
    return wrap_to_pi(psi + math.atan(y / lookahead)), y, x


@njit(cache=True)
def los_straight(x, y, psi, lookahead, out):
    """LOS on the line y = 0: out (3,) <- [a_c, e, progress] with e = y and progress = x."""
    out[0], out[1], out[2] = los_tuple(PATH_STRAIGHT, x, y, psi, 0.0, 1.0, lookahead, math.nan)


@njit(cache=True)
def los_guidance(path_kind, x, y, psi, amplitude, wavelength, lookahead, out):
    """Dispatch on ``path_kind`` (PATH_STRAIGHT or PATH_SINE); out (3,) <- [a_c, e, progress]."""
    out[0], out[1], out[2] = los_tuple(
        path_kind, x, y, psi, amplitude, wavelength, lookahead, out[2]
    )
