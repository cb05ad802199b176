"""The optional "motion" observation part (``motion_obs=True``): sway and yaw rate, body frame."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from rov_envs.envs.sb3 import RovSB3VecEnv
from rov_envs.physics.params import VEHICLES
from rov_envs.sim import kernel as K
from rov_envs.sim.engine import RovBatch
from rov_envs.sim.spaces import MOTION_SPACE


def test_motion_part_is_on_by_default_and_optional(env_id: str) -> None:
    assert "motion" not in gym.make(env_id, motion_obs=False).observation_space.spaces
    env = gym.make(env_id)
    space = env.observation_space
    assert space["motion"] == MOTION_SPACE
    np.testing.assert_array_equal(space["motion"].high, [3.0, 2.0])
    np.testing.assert_array_equal(space["motion"].low, [-3.0, -2.0])
    obs, _ = env.reset(seed=0)
    assert space.contains(obs)
    np.testing.assert_array_equal(obs["motion"], [0.0, 0.0])  # starts at rest
    # every other part is unchanged by the new one
    plain, _ = gym.make(env_id, motion_obs=False).reset(seed=0)
    assert set(obs) - set(plain) == {"motion"}
    for k in plain:
        np.testing.assert_array_equal(obs[k], plain[k])


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_motion_part_equals_the_vehicle_state_after_a_step(vehicle: str) -> None:
    env = gym.make(
        "rov_envs/PlanningSine-v0", motion_obs=True, vehicle=vehicle, current=(0.3, -0.4)
    )
    env.reset(seed=1)
    rng = np.random.default_rng(0)
    seen = []
    for _ in range(40):
        obs, _, term, trunc, info = env.step(int(rng.integers(0, 5)))
        state = env.unwrapped.state  # x y z phi theta psi u v w p q r ...
        np.testing.assert_array_equal(obs["motion"], state[[7, 11]].astype(np.float32))
        np.testing.assert_array_equal(obs["motion"], info["velocity"][1:].astype(np.float32))
        seen.append(obs["motion"])
        if term or trunc:  # (Wu's vehicle pivots off the path under random turns)
            env.reset()
    assert np.abs(np.array(seen)).min(axis=0).max() > 0.0  # it really moved


def test_motion_part_is_clipped_to_its_bounds() -> None:
    b = RovBatch(2, "PathFollowingStraight", motion_obs=True)
    b.reset_all([0, 1])
    lanes = b.lanes.reshape(-1, K.ROWS, K.LANES)
    lanes[0, K.ROW_U + 1, :2] = (10.0, -0.5)  # sway, m/s
    lanes[0, K.ROW_R, :2] = (-7.0, 0.25)  # yaw rate, rad/s
    for i in range(2):
        K.start_episode(i, *b._arrays())  # observe where they stand
    np.testing.assert_array_equal(b.obs_motion, np.float32([[3.0, -2.0], [-0.5, 0.25]]))


def test_batched_equals_single_with_motion() -> None:
    from rov_envs_helpers import KW, _lockstep

    env_id = "rov_envs/PlanningStraightDense-v0"
    kw = {**KW, "motion_obs": True}
    venv = gym.make_vec(env_id, num_envs=3, vectorization_mode="vector_entry_point", **kw)
    singles = {i: gym.make(env_id, **kw) for i in range(3)}
    vobs, _ = venv.reset(seed=11)
    for i, env in singles.items():
        obs, _ = env.reset(seed=11 + i)
        np.testing.assert_array_equal(obs["motion"], vobs["motion"][i])
    assert venv.observation_space.contains(vobs)
    assert _lockstep(venv, singles, 150) >= 3  # compares every part, motion included


def test_sb3_terminal_observation_has_the_motion_part() -> None:
    kw = {"motion_obs": True, "max_episode_seconds": 2.0, "control_period": 0.2}
    venv = RovSB3VecEnv(2, "rov_envs/PlanningStraight-v0", **kw)
    venv.seed(3)
    venv.reset()
    single = gym.make("rov_envs/PlanningStraight-v0", **kw)
    single.reset(seed=3)
    for _ in range(10):
        obs, _, dones, infos = venv.step(np.array([1, 1]))
        sobs, *_ = single.step(1)
    assert dones.all()
    terminal = infos[0]["terminal_observation"]
    assert set(terminal) == set(sobs) == {"motion", "path", "goal", "sonar"}
    for k in sobs:
        np.testing.assert_array_equal(terminal[k], sobs[k])
    assert sobs["motion"][1] > 0.1  # turning left at the end
    np.testing.assert_array_equal(obs["motion"][0], [0.0, 0.0])  # already the next episode


def test_bad_motion_obs_is_refused() -> None:
    with pytest.raises(ValueError, match=r"motion_obs='yes' is not allowed: expected True or"):
        gym.make("rov_envs/PathFollowingSine-v0", motion_obs="yes")
