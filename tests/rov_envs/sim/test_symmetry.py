"""The tasks are left-right symmetric up to rounding (rov_envs.sim.symmetry): the reflected
task (obstacles' y and the sine's amplitude negated) driven by the mirrored actions observes the
mirrored observations and earns the same rewards, so a learner may add mirrored samples."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import rov_envs
from rov_envs.sim.symmetry import MIRRORED_ACTIONS, MIRRORED_PARTS


def _mirrored(obs: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    return {
        key: value[::-1] if MIRRORED_PARTS[key] == "reverse" else -value
        for key, value in obs.items()
    }


@pytest.mark.parametrize(
    ("task", "kwargs"),
    [("PlanningStraight", {}),
     ("PlanningSine", {}),
     ("PathFollowingSine", {"goal_obs": True, "goal_offset": True}),
     ("ObstacleAvoidance", {})],
)  # fmt: skip
def test_the_mirrored_task_replays_the_episode_mirrored(task, kwargs) -> None:
    env_id = f"rov_envs/{task}-v0"
    env = gym.make(env_id, start_noise=(0.0, 0.0), **kwargs)
    obs, _ = env.reset(seed=3)
    config = env.unwrapped.config
    mirror_kwargs = dict(kwargs, amplitude=-config.amplitude)
    obstacles = np.asarray(env.unwrapped.obstacles)
    if len(obstacles):
        mirror_kwargs["obstacles"] = [(x, -y, r) for x, y, r in obstacles]
    mirror = gym.make(env_id, start_noise=(0.0, 0.0), **mirror_kwargs)
    mirror_obs, _ = mirror.reset(seed=3)
    actions = np.random.default_rng(0).choice(5, size=600, p=[0.2, 0.15, 0.35, 0.15, 0.15])
    turned = set()
    for step, action in enumerate(actions):
        expected = _mirrored(obs)
        assert set(mirror_obs) == set(expected)
        for key, value in expected.items():
            np.testing.assert_allclose(
                mirror_obs[key], value, rtol=0, atol=1e-6, err_msg=f"{key}, step {step}"
            )
        obs, reward, terminated, truncated, info = env.step(int(action))
        mirror_obs, mirror_reward, m_terminated, m_truncated, m_info = mirror.step(
            MIRRORED_ACTIONS[action]
        )
        turned.add(int(action))
        assert mirror_reward == pytest.approx(reward, rel=1e-9, abs=1e-9)
        assert (m_terminated, m_truncated) == (terminated, truncated)
        assert m_info["position"][1] == pytest.approx(-info["position"][1], rel=1e-9, abs=1e-12)
        if terminated or truncated:
            break
    assert step >= 20 and turned == {0, 1, 2, 3, 4}


def test_the_map_is_an_involution_over_every_part_the_tasks_observe() -> None:
    assert sorted(MIRRORED_ACTIONS) == list(range(5))
    assert all(MIRRORED_ACTIONS[MIRRORED_ACTIONS[a]] == a for a in range(5))
    for env_id in rov_envs.ENV_IDS:
        env = gym.make(env_id, motion_obs=True, goal_obs=True)
        assert set(env.observation_space.spaces) <= set(MIRRORED_PARTS), env_id
    assert rov_envs.LEFT_RIGHT_MIRROR == {
        "actions": list(MIRRORED_ACTIONS),
        "observations": dict(MIRRORED_PARTS),
    }
