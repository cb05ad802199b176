"""Mirrored minibatches: a learner that knows its task is left-right symmetric learns from each
stored transition and from its mirror image (not in the paper).

A task is mirror-symmetric when reflecting it maps every episode to an episode of the reflected
task with the same rewards (``rov_envs.LEFT_RIGHT_MIRROR`` for the BlueROV2 tasks, checked by
``tests/rov_envs/sim/test_symmetry.py``). The reflected transition (M s, M a, r, M s') is then a
true transition of the reflected task, and the soft Q-function of a symmetric task satisfies
Q(M s, M a) = Q(s, a). Replacing part of each minibatch by mirrored transitions (as data
augmentation in "invariant transform experience replay", Lin et al. 2020) shows the critics and
the actor the same situations with the obstacles on the other side, where the planning tasks'
one fixed layout shows them on one side only.

A mirror map is plain data, so that a checkpoint stores it without code:
``{"actions": [index of each action's mirror image], "observations": {part: "negate" |
"reverse" | "keep"}}`` for a ``Dict`` observation. Half of each minibatch
(:data:`MIRROR_FRACTION`; its first rows, which are drawn at random) is mirrored, so that an
update costs what it cost without the mirror.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, NamedTuple

import torch as th
from gymnasium import spaces

__all__ = ["MIRROR_FRACTION", "MIRROR_OPERATIONS", "MirroredBatches", "check_mirror_map"]

#: What a mirror map may do to an observation part: change its sign, reverse its last axis
#: (sectors ordered right to left become left to right), or leave it.
MIRROR_OPERATIONS = ("negate", "reverse", "keep")
#: The share of each minibatch that is mirrored.
MIRROR_FRACTION = 0.5


def check_mirror_map(
    mirror: Any, observation_space: spaces.Space, action_space: spaces.Space, where: str = "mirror"
) -> dict[str, Any]:
    """``mirror`` as a checked plain dict, or a ValueError naming what is wrong: a ``Dict``
    observation space whose every part has an operation of :data:`MIRROR_OPERATIONS` (the
    map's other parts are dropped), and a discrete action space whose actions the map permutes
    with an involution (mirroring twice is the identity)."""
    if not isinstance(mirror, Mapping) or set(mirror) != {"actions", "observations"}:
        raise ValueError(
            f"{where}={mirror!r:.200} is not allowed: expected a dict with the keys 'actions' "
            "and 'observations' (e.g. rov_envs.LEFT_RIGHT_MIRROR)"
        )
    if not isinstance(action_space, spaces.Discrete):
        raise ValueError(f"{where} needs discrete actions, got the action space {action_space}")
    n = int(action_space.n)
    actions = mirror["actions"]
    if (
        not isinstance(actions, (list, tuple))
        or sorted(a for a in actions if isinstance(a, int) and not isinstance(a, bool))
        != list(range(n))
        or any(actions[actions[a]] != a for a in range(n))
    ):
        raise ValueError(
            f"{where}['actions']={actions!r:.200} is not allowed: expected the mirror image of "
            f"each of the {n} actions, a permutation of 0..{n - 1} that is its own inverse"
        )
    if not isinstance(observation_space, spaces.Dict):
        raise ValueError(
            f"{where} needs a Dict observation space (its parts are mirrored by name), got "
            f"{observation_space}"
        )
    parts = mirror["observations"]
    names = list(observation_space.spaces)
    if (
        not isinstance(parts, Mapping)
        or not set(names) <= set(parts)
        or any(parts[name] not in MIRROR_OPERATIONS for name in names)
    ):
        raise ValueError(
            f"{where}['observations']={parts!r:.200} is not allowed: expected one of "
            f"{list(MIRROR_OPERATIONS)} for each observation part {sorted(names)}"
        )
    # parts the space lacks are left out (one map serves every task of a family)
    return {"actions": [int(a) for a in actions], "observations": {n: parts[n] for n in names}}


class MirroredBatches:
    """Replaces the first ``fraction`` of the rows of each sampled minibatch by their mirror
    image: s, s' (and the one-step successor, when the sample has one) and a mirrored;
    rewards, ends and discounts kept."""

    def __init__(self, mirror: Mapping[str, Any], fraction: float = MIRROR_FRACTION):
        self.actions = th.as_tensor(mirror["actions"], dtype=th.long)
        self.parts = dict(mirror["observations"])
        self.fraction = float(fraction)

    def __call__(self, samples: NamedTuple) -> NamedTuple:
        observations = samples.observations  # type: ignore[attr-defined]
        k = int(round(self.fraction * len(samples.actions)))  # type: ignore[attr-defined]
        if k == 0:
            return samples
        changes: dict[str, Any] = {
            "observations": self._observations(observations, k),
            "next_observations": self._observations(samples.next_observations, k),  # type: ignore[attr-defined]
            "actions": self._actions(samples.actions, k),  # type: ignore[attr-defined]
        }
        successors = getattr(samples, "step_next_observations", None)
        if successors is not None:
            changes["step_next_observations"] = self._observations(successors, k)
        return samples._replace(**changes)  # type: ignore[attr-defined]

    def _observations(self, observations: Mapping[str, th.Tensor], k: int) -> dict[str, th.Tensor]:
        out = {}
        for key, value in observations.items():
            op = self.parts[key]
            if op == "keep":
                out[key] = value
                continue
            head = -value[:k] if op == "negate" else value[:k].flip(-1)
            out[key] = th.cat((head, value[k:]))
        return out

    def _actions(self, actions: th.Tensor, k: int) -> th.Tensor:
        table = self.actions.to(actions.device)
        head = table[actions[:k].long()].to(actions.dtype)
        return th.cat((head, actions[k:]))
