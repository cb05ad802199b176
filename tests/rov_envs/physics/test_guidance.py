"""LOS guidance (paper eq. (16)) on hand-computed states for the straight and the sine path."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rov_envs.physics.guidance import (
    DEFAULT_LOOKAHEAD,
    PATH_SINE,
    PATH_STRAIGHT,
    SINE_AMPLITUDE,
    SINE_WAVELENGTH,
    los_guidance,
    los_sine,
    los_straight,
    sine_closest_point,
    wrap_to_pi,
)

A = SINE_AMPLITUDE
LAM = SINE_WAVELENGTH
K = 2 * math.pi / LAM
D = 5.0


def straight(x, y, psi, lookahead=D):
    out = np.empty(3)
    los_straight(x, y, psi, lookahead, out)
    return out


def sine(x, y, psi, warm=math.nan):
    out = np.array([0.0, 0.0, warm])
    los_sine(x, y, psi, A, LAM, D, out)
    return out


def test_wrap_to_pi_half_open():
    assert wrap_to_pi(math.pi) == pytest.approx(math.pi)
    assert wrap_to_pi(-math.pi) == pytest.approx(math.pi)
    assert wrap_to_pi(3 * math.pi / 2) == pytest.approx(-math.pi / 2)
    assert wrap_to_pi(-7.0) == pytest.approx(-7.0 + 2 * math.pi)
    assert wrap_to_pi(0.3 + 4 * math.pi) == pytest.approx(0.3)


def test_straight_path_hand_computed():
    a_c, e, prog = straight(10.0, 2.0, 0.0)
    assert e == 2.0 and prog == 10.0  # left of the path = positive
    assert a_c == pytest.approx(math.atan(2.0 / 5.0))  # chi_d = -atan(0.4): heading too far left
    a_c, e, _ = straight(50.0, -5.0, 0.2)
    assert e == -5.0
    assert a_c == pytest.approx(0.2 - math.pi / 4)  # chi_d = +45 deg back towards the line
    assert DEFAULT_LOOKAHEAD == 5.0


def test_straight_path_wrapping():
    a_c, _, _ = straight(0.0, 5.0, 3.0)  # psi - chi_d = 3 + pi/4 > pi
    assert a_c == pytest.approx(3.0 + math.pi / 4 - 2 * math.pi)
    a_c, _, _ = straight(0.0, -5.0, -3.0)  # -3 - pi/4 < -pi
    assert a_c == pytest.approx(-3.0 - math.pi / 4 + 2 * math.pi)
    a_c, _, _ = straight(0.0, 0.0, 2 * math.pi + 0.1)  # continuous heading
    assert a_c == pytest.approx(0.1)


def test_sine_default_shape_passes_start_target_and_obstacle_crests():
    assert A * math.sin(K * 0.0) == 0.0
    assert abs(A * math.sin(K * 120.0)) < 1e-12
    assert A * math.sin(K * 30.0) == pytest.approx(17.5 - 2.5)  # obstacle (30, 17.5)
    assert A * math.sin(K * 90.0) == pytest.approx(-12.5 - 2.5)  # obstacle (90, -12.5)


def test_sine_on_path_points():
    a_c, e, prog = sine(0.0, 0.0, 0.0)  # start: tangent atan(A k)
    assert prog == pytest.approx(0.0, abs=1e-9) and e == pytest.approx(0.0, abs=1e-9)
    assert a_c == pytest.approx(-math.atan(A * K))
    a_c, e, prog = sine(30.0, 15.0, 0.4)  # crest: tangent 0
    assert prog == pytest.approx(30.0) and e == pytest.approx(0.0, abs=1e-9)
    assert a_c == pytest.approx(0.4)


def test_sine_below_the_crest_and_wrapping():
    # 5 m below the crest the crest is still the closest point (radius of curvature 24.3 m)
    a_c, e, prog = sine(30.0, 10.0, 0.0)
    assert prog == pytest.approx(30.0, abs=1e-9)
    assert e == pytest.approx(-5.0)
    assert a_c == pytest.approx(-math.pi / 4)
    a_c, e, _ = sine(90.0, -10.0, 3.0)  # 5 m above the trough, heading backwards
    assert e == pytest.approx(5.0)
    assert a_c == pytest.approx(3.0 + math.pi / 4 - 2 * math.pi)  # wrapped into (-pi, pi]


@pytest.mark.parametrize("seed", range(3))
def test_sine_closest_point_matches_dense_search(seed):
    rng = np.random.default_rng(seed)
    s = np.linspace(-60, 180, 480_001)
    for _ in range(20):
        x, y = rng.uniform(0, 120), rng.uniform(-30, 30)
        d2 = (s - x) ** 2 + (A * np.sin(K * s) - y) ** 2
        best = s[np.argmin(d2)]
        out = sine(x, y, 0.0)
        assert out[2] == pytest.approx(best, abs=2e-3)
        assert abs(out[1]) == pytest.approx(math.sqrt(d2.min()), abs=1e-6)
        # the sign: left of the path (counter-clockwise from its tangent) is positive
        gamma = math.atan(A * K * math.cos(K * out[2]))
        normal = np.array([-math.sin(gamma), math.cos(gamma)])
        offset = np.array([x - out[2], y - A * math.sin(K * out[2])])
        assert np.sign(out[1]) == np.sign(offset @ normal)


def test_warm_start_follows_and_bad_warm_starts_fall_back():
    cold = sine(47.0, 8.0, 0.0)
    for warm in (46.5, 40.0, 1e6, math.inf, -math.inf):
        warm_out = sine(47.0, 8.0, 0.0, warm=warm)
        assert warm_out[2] == pytest.approx(cold[2], abs=1e-8)
    # a warm start in the wrong local minimum is rejected: far below a crest (concave side)
    x, y = 30.0, -14.0  # 29 m below the crest: two symmetric local minima, not the crest
    s = np.linspace(-30, 90, 240_001)
    d2 = (s - x) ** 2 + (A * np.sin(K * s) - y) ** 2
    out = sine(x, y, 0.0, warm=30.0)
    assert math.sqrt((out[2] - x) ** 2 + (A * math.sin(K * out[2]) - y) ** 2) == pytest.approx(
        math.sqrt(d2.min()), abs=1e-6
    )
    assert sine_closest_point(x, y, 0.0, LAM, 3.0) == x  # flat "sine"


def test_los_guidance_dispatch():
    out = np.array([0.0, 0.0, math.nan])
    los_guidance(PATH_STRAIGHT, 10.0, 2.0, 0.0, A, LAM, D, out)
    np.testing.assert_allclose(out, straight(10.0, 2.0, 0.0))
    out = np.array([0.0, 0.0, math.nan])
    los_guidance(PATH_SINE, 30.0, 10.0, 0.0, A, LAM, D, out)
    np.testing.assert_allclose(out, sine(30.0, 10.0, 0.0))
