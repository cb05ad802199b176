"""The fused per-control-step kernel equals its parts called one by one."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rov_envs.physics import ACTION_TABLE, BlueROV2Params
from rov_envs.physics.dynamics import advance
from rov_envs.physics.fused import advance_observe_batch, observe_batch
from rov_envs.physics.guidance import PATH_SINE, PATH_STRAIGHT, los_guidance
from rov_envs.physics.sonar import nearest_surface_distance, sonar_scan

P = BlueROV2Params().to_array()


@pytest.mark.parametrize("path_kind", [PATH_STRAIGHT, PATH_SINE])
def test_fused_equals_parts(path_kind):
    rng = np.random.default_rng(path_kind)
    n, m, q = 6, 5, 9
    states = np.zeros((n, 18))
    states[:, 0] = rng.uniform(0, 100, n)
    states[:, 1] = rng.uniform(-10, 10, n)
    states[:, 5] = rng.uniform(-3, 3, n)
    obstacles = np.zeros((n, m, 3))
    obstacles[:, :, 0] = states[:, :1] + rng.uniform(-20, 20, (n, m))
    obstacles[:, :, 1] = states[:, 1:2] + rng.uniform(-20, 20, (n, m))
    obstacles[:, :, 2] = 1.5
    n_obs = np.array([5, 3, 0, 1, 5, 2], dtype=np.int64)
    currents = rng.uniform(-0.2, 0.2, (n, 3))
    sonar = np.empty((n, q))
    nearest = np.empty(n)
    guide = np.full((n, 3), math.nan)
    args = (math.pi, 25.0, sonar, nearest, path_kind, 15.0, 120.0, 5.0, guide)
    observe_batch(states, obstacles, n_obs, *args)
    singles = states.copy()
    s_guide = np.full((n, 3), math.nan)
    for i in range(n):
        los_guidance(
            path_kind, singles[i, 0], singles[i, 1], singles[i, 5], 15.0, 120.0, 5.0, s_guide[i]
        )
    np.testing.assert_allclose(guide, s_guide, rtol=1e-13, atol=1e-13)
    s_guide[:] = guide
    for _ in range(4):
        cmds = ACTION_TABLE[rng.integers(0, 5, n)].copy()
        advance_observe_batch(states, cmds, P, currents, 0.2, 4, obstacles, n_obs, *args)
        for i in range(n):
            advance(singles[i], cmds[i], P, currents[i], 0.2, 4)
            obs = obstacles[i, : n_obs[i]].copy()
            out = np.empty(q)
            sonar_scan(singles[i, 0], singles[i, 1], singles[i, 5], obs, math.pi, 25.0, out)
            np.testing.assert_array_equal(sonar[i], out)
            assert nearest[i] == nearest_surface_distance(singles[i, 0], singles[i, 1], obs)
            los_guidance(
                path_kind, singles[i, 0], singles[i, 1], singles[i, 5], 15.0, 120.0, 5.0, s_guide[i]
            )
        np.testing.assert_array_equal(states, singles)
        # guidance inlined in the fused kernel may be compiled with different rounding (1 ulp)
        np.testing.assert_allclose(guide, s_guide, rtol=1e-13, atol=1e-13)
        s_guide[:] = guide


def test_fused_without_sonar_and_bad_arguments():
    states = np.zeros((2, 18))
    sonar = np.empty((2, 0))
    nearest = np.empty(2)
    guide = np.full((2, 3), math.nan)
    obstacles = np.zeros((2, 0, 3))
    n_obs = np.zeros(2, dtype=np.int64)
    cmds = np.tile(ACTION_TABLE[2], (2, 1))
    advance_observe_batch(
        states, cmds, P, np.zeros((2, 3)), 0.2, 4, obstacles, n_obs, math.pi, 25.0,
        sonar, nearest, PATH_STRAIGHT, 0.0, 120.0, 5.0, guide,
    )  # fmt: skip
    assert np.all(nearest == math.inf) and np.all(guide[:, 2] > 0)
    with pytest.raises(ValueError, match="n_obstacles"):
        observe_batch(
            states, obstacles, np.ones(2, dtype=np.int64), math.pi, 25.0, sonar, nearest,
            PATH_STRAIGHT, 0.0, 120.0, 5.0, guide,
        )  # fmt: skip
    with pytest.raises(ValueError, match="path_kind"):
        observe_batch(
            states, obstacles, n_obs, math.pi, 25.0, sonar, nearest, 7, 0.0, 120.0, 5.0, guide
        )


def test_fused_batch_is_bitwise_n_single_calls():
    rng = np.random.default_rng(5)
    n, q = 4, 9
    states = np.zeros((n, 18))
    states[:, 1] = rng.uniform(-5, 5, n)
    obstacles = np.tile(np.array([[30.0, 17.5, 1.5], [20.0, 2.0, 1.5]]), (n, 1, 1))
    n_obs = np.full(n, 2, dtype=np.int64)
    currents = np.zeros((n, 3))
    bufs = [np.empty((n, q)), np.empty(n), np.full((n, 3), math.nan)]
    one = [states.copy(), np.empty((n, q)), np.empty(n), np.full((n, 3), math.nan)]
    for _ in range(20):
        cmds = ACTION_TABLE[rng.integers(0, 5, n)].copy()
        advance_observe_batch(
            states, cmds, P, currents, 0.2, 4, obstacles, n_obs, math.pi, 25.0, bufs[0],
            bufs[1], PATH_SINE, 15.0, 120.0, 5.0, bufs[2],
        )  # fmt: skip
        for i in range(n):
            sl = slice(i, i + 1)
            advance_observe_batch(
                one[0][sl], cmds[sl], P, currents[sl], 0.2, 4, obstacles[sl], n_obs[sl],
                math.pi, 25.0, one[1][sl], one[2][sl], PATH_SINE, 15.0, 120.0, 5.0, one[3][sl],
            )  # fmt: skip
    for a, b in zip([states, *bufs], one):
        np.testing.assert_array_equal(a, b)
