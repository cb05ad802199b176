"""The study's figures, numbered as the paper's (section 4.3, Figures 10-20).

Every function takes :class:`.results.StudyResults` and a folder, writes PNG files and returns
their names (a figure whose data is missing is skipped and not returned).

* Figure 10 a/b: episode return (moving average over ``stats.SMOOTH_WINDOW`` episodes) during
  training, mean across seeds with the 95 % confidence band.
* Figures 11 / 14: trajectories of seed 0 during training at the paper's episodes (those inside
  the budget), one row per agent, and (e) the PID and adaptive PID controllers on the same task.
* Figures 12, 13, 15, 16 (original task; path following without obstacles) and 17-19
  (generalization tasks): (a) trajectories, (b) heading deviation a_c (eq. 16) and (c) distance
  from the target route |g| over time, first evaluation episode of each final policy (seed 0) and
  of the adaptive PID controller.
* Figure 20: success rates on the three generalization tasks, pooled over seeds, with 95 %
  intervals that also cover the spread between seeds (:func:`.stats.success_interval`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from sb3_pnn.common.atomic import write_atomic
from sb3_pnn.reproduce.planning.plan import (  # noqa: E402
    AGENT_LABELS,
    AGENTS,
    BASELINES,
    PAPER_TRAJECTORY_EPISODES,
)
from sb3_pnn.reproduce.reporting.stats import curve_band, smooth, success_interval  # noqa: E402
from sb3_pnn.reproduce.running.results import StudyResults  # noqa: E402

COLORS = {
    "pnn": "tab:blue",
    "spnn": "tab:red",
    "sac_single": "tab:green",
    "sac_multi": "tab:orange",
    "pid": "tab:gray",
    "adaptive_pid": "black",
}
#: Line styles, so that a policy drawn under another stays visible (PNN and SPNN often share a
#: route).
STYLES = {
    "pnn": (0, (5, 2)),
    "spnn": "-",
    "sac_single": (0, (1, 1.5)),
    "sac_multi": (0, (3, 1, 1, 1)),
    "pid": "-",
    "adaptive_pid": "-",
}
PATH_TITLES = {"straight": "straight line", "sine": "sinusoidal curve"}
#: (figure number, path, evaluation label, title) of the evaluation figures.
EVAL_FIGURES = (
    (12, "straight", "original", "straight line path following with local path planning"),
    (13, "straight", "path_following", "straight line path following (no obstacles)"),
    (15, "sine", "original", "sinusoidal curve following with local path planning"),
    (16, "sine", "path_following", "sinusoidal curve following (no obstacles)"),
    (17, "straight", "uniform", "new task: straight line, uniformly distributed obstacles"),
    (18, "straight", "dense", "new task: straight line, dense obstacles"),
    (19, "sine", "dense", "new task: sinusoidal curve, dense obstacles"),
)
#: Figure 20 of the paper (success rate, %): straight uniform, straight dense, sine dense.
PAPER_SUCCESS: dict[str, tuple[float, float, float]] = {
    "spnn": (100, 98, 98),
    "pnn": (98, 92, 94),
    "sac_single": (88, 80, 80),
    "sac_multi": (90, 66, 80),
    "adaptive_pid": (96, 11, 31),
}
#: Figure 20's tasks: (path, evaluation label, x tick).
GENERALIZATION = (
    ("straight", "uniform", "straight, uniform"),
    ("straight", "dense", "straight, dense"),
    ("sine", "dense", "sine, dense"),
)


def _target_path(path: str) -> tuple[np.ndarray, np.ndarray]:
    from rov_envs.physics.guidance import (
        SINE_AMPLITUDE,
        SINE_PATH_LENGTH,
        SINE_WAVELENGTH,
        STRAIGHT_PATH_LENGTH,
    )

    if path == "straight":
        return np.array([0.0, STRAIGHT_PATH_LENGTH]), np.zeros(2)
    x = np.linspace(0.0, SINE_PATH_LENGTH, 400)
    return x, SINE_AMPLITUDE * np.sin(2 * math.pi * x / SINE_WAVELENGTH)


def _fixed_obstacles(path: str) -> list[tuple[float, float, float]]:
    from rov_envs.sim.tasks import PAPER_SINE_OBSTACLES, PAPER_STRAIGHT_OBSTACLES

    return list(PAPER_STRAIGHT_OBSTACLES if path == "straight" else PAPER_SINE_OBSTACLES)


def _draw_scene(ax: Any, path: str, obstacles: list[Any]) -> None:
    x, y = _target_path(path)
    ax.plot(x, y, "k--", lw=0.8, label="target route")
    for ox, oy, r in obstacles:
        ax.add_patch(plt.Circle((ox, oy), r, color="tab:brown", alpha=0.7))
        ax.add_patch(plt.Circle((ox, oy), r + 2.0, color="tab:brown", fill=False, lw=0.4, ls=":"))
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def _save(fig: Any, folder: Path, name: str) -> str:
    fig.tight_layout()
    write_atomic(folder / name, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)
    return name


def learning_curves(results: StudyResults, folder: Path) -> list[str]:
    """Figure 10 (a) straight, (b) sine."""
    paths = [p for p in ("straight", "sine") if results.select("transfer", path=p)]
    if not paths:
        return []
    fig, axes = plt.subplots(1, len(paths), figsize=(6.5 * len(paths), 4.2), squeeze=False)
    for ax, path, letter in zip(axes[0], paths, "ab"):
        for agent in AGENTS:
            runs = [r for r in results.select("transfer", agent, path) if r.episodes]
            if not runs:
                continue
            band = curve_band([smooth(r.episodes["returns"]) for r in runs])
            ep = np.arange(band.shape[1])
            ax.plot(
                ep,
                band[0],
                color=COLORS[agent],
                lw=1.8,
                label=f"{AGENT_LABELS[agent]} (n={len(runs)})",
            )
            ax.fill_between(ep, band[1], band[2], color=COLORS[agent], alpha=0.2)
        ax.set_title(f"({letter}) {PATH_TITLES[path]} with local path planning")
        ax.text(0.99, 0.02, "shaded: 95 % confidence interval of the mean over seeds",
                transform=ax.transAxes, ha="right", va="bottom", fontsize=7)  # fmt: skip
        ax.set_xlabel("episode")
        ax.set_ylabel("episode return (moving average)")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    return [_save(fig, folder, "fig10_learning_curves.png")]


def _eval_trace(result: Any, label: str) -> dict[str, Any] | None:
    ev = result.evals.get(label) if result is not None else None
    if not ev or not ev.get("trajectories"):
        return None
    return ev["trajectories"][0]


def training_trajectories(results: StudyResults, folder: Path) -> list[str]:
    """Figures 11 (straight) and 14 (sine)."""
    names = []
    for number, path in ((11, "straight"), (14, "sine")):
        agents = [a for a in AGENTS if results.select("transfer", a, path)]
        if not agents:
            continue
        first = results.select("transfer", agents[0], path)[0]
        episodes = list(first.spec.record_episodes)
        fig, axes = plt.subplots(
            len(agents) + 1, 1, figsize=(8, 2.6 * (len(agents) + 1)), squeeze=False
        )
        cmap = plt.get_cmap("viridis")
        for row, agent in enumerate(agents):
            ax = axes[row][0]
            run = results.select("transfer", agent, path)[0]
            _draw_scene(ax, path, _fixed_obstacles(path))
            trajs = run.trajectories()
            for k, ep in enumerate(episodes):
                if ep in trajs:
                    t = trajs[ep]
                    ok = run.episodes["successes"][ep] if run.episodes else False
                    ax.plot(t[:, 0], t[:, 1], color=cmap(k / max(1, len(episodes) - 1)), lw=1.2,
                            label=f"ep {ep}{' (success)' if ok else ''}")  # fmt: skip
            ax.set_title(f"({'abcd'[row]}) {AGENT_LABELS[agent]}, seed {run.spec.seed}")
            ax.legend(fontsize=7, ncol=3, loc="upper right")
        ax = axes[-1][0]
        _draw_scene(ax, path, _fixed_obstacles(path))
        for baseline in BASELINES:
            runs = results.select("baseline", baseline, path)
            trace = _eval_trace(runs[0] if runs else None, "original")
            if trace:
                ax.plot(trace["x"], trace["y"], color=COLORS[baseline], lw=1.2,
                        label=f"{AGENT_LABELS[baseline]} ({trace['end_reason']})")  # fmt: skip
        ax.set_title("(e) PID and adaptive PID controllers")
        ax.legend(fontsize=7)
        paper = ", ".join(str(e) for e in PAPER_TRAJECTORY_EPISODES[path])
        fig.suptitle(f"Training trajectories, {PATH_TITLES[path]} (paper's episodes: {paper})")
        names.append(_save(fig, folder, f"fig{number}_training_trajectories_{path}.png"))
    return names


def evaluation_traces(results: StudyResults, folder: Path) -> list[str]:
    """Figures 12, 13, 15-19: trajectories, heading deviation, distance from route."""
    names = []
    for number, path, label, title in EVAL_FIGURES:
        entries = []
        for agent in AGENTS:
            runs = results.select("transfer", agent, path)
            trace = _eval_trace(runs[0], label) if runs else None
            if trace:
                entries.append((agent, runs[0].spec.seed, trace))
        runs = results.select("baseline", "adaptive_pid", path)
        trace = _eval_trace(runs[0], label) if runs else None
        if trace:
            entries.append(("adaptive_pid", None, trace))
        if not entries:
            continue
        fig = plt.figure(figsize=(12, 7))
        ax_a = fig.add_subplot(2, 1, 1)
        ax_b = fig.add_subplot(2, 2, 3)
        ax_c = fig.add_subplot(2, 2, 4)
        _draw_scene(ax_a, path, entries[0][2].get("obstacles") or [])
        for agent, seed, tr in entries:
            tag = (
                AGENT_LABELS[agent]
                + ("" if seed is None else f" s{seed}")
                + f" ({tr['end_reason']})"
            )
            style = {"color": COLORS[agent], "ls": STYLES[agent]}
            ax_a.plot(tr["x"], tr["y"], lw=1.3, label=tag, **style)
            t = np.asarray(tr["t"], dtype=float)
            ax_b.plot(t, np.degrees(tr["heading_error"]), lw=1.0, **style)
            ax_c.plot(t, np.abs(tr["cross_track"]), lw=1.0, **style)
        ax_a.set_title(f"(a) trajectories: {title}")
        ax_a.legend(fontsize=7, ncol=3)
        ax_b.set_title("(b) heading deviation $a_c$")
        ax_b.set_xlabel("t (s)")
        ax_b.set_ylabel("deg")
        ax_c.set_title("(c) distance from the target route $|g|$")
        ax_c.set_xlabel("t (s)")
        ax_c.set_ylabel("m")
        for ax in (ax_b, ax_c):
            ax.grid(alpha=0.3)
        names.append(_save(fig, folder, f"fig{number}_{path}_{label}.png"))
    return names


def run_kind(agent: str) -> str:
    """The kind of run that holds ``agent``'s results: the PIDs are baselines, not trained."""
    return "baseline" if agent in BASELINES else "transfer"


