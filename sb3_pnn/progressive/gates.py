"""Selectors of the SPNN (paper eq. 15 and, beyond the paper, its future work).

Every gate maps a batch of (preprocessed) observations to weights g(s) of shape (B, 2) over the
two prior columns [path following, obstacle avoidance]; rows sum to 1.

* ``"hard"`` (the paper's switch): with d = min(obs[sonar_key]) * sonar_range, the nearest
  obstacle in metres, g = [1, 0] when d > d_th and [0, 1] when d <= d_th. Decided per sample by
  a mask, never by Python control flow.
* ``"soft"``: g_2 = sigmoid((d_th - d) / temperature), g_1 = 1 - g_2; it tends to the hard gate
  as temperature -> 0 (at d == d_th it gives 0.5, the hard gate picks column 2).
* ``corridor`` (beyond the paper, either distance gate): the avoidance column is weighted only
  while the vehicle is inside the fraction ``corridor`` of the corridor whose edge ends the
  episode, |g| / d_L < corridor, read from the observation's "path" part [a_c / pi, g / d_L];
  outside it the path column steers, whatever the sonar reads. The avoidance column trains
  within 30 m of its start-goal line and, among obstacles near a bend of the sinusoid (d_L =
  15 m), keeps detouring until the corridor's edge ends the episode (docs/ablation section 25).
* ``latch_key`` (beyond the paper, the hard gate): the avoidance column has control while the
  observation's part ``latch_key`` reads 1 (rov_envs' ``obstacle_latch``: on from a reading
  within its ``on`` metres until one beyond its ``off``) instead of while d <= d_th: a switch
  with memory whose memory is in the observation, so replayed samples switch as the acting
  policy did.
* ``"learned"`` (A2T-style, Rajendran et al. 2017): g = softmax(MLP(s)) from the flattened new
  observation; trained by the loss of the network that owns it. The actor and each critic own
  one (a shared gate would sit in two optimizers); hard and soft gates have no parameters, so the
  actor and critics use the very same rule.
"""

from __future__ import annotations

import torch as th
from torch import nn

GATES = ("hard", "soft", "learned")


def checked_corridor(value: object, name: str = "corridor") -> float | None:
    """A gate's corridor bound: None, or a fraction of d_L in (0, 1]; else a ValueError naming
    ``name`` and the value."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value <= 1:
        raise ValueError(f"{name} must be a fraction of d_L in (0, 1] or None, got {value!r}")
    return float(value)


def nearest_distance(obs: dict[str, th.Tensor], sonar_key: str, sonar_range: float) -> th.Tensor:
    """d = min over sonar sectors of obs[sonar_key], times sonar_range: shape (B,)."""
    if not isinstance(obs, dict) or sonar_key not in obs:
        keys = list(obs) if isinstance(obs, dict) else type(obs).__name__
        raise KeyError(f"SPNN gate needs observation key {sonar_key!r}; observation has {keys}")
    return obs[sonar_key].float().flatten(1).min(dim=1).values * sonar_range


class DistanceGate(nn.Module):
    """The hard (paper) or soft switch on the nearest-obstacle distance (module docstring)."""

    def __init__(
        self,
        mode: str = "hard",
        d_th: float = 12.5,
        sonar_range: float = 25.0,
        sonar_key: str = "sonar",
        temperature: float = 1.0,
        corridor: float | None = None,
        path_key: str = "path",
        latch_key: str | None = None,
    ):
        super().__init__()
        if mode not in ("hard", "soft"):
            raise ValueError(f"DistanceGate mode must be 'hard' or 'soft', got {mode!r}")
        if mode == "soft" and not temperature > 0:
            raise ValueError(f"soft gate temperature must be > 0 (metres), got {temperature!r}")
        if latch_key is not None and mode != "hard":
            raise ValueError(f"latch_key={latch_key!r} needs the hard gate, got mode={mode!r}")
        if not sonar_range > 0:
            raise ValueError(f"sonar_range must be > 0 (metres), got {sonar_range!r}")
        self.mode = mode
        self.corridor = checked_corridor(corridor, "gate corridor")
        self.path_key = path_key
        self.latch_key = latch_key
        self.d_th = float(d_th)
        self.sonar_range = float(sonar_range)
        self.sonar_key = sonar_key
        self.temperature = float(temperature)

    def rule(self) -> tuple[object, ...]:
        """What the gate computes from: two gates with the same rule give the same weights for
        the same observation (they have no parameters)."""
        return (
            self.mode,
            self.d_th,
            self.sonar_range,
            self.sonar_key,
            self.temperature,
            self.corridor,
            self.path_key,
            self.latch_key,
        )

    def forward(self, obs: dict[str, th.Tensor], features: th.Tensor | None = None) -> th.Tensor:
        if self.latch_key is not None:  # the remembered switch: no distance to compute
            if self.latch_key not in obs:
                raise KeyError(
                    f"SPNN gate with a latch needs observation key {self.latch_key!r}; "
                    f"observation has {list(obs)}"
                )
            near = (obs[self.latch_key].float().flatten(1)[:, 0] > 0.5).float()
        else:
            d = nearest_distance(obs, self.sonar_key, self.sonar_range)
            if self.mode == "hard":
                near = (d <= self.d_th).to(d.dtype)
            else:
                near = th.sigmoid((self.d_th - d) / self.temperature)
        if self.corridor is not None:
            if self.path_key not in obs:
                raise KeyError(
                    f"SPNN gate with a corridor needs observation key {self.path_key!r} "
                    f"([a_c / pi, g / d_L]); observation has {list(obs)}"
                )
            inside = obs[self.path_key].float()[:, 1].abs() < self.corridor
            near = near * inside.to(near.dtype)
        return th.stack([1.0 - near, near], dim=1)


class LearnedGate(nn.Module):
    """A2T-style attention over the prior columns: softmax(MLP(features)), (B, n_priors)."""

    def __init__(self, in_dim: int, n_priors: int = 2, hidden: int = 32):
        super().__init__()
        self.net = nn.Sequential(nn.Linear(in_dim, hidden), nn.ReLU(), nn.Linear(hidden, n_priors))

    def forward(self, obs: dict[str, th.Tensor], features: th.Tensor | None = None) -> th.Tensor:
        assert features is not None
        return th.softmax(self.net(features), dim=1)
