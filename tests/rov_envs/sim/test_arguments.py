"""Keyword arguments: bad values are refused naming the argument; good ones take effect."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from rov_envs_helpers import paper_env

from rov_envs.physics.thrusters import ACTION_TABLE, continuous_to_speeds

BAD = [
    ("obstacles", [(1.0, 2.0)]),
    ("obstacles", [(50.0, 0.0, -1.0)]),
    ("obstacles", [(1.0, 0.0, 1.5)]),  # start point in collision
    ("obstacles", "rocks"),
    ("current", (1.0,)),
    ("current", (5.0, 0.0)),
    ("current", (float("nan"), 0.0)),
    ("sonar_noise", -0.1),
    ("sonar_noise", "loud"),
    ("start_noise", (-1.0, 0.0)),
    ("start_noise", 0.5),
    ("length", 5.0),
    ("length", float("inf")),
    ("amplitude", -60.0),
    ("wavelength", 1.0),
    ("sonar_sectors", 0),
    ("sonar_sectors", 2.5),
    ("sonar_sectors", True),
    ("sonar_span", 0.0),
    ("sonar_span", 7.0),
    ("sonar_range", 0.0),
    ("continuous", "yes"),
    ("max_episode_seconds", 0.0),
    ("render_mode", "ansi"),
    ("success_reward", -1.0),
    ("success_reward", "big"),
    ("vehicle", "bluerov"),
    ("motion_obs", 1),
    ("colour", "red"),
    ("control_period", "0.2"),  # a numeric string is a typo in a config, not a number
    ("sonar_range", "25"),
    ("start_noise", ("1", "0.1")),
    ("los_lookahead", 0.1),
    ("goal_distance", -5.0),
    ("heading_rule", "sideways"),
    ("corridor", 0.5),
    ("corridor", "wide"),
]


@pytest.mark.filterwarnings("ignore::UserWarning")
@pytest.mark.parametrize(("name", "value"), BAD)
def test_bad_argument_refused(name: str, value: object) -> None:
    with pytest.raises(ValueError, match=name) as err:
        gym.make("rov_envs/PlanningStraight-v0", **{name: value})
    assert "expected" in str(err.value)


def test_bad_argument_refused_by_batched_env() -> None:
    with pytest.raises(ValueError, match="sonar_range"):
        gym.make_vec(
            "rov_envs/PlanningSine-v0",
            num_envs=2,
            vectorization_mode="vector_entry_point",
            sonar_range=-1.0,
        )


def test_bad_actions_refused() -> None:
    env = gym.make("rov_envs/PathFollowingStraight-v0").unwrapped
    env.reset(seed=0)
    for bad in (5, -1, 2.7, None, "2", np.array([1, 2]), [2], (2,), np.array([[2]]), True):
        with pytest.raises(ValueError, match="action"):
            env.step(bad)
    for good in (2, np.int64(2), np.array(2), np.array([2])):
        env.step(good)
    cenv = gym.make("rov_envs/PathFollowingStraight-v0", continuous=True).unwrapped
    cenv.reset(seed=0)
    for bad in (np.array([np.nan, 0.0]), [0.1, 0.2, 0.3], "fast", 1.0):
        with pytest.raises(ValueError, match="action"):
            cenv.step(bad)


def test_bad_vector_seeds_and_poses_refused() -> None:
    venv = gym.make_vec(
        "rov_envs/PlanningStraight-v0", num_envs=2, vectorization_mode="vector_entry_point"
    )
    for bad in (1.5, -1, [0, "a"], [0], "seed"):
        with pytest.raises(ValueError, match="seed"):
            venv.reset(seed=bad)
    venv.reset(seed=[3, None])
    env = gym.make("rov_envs/PlanningStraight-v0").unwrapped
    env.reset(seed=0)
    with pytest.raises(ValueError, match="pose"):
        env.set_pose("a", 0.0, 0.0)


def test_custom_obstacles_and_path_parameters() -> None:
    env = paper_env(
        "rov_envs/PlanningSine-v0",
        obstacles=[(40.0, 5.0, 2.0)],
        length=80.0,
        amplitude=5.0,
        wavelength=80.0,
    )
    env.reset(seed=0)
    np.testing.assert_array_equal(env.unwrapped.obstacles, [[40.0, 5.0, 2.0]])
    cfg = env.unwrapped.config
    assert cfg.target == pytest.approx((80.0, 5.0 * math.sin(2 * math.pi)))
    assert cfg.max_steps > 2 * 80 / 0.2  # sine arc longer than its x extent


def test_current_pushes_the_vehicle() -> None:
    xs = []
    for current in ((0.0, 0.0), (0.3, 0.0)):
        env = paper_env("rov_envs/PathFollowingStraight-v0", current=current)
        env.reset(seed=0)
        for _ in range(25):
            _, _, _, _, info = env.step(2)
        xs.append(info["position"][0])
    # 5 s with a 0.3 m/s following current: about 1.5 m further
    assert 1.0 < xs[1] - xs[0] < 2.0


def test_start_noise_perturbs_the_start() -> None:
    env = paper_env("rov_envs/PathFollowingStraight-v0", start_noise=(1.0, 0.2))
    _, info = env.reset(seed=0)
    assert np.hypot(*info["position"]) > 0.0 and info["heading"] != 0.0
    _, info = paper_env("rov_envs/PathFollowingStraight-v0").reset(seed=0)
    assert np.all(info["position"] == 0.0) and info["heading"] == 0.0


def test_sonar_noise_only_on_returns() -> None:
    env = gym.make("rov_envs/PlanningStraight-v0", sonar_noise=1.0)
    env.reset(seed=0)
    env.unwrapped.set_pose(55.0, 0.0, 0.0)
    clean = gym.make("rov_envs/PlanningStraight-v0")
    clean.reset(seed=0)
    clean.unwrapped.set_pose(55.0, 0.0, 0.0)
    noisy_obs, *_ = env.step(2)
    clean_obs, *_ = clean.step(2)
    seen = clean_obs["sonar"] < 1.0
    assert seen.any() and (~seen).any()
    assert np.all(noisy_obs["sonar"][~seen] == 1.0)
    assert np.any(noisy_obs["sonar"][seen] != clean_obs["sonar"][seen])


@pytest.mark.parametrize(("surge", "yaw", "row"), [(1.0, 0.0, 2), (0.5, 0.5, 1), (0.5, -0.5, 4)])
def test_continuous_mapping_in_the_env(surge: float, yaw: float, row: int) -> None:
    """(1, 0) is "Go straight", (0.5, +-0.5) "Turn left/right 2": the env steps alike."""
    np.testing.assert_allclose(continuous_to_speeds(surge, yaw), ACTION_TABLE[row], atol=1e-9)
    cont = gym.make("rov_envs/PathFollowingStraight-v0", continuous=True)
    disc = gym.make("rov_envs/PathFollowingStraight-v0")
    cont.reset(seed=0)
    disc.reset(seed=0)
    for _ in range(4):  # 0.8 s: the turns end the episode (|a_c| >= pi/2) soon after
        c_obs, c_r, *_ = cont.step(np.array([surge, yaw], dtype=np.float32))
        d_obs, d_r, *_ = disc.step(row)
    np.testing.assert_allclose(cont.unwrapped.state, disc.unwrapped.state, rtol=0, atol=1e-9)
    assert c_r == pytest.approx(d_r, abs=1e-9)


def test_sb3_vec_env_names_a_wrong_action_shape() -> None:
    from rov_envs import RovSB3VecEnv

    venv = RovSB3VecEnv(3, "rov_envs/PlanningStraight-v0")
    venv.reset()
    for bad in (np.array([2, 2]), np.array([[2, 2, 2]]), np.array([2.0, 2.0, 2.0])):
        with pytest.raises(ValueError, match="one per vehicle"):
            venv.step(bad)
    venv.step(np.array([2, 2, 2]))
    venv.step(np.array([[2], [2], [2]]))