def per_run_success(runs: list[Any], label: str) -> list[tuple[int, int]]:
    """(successes, episodes) of evaluation ``label``, one pair per run that has it."""
    out = []
    for r in runs:
        ev = r.evals.get(label)
        if ev:
            out.append((int(ev["successes"]), int(ev["n_episodes"])))
    return out


def success_bars(results: StudyResults, folder: Path) -> list[str]:
    """Figure 20 (intervals: :func:`.stats.success_interval`, which also covers seed spread)."""
    policies = [*AGENTS, "adaptive_pid"]
    width = 0.8 / len(policies)
    fig, ax = plt.subplots(figsize=(9, 4.5))
    any_data = False
    for j, agent in enumerate(policies):
        for i, (path, label, _) in enumerate(GENERALIZATION):
            pairs = per_run_success(results.select(run_kind(agent), agent, path), label)
            if not pairs:
                continue
            any_data = True
            rate, lo, hi = success_interval(pairs)
            x = i + (j - (len(policies) - 1) / 2) * width
            ax.bar(x, 100 * rate, width, color=COLORS[agent],
                   label=AGENT_LABELS[agent] if i == 0 else None)  # fmt: skip
            ax.errorbar(x, 100 * rate, yerr=[[100 * (rate - lo)], [100 * (hi - rate)]],
                        color="k", capsize=2, lw=0.8)  # fmt: skip
            paper = PAPER_SUCCESS.get(agent)
            if paper is not None:
                ax.plot(x, paper[i], marker="D", mfc="white", mec=COLORS[agent], ms=6, ls="none")
    if not any_data:
        plt.close(fig)
        return []
    ax.set_xticks(range(len(GENERALIZATION)), [g[2] for g in GENERALIZATION])
    ax.set_ylabel("success rate (%)")
    ax.set_ylim(0, 105)
    ax.set_title(
        "Figure 20: success on the new planning tasks\n(bars: ours, pooled over seeds; "
        "95 % intervals covering seed spread; diamonds: the paper)",
        fontsize=10,
    )
    handles, labels = ax.get_legend_handles_labels()
    handles.append(Line2D([], [], marker="D", mfc="white", mec="k", ms=6, ls="none"))
    labels.append("the paper (edge in the policy's colour)")
    ax.legend(handles, labels, fontsize=8, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.1))
    ax.grid(axis="y", alpha=0.3)
    return [_save(fig, folder, "fig20_success_rates.png")]


def make_figures(results: StudyResults, folder: Path) -> list[str]:
    """All figures; returns the file names written."""
    folder.mkdir(parents=True, exist_ok=True)
    names: list[str] = []
    for fn in (learning_curves, training_trajectories, evaluation_traces, success_bars):
        names += fn(results, folder)
    return names
