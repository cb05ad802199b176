"""Play a trained SPNN with a memory in eq. 15's hard switch (beyond the paper).

Eq. 15 hands the vehicle to the obstacle-avoidance column while the nearest sonar reading is
within d_th and back to the path-following column as soon as it is not. rov_envs' sonar looks
180 degrees ahead, so it loses an obstacle the vehicle turns away from; the memoryless switch
then returns control to the path follower, which turns the vehicle back toward the obstacle,
and the two columns can alternate until the episode's time limit. :class:`SwitchMemory` plays an
SPNN trained with eq. 15's switch (its training is unchanged) with a Schmitt trigger instead:
once the avoidance column has control it keeps it until the nearest reading is beyond
d_th + hysteresis; every episode starts without memory. One memory per vehicle of the batch,
reset where ``episode_start`` is true, as SB3's ``predict`` passes it for recurrent policies.

A model trained with the memory as an observation part is a different thing
(``SelectivePolicy(gate_latch_key=...)`` with rov_envs' ``obstacle_latch``): its replayed samples
switch as the acting policy did. Measured in docs/ablation sections 42 and 46.

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


class SwitchMemory:
    """A trained SPNN whose hard gate keeps the avoidance column until the nearest reading is
    beyond ``d_th + hysteresis`` (m); ``predict`` as SB3's, one memory per vehicle.

    :param model: a loaded SPNN model (``DiscreteSAC`` with a ``SelectivePolicy`` whose gate is
        eq. 15's hard switch, without ``gate_latch_key``)
    :param hysteresis: metres beyond d_th at which the avoidance column hands control back (0:
        eq. 15's memoryless switch)
    :param d_th: the switch distance; None (default): the model's own
    """

    def __init__(self, model: Any, hysteresis: float, d_th: float | None = None):
        gate = getattr(getattr(getattr(model, "policy", None), "actor", None), "gate", None)
        if getattr(gate, "mode", None) != "hard" or getattr(gate, "latch_key", None) is not None:
            raise ValueError(
                "SwitchMemory needs an SPNN whose gate is eq. 15's hard switch without a latch "
                f"part, got gate {gate!r}"
            )
        for name, value in (("hysteresis", hysteresis), ("d_th", d_th)):
            if value is not None and (not is_finite_number(value) or value < 0):
                raise ValueError(f"{name}={value!r} is not allowed: expected a distance >= 0 (m)")
        self.model, self.gate = model, gate
        self.hysteresis = float(hysteresis)
        self.d_th = float(gate.d_th if d_th is None else d_th)
        self.near: np.ndarray | None = None

    def reset(self) -> None:
        """Forget every vehicle's memory (as ``episode_start`` true for all)."""
        self.near = None

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        nearest = np.asarray(obs[self.gate.sonar_key]).min(axis=-1) * self.gate.sonar_range
        near = remembered_switch(nearest, self.near, self.d_th, self.hysteresis, episode_start)
        self.near = near
        trained = self.gate.d_th
        # the gate selects per sample: a d_th above or below every reading decides it
        self.gate.d_th = th.as_tensor(np.where(near, np.inf, -np.inf), dtype=th.float32)
        try:
            return self.model.predict(obs, state, episode_start, deterministic)
        finally:
            self.gate.d_th = trained
