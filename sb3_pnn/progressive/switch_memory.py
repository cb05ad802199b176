"""Play a trained SPNN with a memory in its distance gate (beyond the paper).

Eq. 15 hands the vehicle to the obstacle-avoidance column while the nearest sonar reading is
within d_th and back to the path-following column as soon as it is not. rov_envs' sonar looks
180 degrees ahead, so it loses an obstacle the vehicle turns away from; the memoryless switch
then returns control to the path follower, which turns the vehicle back toward the obstacle,
and the two columns can alternate until the episode's time limit. :class:`SwitchMemory` plays an
SPNN trained with eq. 15's switch (its training is unchanged) with a Schmitt trigger instead:
once the avoidance column has control it keeps it until the nearest reading is beyond
d_th + hysteresis; every episode starts without memory. One memory per vehicle of the batch,
reset where ``episode_start`` is true, as SB3's ``predict`` passes it for recurrent policies.

The soft gate (the avoidance column weighted sigmoid((d_th - d) / T)) gets the same memory as a
held weight: while the nearest reading stays within d_th + hysteresis, the avoidance column's
weight is never lower than it was on the step before, so turning away from an obstacle does not
by itself hand the vehicle back; beyond d_th + hysteresis the weight is the memoryless one
again. The gate's corridor bound, where set, still acts on the held weight.

A model trained with the memory as an observation part is a different thing
(``SelectivePolicy(gate_latch_key=...)`` with rov_envs' ``obstacle_latch``): its replayed samples
switch as the acting policy did. Measured in docs/ablation sections 42 and 46-48.

Usage::

    model = DiscreteSAC.load("spnn_straight.zip")
    policy = SwitchMemory(model, hysteresis=10.0)
    action, _ = policy.predict(obs, episode_start=np.array([True]))
"""

from __future__ import annotations

from typing import Any

import numpy as np
import torch as th

from rov_envs.sim.engine import schmitt_trigger
from sb3_pnn.common.checks import is_finite_number
from sb3_pnn.common.policy_wrapper import PolicyWrapper


def held_weight(
    weight: np.ndarray,
    nearest: np.ndarray,
    previous: np.ndarray | None,
    release: float,
    episode_start: np.ndarray | None,
) -> np.ndarray:
    """Per vehicle, the soft gate's avoidance weight with memory: the larger of ``weight`` (this
    step's, memoryless) and ``previous`` (the step before's) while the nearest reading is within
    ``release`` metres; this step's alone beyond it and at an episode's start."""
    if previous is None or previous.shape != np.shape(weight):
        return weight
    keep = nearest <= release
    if episode_start is not None:
        keep &= ~np.asarray(episode_start).astype(bool)
    return np.where(keep, np.maximum(weight, previous), weight)


def remembered_switch(
    nearest: np.ndarray,
    previous: np.ndarray | None,
    d_th: float,
    hysteresis: float,
    episode_start: np.ndarray | None,
) -> np.ndarray:
    """Per vehicle, whether the avoidance column has control: within ``d_th`` of the nearest
    obstacle (eq. 15), or it had control on the step before (``previous``) and the obstacle is
    still within ``d_th + hysteresis``; a vehicle starting an episode has no memory."""
    if previous is None or previous.shape != np.shape(nearest):
        return nearest <= d_th
    starting = np.zeros_like(previous) if episode_start is None else np.asarray(episode_start)
    return schmitt_trigger(nearest, previous & ~starting.astype(bool), d_th, d_th + hysteresis)


class SwitchMemory(PolicyWrapper):
    """A trained SPNN whose distance gate remembers: the hard switch keeps the avoidance column
    until the nearest reading is beyond ``d_th + hysteresis`` (m), the soft gate holds the
    avoidance column's weight until then; ``predict`` as SB3's, one memory per vehicle.

    :param model: a loaded SPNN model (``DiscreteSAC`` with a ``SelectivePolicy`` whose gate is
        eq. 15's hard switch or the soft gate, without ``gate_latch_key``)
    :param hysteresis: metres beyond d_th at which the memory is released (0: the gate without
        memory)
    :param d_th: the switch distance; None (default): the model's own
    """

    def __init__(self, model: Any, hysteresis: float, d_th: float | None = None):
        gate = getattr(getattr(getattr(model, "policy", None), "actor", None), "gate", None)
        if getattr(gate, "mode", None) not in ("hard", "soft") or (
            getattr(gate, "latch_key", None) is not None
        ):
            raise ValueError(
                "SwitchMemory needs an SPNN whose gate is eq. 15's hard switch or the soft gate, "
                f"without a latch part; got gate {gate!r}"
            )
        for name, value in (("hysteresis", hysteresis), ("d_th", d_th)):
            if value is not None and (not is_finite_number(value) or value < 0):
                raise ValueError(f"{name}={value!r} is not allowed: expected a distance >= 0 (m)")
        super().__init__(model)
        self.gate = gate
        self.hysteresis = float(hysteresis)
        self.d_th = float(gate.d_th if d_th is None else d_th)
        self.near: np.ndarray | None = None

    @property
    def model(self) -> Any:
        """The SPNN model played (its other attributes, spaces and ``trained_env`` among them,
        pass through, so that an evaluation reads the model's task keywords and checks its
        spaces)."""
        return self.wrapped

    def forget(self) -> None:
        self.near = None

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        nearest = np.asarray(obs[self.gate.sonar_key]).min(axis=-1) * self.gate.sonar_range
        if self.gate.mode == "hard":
            near = remembered_switch(nearest, self.near, self.d_th, self.hysteresis, episode_start)
            # the gate selects per sample: a d_th above or below every reading decides it
            per_sample = np.where(near, np.inf, -np.inf)
        else:
            temperature = self.gate.temperature
            weight = 1.0 / (1.0 + np.exp(-(self.d_th - nearest) / temperature))
            release = self.d_th + self.hysteresis
            near = held_weight(weight, nearest, self.near, release, episode_start)
            # the d_th at which the gate's own sigmoid gives the held weight
            held = np.clip(near, 1e-7, 1.0 - 1e-7)
            per_sample = nearest + temperature * np.log(held / (1.0 - held))
        self.near = near
        trained = self.gate.d_th
        self.gate.d_th = th.as_tensor(per_sample, dtype=th.float32)
        try:
            return self.model.predict(obs, state, episode_start, deterministic)
        finally:
            self.gate.d_th = trained
