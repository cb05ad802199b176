"""The "latch" part (``obstacle_latch``): a Schmitt trigger on the nearest sonar reading, each
episode starting from its first reading alone, the same in the single env, the Gymnasium vector
env and SB3's same-step autoreset."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import rov_envs  # noqa: F401 - registers the tasks
from rov_envs.envs.sb3 import RovSB3VecEnv
from rov_envs.sim.config import SONAR_RANGE

ON, OFF = 12.5, 22.5
STRAIGHT = "rov_envs/PlanningStraight-v0"


def _expected(nearest: list[float]) -> list[int]:
    """The trigger's state after each reading, from no memory."""
    state, out = False, []
    for d in nearest:
        state = d <= ON or (state and d <= OFF)
        out.append(int(state))
    return out


def test_latch_is_a_schmitt_trigger_on_the_nearest_reading() -> None:
    env = gym.make(STRAIGHT, obstacle_latch=(ON, OFF))
    plain = gym.make(STRAIGHT)
    obs, _ = env.reset(seed=4)
    ref, _ = plain.reset(seed=4)
    nearest, latch = [float(obs["sonar"].min() * SONAR_RANGE)], [int(obs["latch"][0])]
    turned = False
    for _ in range(300):  # ahead until an obstacle is within 12 m, one turn, ahead past it
        action = 1 if nearest[-1] < 12.0 and not turned else 2
        turned |= action == 1
        obs, _, term, trunc, _ = env.step(action)
        ref, *_ = plain.step(action)
        assert set(obs) == set(ref) | {"latch"}  # the other parts are untouched
        assert all(np.array_equal(obs[k], ref[k]) for k in ref)
        nearest.append(float(obs["sonar"].min() * SONAR_RANGE))
        latch.append(int(obs["latch"][0]))
        if term or trunc:
            break
    assert latch == _expected(nearest)
    held = [i for i, d in enumerate(nearest) if ON < d <= OFF and latch[i]]
    assert len(held) >= 5, "passing the obstacle keeps the latch on beyond ON"
    assert env.observation_space["latch"].contains(obs["latch"])


def test_vector_envs_reset_the_latch_with_the_episode() -> None:
    """SB3's same-step autoreset: the terminal observation keeps the ended episode's latch, the
    next episode's first observation starts from its own reading."""
    env = RovSB3VecEnv(3, "PlanningStraight", obstacle_latch=(ON, OFF))
    obs = env.reset()
    previous = obs["latch"][:, 0].astype(bool)
    ends = 0
    for _ in range(400):
        obs, _, dones, infos = env.step(np.full(3, 2))  # straight ahead: into the obstacles
        nearest = obs["sonar"].min(axis=1) * SONAR_RANGE
        for i, info in enumerate(infos):
            if dones[i]:
                ends += 1
                final = info["terminal_observation"]
                d = float(final["sonar"].min() * SONAR_RANGE)
                assert final["latch"][0] == float(d <= ON or (previous[i] and d <= OFF))
                assert obs["latch"][i, 0] == float(nearest[i] <= ON)  # no memory carried
            else:
                want = nearest[i] <= ON or (previous[i] and nearest[i] <= OFF)
                assert obs["latch"][i, 0] == float(want)
        previous = obs["latch"][:, 0].astype(bool)
        if ends >= 3:
            break
    assert ends >= 3


@pytest.mark.parametrize(
    ("task", "value"),
    [
        ("PlanningStraight", (ON,)),
        ("PlanningStraight", (OFF, ON)),
        ("PlanningStraight", (0.0, OFF)),
        ("PlanningStraight", "near"),
        ("PathFollowingStraight", (ON, OFF)),  # no sonar
    ],
)
def test_bad_latch_is_refused(task, value) -> None:
    with pytest.raises(ValueError, match=r"obstacle_latch=.* is not allowed: expected None or"):
        gym.make(f"rov_envs/{task}-v0", obstacle_latch=value)
