"""A diagnosis at inference: SPNN's corridor bound with a release distance (docs/ablation
section 49, not adopted).

The gate's corridor bound (``spnn_gate_corridor=c``) weights the avoidance column only while
abs(g) < c d_L. A detour that reaches the bound hands the vehicle to the path column, which
turns it back inside, where the avoidance column may take it out again: the two can alternate
along abs(g) = c d_L. :class:`CorridorRelease` plays a trained SPNN with a hysteresis on the
bound: once abs(g) has reached c d_L the avoidance column stays cut until abs(g) < r d_L
(r < c), per vehicle, forgotten at an episode's start. Training is unchanged.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import torch as th

from sb3_pnn.common.policy_wrapper import PolicyWrapper
from sb3_pnn.progressive.switch_memory import remembered_switch


class CorridorRelease(PolicyWrapper):
    """A policy (a loaded SPNN model, or a wrapper of one with SB3's ``predict``) whose gate's
    corridor bound is released only below ``release`` d_L once it has cut.

    :param policy: what to play (its ``predict`` is called)
    :param gate: the SPNN's distance gate (``model.policy.actor.gate``), with a corridor bound
    :param release: the fraction of d_L below which the bound lets the avoidance column back
    """

    def __init__(self, policy: Any, gate: Any, release: float):
        bound = getattr(gate, "corridor", None)
        if bound is None:
            raise ValueError(
                "CorridorRelease needs an SPNN gate with a corridor bound (spnn_gate_corridor or "
                f"--gate-corridor); got gate {gate!r}"
            )
        if not 0 <= release < bound:
            raise ValueError(
                f"release={release!r} is not allowed: expected a fraction of d_L in [0, {bound})"
            )
        super().__init__(policy)
        self.gate = gate
        self.bound, self.release = float(bound), float(release)
        self.cut: np.ndarray | None = None

    def forget(self) -> None:
        self.cut = None

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        offset = np.abs(np.atleast_2d(np.asarray(obs[self.gate.path_key]))[:, 1])
        # cut at or beyond the bound, kept cut until below the release: SwitchMemory's Schmitt
        # trigger on the negated offset ("within -bound", kept until "beyond -release")
        self.cut = remembered_switch(
            -offset, self.cut, -self.bound, self.bound - self.release, episode_start
        )
        # a bound of 0 cuts the vehicle's sample; the gate compares per sample
        self.gate.corridor = th.as_tensor(np.where(self.cut, 0.0, self.bound), dtype=th.float32)
        try:
            return self.wrapped.predict(obs, state, episode_start, deterministic)
        finally:
            self.gate.corridor = self.bound
