"""Sector sonar against hand-computed geometry and a brute-force sampling of the circles."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rov_envs.physics.sonar import (
    nearest_surface_distance,
    nearest_surface_distance_n,
    sonar_scan,
    sonar_scan_n,
)

SPAN = math.pi
Q = 9
RANGE = 25.0
W = SPAN / Q  # 20 deg sectors; sector 4 is [-10, 10] deg


def scan(x, y, psi, obstacles, span=SPAN, q=Q, max_range=RANGE):
    out = np.empty(q)
    sonar_scan(
        x, y, psi, np.asarray(obstacles, dtype=np.float64).reshape(-1, 3), span, max_range, out
    )
    return out


def brute_force(x, y, psi, obstacles, span=SPAN, q=Q, max_range=RANGE, n=40_000):
    """Sample every circle densely; bin the points by relative bearing."""
    out = np.full(q, max_range)
    th = np.linspace(0, 2 * np.pi, n, endpoint=False)
    for ox, oy, r in obstacles:
        px = ox + r * np.cos(th) - x
        py = oy + r * np.sin(th) - y
        d = np.hypot(px, py)
        rel = np.angle(np.exp(1j * (np.arctan2(py, px) - psi)))
        inside = (rel >= -span / 2) & (rel <= span / 2)
        idx = np.minimum(((rel[inside] + span / 2) / (span / q)).astype(int), q - 1)
        np.minimum.at(out, idx, np.minimum(d[inside], max_range))
    return out


def entry(dc, delta, r):
    """Near intersection of a ray at angle delta from the centre direction (hand formula)."""
    return dc * math.cos(delta) - math.sqrt(r * r - (dc * math.sin(delta)) ** 2)


def test_dead_ahead():
    out = scan(0, 0, 0, [(10, 0, 1.5)])
    expected = np.full(Q, RANGE)
    expected[4] = 8.5  # half-width asin(0.15) = 8.6 deg < 10 deg: only the middle sector
    np.testing.assert_allclose(out, expected, atol=1e-12)


def test_heading_and_position_rotate_the_scan():
    out = scan(2.0, 3.0, math.pi / 2, [(2.0, 13.0, 1.5)])  # facing +y, obstacle ahead
    assert out[4] == pytest.approx(8.5, abs=1e-12)
    out = scan(0, 0, 0, [(0, 10, 1.5)])  # at the vehicle's left: last sector (70-90 deg)
    assert out[8] == pytest.approx(8.5, abs=1e-12) and out[:8].min() == RANGE
    out = scan(0, 0, 0, [(0, -10, 1.5)])  # at its right: first sector
    assert out[0] == pytest.approx(8.5, abs=1e-12) and out[1:].min() == RANGE


def test_obstacle_straddling_two_sectors():
    b = math.radians(12.0)  # centre 2 deg inside sector 5, circle crosses the 10 deg ray
    out = scan(0, 0, 0, [(10 * math.cos(b), 10 * math.sin(b), 1.5)])
    assert out[5] == pytest.approx(8.5, abs=1e-12)  # radial closest point
    assert out[4] == pytest.approx(entry(10.0, math.radians(-2.0), 1.5), abs=1e-9)
    assert 8.5 < out[4] < 9.0
    assert np.all(np.delete(out, [4, 5]) == RANGE)


def test_behind_and_beyond_range_are_not_seen():
    assert np.all(scan(0, 0, 0, [(-10, 0, 1.5)]) == RANGE)  # behind
    assert np.all(scan(0, 0, 0, [(-3, 10, 1.5)]) == RANGE)  # 107 deg, fully outside the span
    assert np.all(scan(0, 0, 0, [(30, 0, 1.5)]) == RANGE)  # 28.5 m > 25 m: capped
    assert scan(0, 0, 0, [(26, 0, 1.5)])[4] == pytest.approx(24.5)


def test_partially_in_wedge_through_the_boundary_ray():
    b = math.radians(95.0)  # centre outside the span, the circle reaches over the 90 deg ray
    out = scan(0, 0, 0, [(5 * math.cos(b), 5 * math.sin(b), 1.5)])
    assert out[8] == pytest.approx(entry(5.0, math.radians(-5.0), 1.5), abs=1e-9)
    assert out[8] > 3.5  # farther than the radial closest point, which lies outside
    assert np.all(out[:8] == RANGE)


def test_nearest_obstacle_per_sector_and_inside():
    obs = [(10, 0, 1.5), (6, 0.5, 1.0), (0, 8, 2.0)]
    out = scan(0, 0, 0, obs)
    assert out[4] == pytest.approx(math.hypot(6, 0.5) - 1.0)
    assert out[8] == pytest.approx(6.0)
    assert np.all(scan(10, 0.5, 0, obs) == 0.0)  # inside an obstacle


@pytest.mark.parametrize("seed", range(4))
def test_matches_brute_force_sampling(seed):
    rng = np.random.default_rng(seed)
    obs = np.column_stack(
        [rng.uniform(-20, 20, 8), rng.uniform(-20, 20, 8), rng.uniform(0.5, 3.0, 8)]
    )
    x, y = 0.3, -0.2
    keep = np.hypot(obs[:, 0] - x, obs[:, 1] - y) > obs[:, 2] + 0.5
    obs = obs[keep]
    psi = rng.uniform(-math.pi, math.pi)
    for span, q in ((SPAN, Q), (2 * math.pi / 3, 5), (2 * math.pi, 12)):
        out = scan(x, y, psi, obs, span=span, q=q)
        np.testing.assert_allclose(out, brute_force(x, y, psi, obs, span=span, q=q), atol=2e-3)


def test_padded_variants_use_the_first_rows():
    obs = np.array([[10.0, 0.0, 1.5], [5.0, 0.0, 1.0], [0.0, 0.0, 0.0]])
    out = np.empty(Q)
    sonar_scan_n(0.0, 0.0, 0.0, obs, 1, SPAN, RANGE, out)
    assert out[4] == pytest.approx(8.5)
    assert nearest_surface_distance_n(0.0, 0.0, obs, 2) == pytest.approx(4.0)
    assert nearest_surface_distance_n(0.0, 0.0, obs, 0) == math.inf


def test_nearest_surface_distance():
    obs = np.array([[-10.0, 0.0, 1.5], [3.0, 4.0, 1.0]])
    assert nearest_surface_distance(0.0, 0.0, obs) == pytest.approx(4.0)  # any bearing
    assert nearest_surface_distance(-10.5, 0.0, obs) == 0.0  # inside
    assert nearest_surface_distance(0.0, 0.0, np.zeros((0, 3))) == math.inf


def test_bad_arguments_are_refused():
    out = np.empty(Q)
    with pytest.raises(ValueError, match="span"):
        sonar_scan(0.0, 0.0, 0.0, np.zeros((1, 3)), 7.0, RANGE, out)
    with pytest.raises(ValueError, match="max_range"):
        sonar_scan(0.0, 0.0, 0.0, np.zeros((1, 3)), SPAN, -1.0, out)
    with pytest.raises(ValueError, match="obstacles"):
        sonar_scan(0.0, 0.0, 0.0, np.zeros((1, 2)), SPAN, RANGE, out)
