"""Figures like the paper's Figures 11-19: trajectories, heading deviation and route distance.

Every function takes runs recorded from the environments: a run is either a list of ``info``
dicts (as returned by ``reset`` and ``step``) or a dict of arrays with keys ``"position"``
(T, 2), ``"heading_error"`` (T,) and ``"cross_track"`` (T,). :func:`record_episode` makes one.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from rov_envs.render.frames import path_points
from rov_envs.sim.config import CONTROL_PERIOD, EnvConfig

Run = Sequence[Mapping[str, Any]] | Mapping[str, np.ndarray]


def run_arrays(run: Run, dt: float = CONTROL_PERIOD) -> dict[str, np.ndarray]:
    """A run as arrays: position (T, 2), heading_error (T,) rad, cross_track (T,) m, time (T,) s.

    ``dt``: seconds between records (the control period).
    """
    if isinstance(run, Mapping):
        pos = np.asarray(run["position"], dtype=np.float64).reshape(-1, 2)
        out = {
            "position": pos,
            "heading_error": np.asarray(run["heading_error"], dtype=np.float64),
            "cross_track": np.asarray(run["cross_track"], dtype=np.float64),
        }
    else:
        if len(run) == 0:
            raise ValueError("run=[] is not allowed: expected at least one info dict")
        out = {
            "position": np.array([np.asarray(i["position"], dtype=np.float64) for i in run]),
            "heading_error": np.array([float(i["heading_error"]) for i in run]),
            "cross_track": np.array([float(i["cross_track"]) for i in run]),
        }
    out["time"] = np.arange(out["position"].shape[0]) * dt
    return out


def record_episode(
    env: Any, policy: Callable[[Any, dict], Any], seed: int | None = None, max_steps: int = 100000
) -> list[dict[str, Any]]:
    """Run ``policy(obs, info) -> action`` for one episode; returns the info dicts (reset first)."""
    obs, info = env.reset(seed=seed)
    infos = [info]
    for _ in range(max_steps):
        obs, _, terminated, truncated, info = env.step(policy(obs, info))
        infos.append(info)
        if terminated or truncated:
            break
    return infos


def plot_runs(
    runs: Sequence[Run],
    labels: Sequence[str] | None = None,
    config: EnvConfig | None = None,
    obstacles: np.ndarray | None = None,
    title: str | None = None,
    dt: float | None = None,
) -> Figure:
    """Trajectory (top), heading deviation a_c in degrees and distance from the route g (m).

    ``config`` (``env.unwrapped.config``) draws the path and the |g| = d_L corridor;
    ``obstacles`` (M, 3) draws the obstacles with their 2 m collision margin; ``dt``, the
    seconds between records, defaults to the config's control period.
    """
    if dt is None:
        dt = config.dt if config is not None else CONTROL_PERIOD
    if len(runs) == 0:
        raise ValueError("runs=[] is not allowed: expected at least one run")
    if labels is not None and len(labels) != len(runs):
        raise ValueError(f"labels={labels!r} is not allowed: expected {len(runs)} labels")
    arrays = [run_arrays(r, dt) for r in runs]
    names = list(labels) if labels is not None else [f"run {k}" for k in range(len(runs))]
    fig = Figure(figsize=(9, 8), layout="constrained")
    gs = fig.add_gridspec(3, 1, height_ratios=[2, 1, 1])
    ax_t = fig.add_subplot(gs[0])
    ax_a = fig.add_subplot(gs[1])
    ax_g = fig.add_subplot(gs[2], sharex=ax_a)
    if config is not None:
        px, py = path_points(config)
        ax_t.plot(px, py, "--", color="tab:blue", lw=1.2, label="target path")
        ax_t.plot([px[-1]], [py[-1]], "*", color="tab:blue", ms=12, label="target")
    if obstacles is not None:
        for k, (ox, oy, rad) in enumerate(np.asarray(obstacles).reshape(-1, 3)):
            ax_t.add_patch(_circle(ox, oy, rad, "tab:red", True, "obstacle" if k == 0 else None))
            ax_t.add_patch(_circle(ox, oy, rad + 2.0, "tab:red", False, None))
    for a, name in zip(arrays, names):
        ax_t.plot(a["position"][:, 0], a["position"][:, 1], lw=1.5, label=name)
        ax_a.plot(a["time"], np.degrees(a["heading_error"]), lw=1.2, label=name)
        ax_g.plot(a["time"], a["cross_track"], lw=1.2, label=name)
    ax_t.set_xlabel("x (m)")
    ax_t.set_ylabel("y (m)")
    ax_t.set_aspect("equal", adjustable="datalim")
    ax_t.legend(loc="best", fontsize=8)
    ax_t.grid(alpha=0.3)
    ax_a.set_ylabel("heading deviation a_c (deg)")
    ax_a.axhline(0.0, color="k", lw=0.6)
    ax_a.grid(alpha=0.3)
    ax_g.set_ylabel("distance from route g (m)")
    ax_g.set_xlabel("time (s)")
    ax_g.axhline(0.0, color="k", lw=0.6)
    ax_g.grid(alpha=0.3)
    if title:
        fig.suptitle(title)
    return fig


def _circle(x: float, y: float, r: float, color: str, fill: bool, label: str | None):
    from matplotlib.patches import Circle

    return Circle(
        (x, y), r, color=color, fill=fill, alpha=0.8 if fill else 0.4, lw=1.0, label=label
    )
