"""What an evaluation measured: per-episode records, trajectories and their summary.

:class:`EvaluationResult` holds the statistics behind Figure 20 (success rate with its 95 %
Wilson interval, :func:`wilson_interval`) and Figures 12-19 (distance from the route, heading
deviation, time to target), and saves itself as JSON.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np


def wilson_interval(successes: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """Wilson score interval for a binomial proportion (95 % for ``z = 1.96``).

    ``p = k / n``; centre ``(p + z^2 / 2n) / (1 + z^2 / n)``, half-width
    ``z / (1 + z^2 / n) * sqrt(p (1 - p) / n + z^2 / 4n^2)``. Returns ``(lo, hi)`` in [0, 1].
    """
    for name, value in (("successes", successes), ("n", n)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise ValueError(f"{name}={value!r} is not allowed: expected an int")
    if n < 1:
        raise ValueError(f"n={n!r} is not allowed: expected an int >= 1")
    if not 0 <= successes <= n:
        raise ValueError(f"successes={successes!r} is not allowed: expected an int in [0, n={n}]")
    z = float(z)
    if not math.isfinite(z) or z <= 0:
        raise ValueError(f"z={z!r} is not allowed: expected a finite float > 0")
    p = successes / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2.0 * n)) / denom
    half = z / denom * math.sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n))
    return (max(0.0, centre - half), min(1.0, centre + half))


@dataclass
class EpisodeRecord:
    """One evaluation episode (distances in m, angles in rad, times in s).

    The cross-track and heading statistics are over the states after each step (the reset state
    is not counted); ``duration_s = steps * dt``; ``time_to_target`` is it for a success, else None.
    """

    index: int
    seed: int
    success: bool
    end_reason: str
    collision: bool
    steps: int
    duration_s: float
    episode_return: float
    mean_abs_cross_track: float
    max_abs_cross_track: float
    mean_abs_heading_error: float
    time_to_target: float | None
    #: sum_t gamma^t r_t over the episode, when the evaluation was given a discount gamma (the
    #: quantity SAC maximises from the start state; None otherwise)
    discounted_return: float | None = None


@dataclass
class Trajectory:
    """Time series of one episode; ``t[0] = 0`` is the reset pose, then one entry per step.

    ``actions[j]`` is the action taken at ``t[j]`` (one fewer entry than ``t``).
    """

    index: int
    seed: int
    success: bool
    end_reason: str
    t: list[float]
    x: list[float]
    y: list[float]
    heading_error: list[float]
    cross_track: list[float]
    actions: list[Any]
    obstacles: list[list[float]]


@dataclass
class EvaluationResult:
    """Statistics of :func:`evaluate_policy_on_task` (see the module docstring)."""

    env_id: str
    policy_name: str
    n_episodes: int
    seed: int
    start_noise: tuple[float, float]
    env_kwargs: dict[str, Any]
    deterministic: bool
    successes: int
    success_rate: float
    success_ci95: tuple[float, float]
    collisions: int
    collision_rate: float
    end_reasons: dict[str, int]
    mean_abs_cross_track: float
    max_abs_cross_track: float
    mean_abs_heading_error: float
    mean_time_to_target: float | None
    mean_return: float
    episodes: list[EpisodeRecord] = field(default_factory=list)
    trajectories: list[Trajectory] = field(default_factory=list)
    wall_time_s: float = 0.0
    #: the rov_envs vehicle preset that ran (``env.unwrapped.vehicle``; None for other envs)
    vehicle: str | None = None
    #: mean of the episodes' discounted returns, when the evaluation was given a discount
    mean_discounted_return: float | None = None

    def to_dict(self) -> dict[str, Any]:
        """A JSON-serialisable dict (tuples become lists). The discounted returns appear only
        when the evaluation measured them, so that other results read as they always have."""
        data = _jsonable(asdict(self))
        if self.mean_discounted_return is None:
            del data["mean_discounted_return"]
            for episode in data["episodes"]:
                del episode["discounted_return"]
        return data

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> EvaluationResult:
        """Rebuild a result written by :meth:`to_dict`."""
        d = dict(data)
        d["start_noise"] = tuple(d["start_noise"])
        d["success_ci95"] = tuple(d["success_ci95"])
        d["episodes"] = [EpisodeRecord(**e) for e in d.get("episodes", [])]
        d["trajectories"] = [Trajectory(**t) for t in d.get("trajectories", [])]
        return cls(**d)

    def save_json(self, path: str | Path) -> Path:
        """Write :meth:`to_dict` as JSON to ``path`` atomically (parents created); return it."""
        from sb3_pnn.common.atomic import write_text_atomic

        return write_text_atomic(path, json.dumps(self.to_dict(), indent=1))

    def summary_rows(self) -> list[tuple[str, str]]:
        """(label, value) rows for a readable table."""
        lo, hi = self.success_ci95
        ttt = self.mean_time_to_target
        reasons = ", ".join(f"{k} {v}" for k, v in sorted(self.end_reasons.items()))
        last = self.seed + self.n_episodes - 1
        pos, head = self.start_noise[0], math.degrees(self.start_noise[1])
        rate = f"{100 * self.success_rate:.1f} % [{100 * lo:.1f}, {100 * hi:.1f}] (95 % Wilson)"
        return [
            ("task", self.env_id),
            ("vehicle", self.vehicle or "n/a"),
            ("policy", self.policy_name),
            ("episodes (seeds)", f"{self.n_episodes} ({self.seed}..{last})"),
            ("start noise", f"{pos:g} m, {head:g} deg"),
            ("success rate", rate),
            ("collisions", f"{self.collisions} ({100 * self.collision_rate:.1f} %)"),
            ("episode endings", reasons),
            ("mean |distance from route|", f"{self.mean_abs_cross_track:.3f} m"),
            ("max |distance from route|", f"{self.max_abs_cross_track:.3f} m"),
            ("mean |heading deviation|", f"{math.degrees(self.mean_abs_heading_error):.2f} deg"),
            ("mean time to target", "n/a (no success)" if ttt is None else f"{ttt:.1f} s"),
            ("mean return", f"{self.mean_return:.1f}"),
            *(
                []
                if self.mean_discounted_return is None
                else [("mean discounted return", f"{self.mean_discounted_return:.1f}")]
            ),
            ("wall time", f"{self.wall_time_s:.1f} s"),
        ]

    def format_table(self) -> str:
        """The summary as an aligned two-column text table."""
        rows = self.summary_rows()
        width = max(len(k) for k, _ in rows)
        return "\n".join(f"{k:<{width}}  {v}" for k, v in rows)


def _jsonable(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, (np.bool_, bool)):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, (np.floating, float)):
        v = float(value)
        return v if math.isfinite(v) else None
    return value


def summarise(
    eps: list[EpisodeRecord], trajectories: list[Trajectory], **meta: Any
) -> EvaluationResult:
    n = len(eps)
    successes = sum(e.success for e in eps)
    collisions = sum(e.collision for e in eps)
    reasons: dict[str, int] = {}
    for e in eps:
        reasons[e.end_reason] = reasons.get(e.end_reason, 0) + 1
    times = [e.time_to_target for e in eps if e.time_to_target is not None]
    discounted = [e.discounted_return for e in eps]
    return EvaluationResult(
        n_episodes=n,
        successes=successes,
        success_rate=successes / n,
        success_ci95=wilson_interval(successes, n),
        collisions=collisions,
        collision_rate=collisions / n,
        end_reasons=reasons,
        mean_abs_cross_track=float(np.mean([e.mean_abs_cross_track for e in eps])),
        max_abs_cross_track=float(max(e.max_abs_cross_track for e in eps)),
        mean_abs_heading_error=float(np.mean([e.mean_abs_heading_error for e in eps])),
        mean_time_to_target=float(np.mean(times)) if times else None,
        mean_return=float(np.mean([e.episode_return for e in eps])),
        mean_discounted_return=(
            None if None in discounted else float(np.mean(discounted))  # type: ignore[arg-type]
        ),
        episodes=eps,
        trajectories=trajectories,
        **meta,
    )
