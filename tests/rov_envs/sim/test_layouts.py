"""Seeded layouts: same seed same episode, fresh each episode, always solvable."""

from __future__ import annotations

import itertools
import math

import gymnasium as gym
import numpy as np
import pytest

from rov_envs.sim.layouts import END_CLEAR, GAP_MIN, LAYOUTS, START_CLEAR

RANDOM_IDS = [
    "rov_envs/ObstacleAvoidance-v0",
    "rov_envs/PlanningStraightUniform-v0",
    "rov_envs/PlanningStraightDense-v0",
    "rov_envs/PlanningSineDense-v0",
]


def _episode(env_id: str, seed: int, steps: int = 60, **kw):
    env = gym.make(env_id, sonar_noise=0.3, start_noise=(0.3, 0.05), **kw)
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(1)
    trace = [np.concatenate([obs[k] for k in sorted(obs)])]
    for _ in range(steps):
        obs, r, term, trunc, info = env.step(int(rng.integers(0, 5)))
        trace.append(np.concatenate([obs[k] for k in sorted(obs)] + [[r]]))
        if term or trunc:
            obs, _ = env.reset()
    return env.unwrapped.obstacles, np.concatenate(trace)


@pytest.mark.parametrize("env_id", RANDOM_IDS + ["rov_envs/PathFollowingSine-v0"])
def test_same_seed_same_episode(env_id: str) -> None:
    a_obs, a = _episode(env_id, 5)
    b_obs, b = _episode(env_id, 5)
    np.testing.assert_array_equal(a_obs, b_obs)
    np.testing.assert_array_equal(a, b)  # bit for bit


@pytest.mark.parametrize("env_id", RANDOM_IDS)
def test_layout_drawn_afresh(env_id: str) -> None:
    env = gym.make(env_id)
    env.reset(seed=0)
    first = env.unwrapped.obstacles
    env.reset()
    second = env.unwrapped.obstacles
    env.reset(seed=1)
    other = env.unwrapped.obstacles
    assert not np.array_equal(first, second) and not np.array_equal(first, other)


@pytest.mark.parametrize("name", sorted(LAYOUTS))
def test_layouts_solvable(name: str) -> None:
    straight = name != "sine_dense"
    d_L = 30.0 if straight else 15.0
    length = 60.0 if name == "avoidance" else (200.0 if straight else 120.0)
    amp, wave = (15.0 if name == "sine_dense" else 0.0), 120.0  # the straight ones ignore it
    for seed in range(40):
        obs = LAYOUTS[name](np.random.default_rng(seed), length, amp, wave)
        assert obs.shape[1] == 3 and obs.shape[0] >= 1
        for (x1, y1, r1), (x2, y2, r2) in itertools.combinations(obs, 2):
            assert math.hypot(x1 - x2, y1 - y2) - r1 - r2 >= GAP_MIN - 1e-9
        for x, y, r in obs:
            assert START_CLEAR - 1e-9 <= x <= length - END_CLEAR + 1e-9 or not straight
            assert math.hypot(x, y) - r > 10.0  # start clear
            y_path = 0.0 if straight else amp * math.sin(2 * math.pi * x / wave)
            # room to pass on at least one side inside the corridor (> 4 m + margin)
            assert d_L - (abs(y - y_path) + r) > 6.0
    if name == "avoidance":  # the start-goal line is always blocked
        for seed in range(20):
            obs = LAYOUTS[name](np.random.default_rng(seed), length, amp, wave)
            assert np.any(np.abs(obs[:, 1]) - obs[:, 2] <= 2.0)


@pytest.mark.parametrize("task", ["PlanningStraight", "PlanningSine", "ObstacleAvoidance"])
def test_scatter_layout_is_drawn_around_the_route_every_episode(task: str) -> None:
    env = gym.make(f"rov_envs/{task}-v0", layout="scatter")
    config = env.unwrapped.config
    sine = config.task.path_kind == 1
    curve_x = np.linspace(0.0, config.length, 4001)
    curve_y = (
        config.amplitude * np.sin(2 * np.pi * curve_x / config.wavelength) if sine else 0 * curve_x
    )
    counts = set()
    for seed in range(40):
        env.reset(seed=seed)
        layout = env.unwrapped.obstacles
        counts.add(len(layout))
        x, y, r = layout.T
        assert ((0.75 <= r) & (r <= 2.5)).all()
        off_route = np.hypot(x[:, None] - curve_x, y[:, None] - curve_y).min(axis=1)
        assert (off_route <= 10.0 + 1e-6).all()  # within 10 m of the route
        assert (np.hypot(x, y) - r > 10.0).all()  # the start is clear
        gaps = np.hypot(x[:, None] - x, y[:, None] - y) - r[:, None] - r
        assert (gaps[~np.eye(len(r), dtype=bool)] >= GAP_MIN - 1e-9).all()  # passable pairs
    assert len(counts) > 3  # its density varies from episode to episode
    with pytest.raises(ValueError, match="layout"):
        gym.make(f"rov_envs/{task}-v0", layout="dense", obstacles=[(50.0, 5.0, 1.0)])
    with pytest.raises(ValueError, match="layout='maze'"):
        gym.make(f"rov_envs/{task}-v0", layout="maze")
