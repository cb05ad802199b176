"""Registration, Gymnasium's env checker, observation layout, render."""

from __future__ import annotations

import importlib

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import rov_envs

EXPECTED_IDS = {
    "rov_envs/PathFollowingStraight-v0",
    "rov_envs/PathFollowingSine-v0",
    "rov_envs/ObstacleAvoidance-v0",
    "rov_envs/PlanningStraight-v0",
    "rov_envs/PlanningSine-v0",
    "rov_envs/PlanningStraightUniform-v0",
    "rov_envs/PlanningStraightDense-v0",
    "rov_envs/PlanningSineDense-v0",
}


def test_exact_ids_registered() -> None:
    assert set(rov_envs.ENV_IDS) == EXPECTED_IDS
    for env_id in EXPECTED_IDS:
        spec = gym.spec(env_id)
        assert spec.vector_entry_point is not None


def test_registration_idempotent() -> None:
    before = {k: v for k, v in gym.registry.items() if k.startswith("rov_envs/")}
    importlib.reload(rov_envs)
    rov_envs.register_envs()
    after = {k: v for k, v in gym.registry.items() if k.startswith("rov_envs/")}
    assert before.keys() == after.keys()


def test_check_env(env_id: str) -> None:
    env = gym.make(env_id)
    check_env(env.unwrapped, skip_render_check=True)  # render tested below
    check_env(gym.make(env_id, continuous=True).unwrapped, skip_render_check=True)


#: The observation parts of each kind of task by default (the recommended set-up); with
#: ``motion_obs=False, goal_obs=False, path_obs=True`` every task observes the paper's state.
PARTS = {
    "PathFollowing": {"path", "motion"},
    "ObstacleAvoidance": {"goal", "sonar", "motion"},
    "Planning": {"path", "goal", "sonar", "motion"},
}


def test_observation_parts(env_id: str) -> None:
    kind = next(k for k in PARTS if env_id.startswith(f"rov_envs/{k}"))
    assert set(gym.make(env_id).observation_space.spaces) == PARTS[kind]
    env = gym.make(env_id, motion_obs=False, goal_obs=False, path_obs=True)
    obs, info = env.reset(seed=1)
    has_sonar = kind != "PathFollowing"
    assert set(obs) == ({"path", "sonar"} if has_sonar else {"path"})
    assert obs["path"].shape == (2,) and obs["path"].dtype == np.float32
    if has_sonar:
        assert obs["sonar"].shape == (9,) and obs["sonar"].dtype == np.float32
        assert env.unwrapped.sonar_range == 25.0
    assert env.action_space == gym.spaces.Discrete(5)
    obs, *_, info = env.step(2)
    for key in (
        "position",
        "heading",
        "velocity",
        "cross_track",
        "heading_error",
        "obstacle_distance",
        "collision",
        "r_c",
        "r_v",
        "r_terminal",
    ):
        assert key in info
    assert info["position"].shape == (2,) and info["velocity"].shape == (3,)
    np.testing.assert_allclose(obs["path"][0], info["heading_error"] / np.pi, rtol=1e-6)


def test_sonar_arguments_shape_the_space() -> None:
    env = gym.make("rov_envs/PlanningStraight-v0", sonar_sectors=15, sonar_range=40.0)
    obs, _ = env.reset(seed=0)
    assert obs["sonar"].shape == (15,)
    assert env.unwrapped.sonar_range == 40.0


@pytest.mark.parametrize(
    "env_id", ["rov_envs/PlanningStraight-v0", "rov_envs/PathFollowingSine-v0"]
)
def test_render_rgb_array(env_id: str) -> None:
    env = gym.make(env_id, render_mode="rgb_array")
    env.reset(seed=0)
    for _ in range(20):
        env.step(2)
    img = env.render()
    assert img.ndim == 3 and img.shape[2] == 3 and img.dtype == np.uint8
    assert img.shape[0] > 16 and img.shape[1] > 16
    # the picture is not blank: path, vehicle and (for planning) obstacles are drawn
    assert len(np.unique(img.reshape(-1, 3), axis=0)) >= 4
    plain = gym.make(env_id)
    plain.reset(seed=0)
    assert plain.render() is None  # no render_mode: nothing
