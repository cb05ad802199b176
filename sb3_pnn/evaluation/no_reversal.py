"""Play a trained policy without immediate reversals of its turn (beyond the paper).

Table 1's five actions turn left (two strengths), go straight or turn right. A policy near a
row of obstacles can settle into a two-step cycle: Turn left 1, Turn right 1, Turn left 1, ...,
each with a confident probability, every turn undoing the last. Each turn drives one side's
thrusters only, so the vehicle creeps (on a straight line about a quarter of the speed of "Go
straight") and runs out of time (docs/ablation section 50). :class:`NoReversal` plays the
policy's own action except where that action turns to the side opposite to the action played on
the step before: it then plays "Go straight" for that step. A reversal therefore takes two
steps instead of one, and a policy that keeps turning one way is untouched. Training is
unchanged; each vehicle of a batch has its own previous action, forgotten where
``episode_start`` is true (as SB3's ``predict`` passes it), so an episode starts without one.

Usage::

    model = DiscreteSAC.load("spnn_sine.zip")
    policy = NoReversal(model)            # or NoReversal(SwitchMemory(model, hysteresis=10))
    action, _ = policy.predict(obs, episode_start=np.array([True]))
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rov_envs.physics.thrusters import ACTION_NAMES
from sb3_pnn.common.policy_wrapper import PolicyWrapper

#: Table 1's actions by the side they turn to: -1 left, 0 straight, +1 right.
TURN_SIDE: np.ndarray = np.array(
    [
        -1 if name.startswith("Turn left") else 1 if name.startswith("Turn right") else 0
        for name in ACTION_NAMES
    ],
    dtype=np.int64,
)
GO_STRAIGHT: int = ACTION_NAMES.index("Go straight")


def without_reversals(
    actions: np.ndarray, previous: np.ndarray | None, episode_start: np.ndarray | None
) -> np.ndarray:
    """Per vehicle, ``actions`` with "Go straight" where the action turns to the side opposite
    to ``previous`` (the actions played on the step before; None, a different batch shape, or
    a vehicle starting an episode: no previous action)."""
    actions = np.asarray(actions, dtype=np.int64)
    if previous is None or previous.shape != actions.shape:
        return actions.copy()
    before = TURN_SIDE[previous]
    if episode_start is not None:
        before = np.where(np.asarray(episode_start).astype(bool), 0, before)
    reversed_turn = TURN_SIDE[actions] * before < 0
    return np.where(reversed_turn, GO_STRAIGHT, actions)


class NoReversal(PolicyWrapper):
    """A policy (anything with SB3's ``predict``, e.g. a loaded model or a
    :class:`sb3_pnn.progressive.SwitchMemory`) whose turn is never reversed from one step to the
    next: such a step plays "Go straight" instead; ``predict`` as SB3's, one previous action per
    vehicle. Its other attributes (spaces, ``trained_env``) are the policy's.

    :param policy: a policy over Table 1's five actions
    """

    def __init__(self, policy: Any):
        space = getattr(policy, "action_space", None)
        n = getattr(space, "n", None)
        if n is not None and int(n) != len(ACTION_NAMES):
            raise ValueError(
                f"NoReversal needs a policy over Table 1's {len(ACTION_NAMES)} actions; got "
                f"action space {space!r}"
            )
        super().__init__(policy)
        self.previous: np.ndarray | None = None

    def forget(self) -> None:
        self.previous = None

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        actions, state = self.wrapped.predict(obs, state, episode_start, deterministic)
        batch = np.atleast_1d(np.asarray(actions))
        played = without_reversals(batch, self.previous, episode_start)
        self.previous = played
        return (played if np.ndim(actions) else played[0]), state
