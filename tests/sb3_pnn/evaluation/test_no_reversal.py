"""NoReversal: a turn that reverses the step before's is played as "Go straight"; each vehicle
keeps its own previous action, forgotten at an episode's start; a policy that alternates the
two gentle turns creeps, and played through NoReversal it gets further in the same time."""

from __future__ import annotations

from types import SimpleNamespace

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

import rov_envs  # noqa: F401
from rov_envs.physics.thrusters import ACTION_NAMES
from sb3_pnn.evaluation import NoReversal
from sb3_pnn.evaluation.no_reversal import GO_STRAIGHT, TURN_SIDE, without_reversals

LEFT_1, LEFT_2 = ACTION_NAMES.index("Turn left 1"), ACTION_NAMES.index("Turn left 2")
RIGHT_1, RIGHT_2 = ACTION_NAMES.index("Turn right 1"), ACTION_NAMES.index("Turn right 2")


class Scripted:
    """Plays the given actions in turn, one row of a batch per call."""

    action_space = spaces.Discrete(len(ACTION_NAMES))

    def __init__(self, rows):
        self.rows = [np.asarray(r) for r in rows]
        self.calls = 0
        self.resets = 0

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        row = self.rows[self.calls % len(self.rows)]
        self.calls += 1
        return row, state

    def reset(self):
        self.resets += 1


def test_turn_sides_follow_table_1() -> None:
    assert TURN_SIDE[[LEFT_1, LEFT_2, GO_STRAIGHT, RIGHT_1, RIGHT_2]].tolist() == [-1, -1, 0, 1, 1]
    assert ACTION_NAMES[GO_STRAIGHT] == "Go straight"


def test_only_a_reversed_turn_becomes_go_straight() -> None:
    previous = np.array([RIGHT_1, LEFT_2, LEFT_1, GO_STRAIGHT, RIGHT_2, RIGHT_1])
    actions = np.array([LEFT_1, RIGHT_2, LEFT_2, RIGHT_1, RIGHT_1, GO_STRAIGHT])
    played = without_reversals(actions, previous, None)
    assert played.tolist() == [GO_STRAIGHT, GO_STRAIGHT, LEFT_2, RIGHT_1, RIGHT_1, GO_STRAIGHT]
    # no previous action, another batch shape, or a vehicle starting an episode: as chosen
    assert without_reversals(actions, None, None).tolist() == actions.tolist()
    assert without_reversals(actions, previous[:2], None).tolist() == actions.tolist()
    start = np.array([True, False, False, False, False, False])
    assert without_reversals(actions, previous, start).tolist()[:2] == [LEFT_1, GO_STRAIGHT]


def test_an_alternating_policy_is_played_turn_straight_turn_per_vehicle() -> None:
    inner = Scripted([[LEFT_1, RIGHT_1], [RIGHT_1, RIGHT_1], [LEFT_1, LEFT_2], [RIGHT_1, LEFT_2]])
    policy = NoReversal(inner)
    played = [policy.predict(None)[0].tolist() for _ in range(4)]
    # vehicle 0 alternates: left, (right ->) straight, left, straight; vehicle 1 keeps its side
    # twice, is straightened where it reverses, then turns left from "Go straight"
    assert played == [
        [LEFT_1, RIGHT_1],
        [GO_STRAIGHT, RIGHT_1],
        [LEFT_1, GO_STRAIGHT],
        [GO_STRAIGHT, LEFT_2],
    ]
    action, _ = policy.predict(None, episode_start=np.array([True, True]))
    assert action.tolist() == [LEFT_1, RIGHT_1]  # a new episode starts without memory
    policy.reset()
    assert policy.previous is None and inner.resets == 1
    single = NoReversal(Scripted([np.int64(LEFT_2), np.int64(RIGHT_2)]))
    assert [int(single.predict(None)[0]) for _ in range(3)] == [LEFT_2, GO_STRAIGHT, LEFT_2]
    assert np.ndim(single.predict(None)[0]) == 0  # one vehicle's action stays a scalar


def test_attributes_pass_through_and_other_action_spaces_are_refused() -> None:
    inner = Scripted([[GO_STRAIGHT]])
    inner.trained_env = {"control_period": 1.0}
    assert NoReversal(inner).trained_env == {"control_period": 1.0}
    with pytest.raises(ValueError, match=r"Table 1's 5 actions; got action space Discrete\(3\)"):
        NoReversal(SimpleNamespace(action_space=spaces.Discrete(3)))


class BangBang:
    """Turns toward the path's course with the gentle turns only: a chattering controller."""

    action_space = spaces.Discrete(len(ACTION_NAMES))

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        return (RIGHT_1 if obs["path"][0] > 0 else LEFT_1), state


def test_alternating_gentle_turns_creep_and_no_reversal_gets_further() -> None:
    """Turn left 1 and Turn right 1 each drive one side's thrusters: a controller alternating
    them keeps the line at a crawl. Played through NoReversal, a reversal goes straight on all
    four thrusters first, and the same 60 s cover about twice the line, still on it."""

    def run(policy) -> tuple[float, float, list[int]]:
        env = gym.make("rov_envs/PathFollowingStraight-v0")
        obs, info = env.reset(seed=0)
        actions = []
        for step in range(60):
            action, _ = policy.predict(obs, episode_start=np.array([step == 0]))
            actions.append(int(action))
            obs, _, terminated, truncated, info = env.step(int(action))
            assert not (terminated or truncated)
        return float(info["progress"]), abs(float(info["cross_track"])), actions

    creep, off_creep, chatter = run(BangBang())
    steady, off_steady, played = run(NoReversal(BangBang()))
    assert chatter.count(GO_STRAIGHT) == 0 and played.count(GO_STRAIGHT) >= 15
    assert creep < 20.0 and steady > 1.6 * creep  # metres along the line in 60 s
    assert off_creep < 1.0 and off_steady < 1.0


def test_a_wrapped_models_policy_network_stays_reachable() -> None:
    """``policy`` of the wrapper is the wrapped model's policy network, as without it."""
    inner = Scripted([[GO_STRAIGHT]])
    inner.policy = "the model's policy network"
    wrapper = NoReversal(inner)
    assert wrapper.policy == "the model's policy network" and wrapper.wrapped is inner
