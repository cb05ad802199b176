"""The ablation's table (``report.md``): success under start noise, learning speed, cost per cell.

For every (cell, task) with finished runs the table gives

* success: evaluation successes pooled over the seeds, with a 95 % interval that also covers the
  spread between seeds (:func:`.stats.success_interval`: episodes of one seed are not independent
  of each other, so a Wilson interval of the pooled episodes alone would claim too much), and the
  per-seed rates;
* first success: the training episode of the first success, median over the seeds that had one,
  and how many seeds had one within the budget;
* time: mean training wall time per run (minutes), on the machine and ``--jobs`` given, and the
  mean CPU time per run (training and evaluation), which other load on the machine affects less.
"""

from __future__ import annotations

import statistics
from collections.abc import Sequence
from typing import Any

from sb3_pnn.reproduce.ablation.catalog import (
    TASK_LABELS,
    TASKS,
    AblationConfig,
    cell_of,
    reduced_column_id,
    run_id,
)
from sb3_pnn.reproduce.planning.setups import FACTOR_LABELS, OURS, PAPER, describe_value
from sb3_pnn.reproduce.reporting.stats import success_interval
from sb3_pnn.reproduce.running.results import StudyResults


def cell_task_summary(
    results: StudyResults, cell: str, task: str, seeds: int
) -> dict[str, Any] | None:
    """Pooled figures of one table entry, or None when no run of it has finished."""
    return runs_summary(results, [run_id(cell, task, s) for s in range(seeds)])


def runs_summary(results: StudyResults, run_ids: Sequence[str]) -> dict[str, Any] | None:
    """Pooled figures of the finished runs among ``run_ids``, or None when none has finished."""
    finished = [results.runs[rid] for rid in run_ids if rid in results.runs]
    if not finished:
        return None
    pairs: list[tuple[int, int]] = []
    firsts: list[int | None] = []
    minutes: list[float] = []
    cpu_minutes: list[float] = []
    for run in finished:
        own = run.evals["own"]
        pairs.append((int(own["successes"]), int(own["n_episodes"])))
        firsts.append(run.manifest.get("first_success"))
        minutes.append(float(run.manifest.get("train_s", 0.0)) / 60.0)
        cpu_minutes.append(float(run.manifest.get("cpu_s", 0.0)) / 60.0)
    reached = [f for f in firsts if f is not None]
    return {
        "runs": len(finished),
        "successes": sum(k for k, _ in pairs),
        "n": sum(n for _, n in pairs),
        "ci95": success_interval(pairs)[1:],
        "rates": [k / n for k, n in pairs],
        "first_median": statistics.median(reached) if reached else None,
        "first_reached": len(reached),
        "train_min": sum(minutes) / len(minutes),
        "cpu_min": sum(cpu_minutes) / len(cpu_minutes),
    }


def _entry(summary: dict[str, Any] | None, seeds: int) -> str:
    if summary is None:
        return "not run"
    lo, hi = summary["ci95"]
    rate = summary["successes"] / summary["n"]
    per_seed = ", ".join(f"{r * 100:.0f}" for r in summary["rates"])
    first = summary["first_median"]
    first_text = "none" if first is None else f"{first:.0f}"
    partial = "" if summary["runs"] == seeds else f" ({summary['runs']}/{seeds} runs)"
    return (
        f"{rate * 100:.0f} % [{lo * 100:.0f}, {hi * 100:.0f}] (seeds: {per_seed} %); "
        f"first {first_text} "
        f"({summary['first_reached']}/{summary['runs']}); {summary['train_min']:.1f} min "
        f"({summary['cpu_min']:.1f} CPU-min)"
        f"{partial}"
    )


def _setup_rows() -> list[str]:
    rows = ["| factor | paper | ours |", "|---|---|---|"]
    paper, ours = PAPER.to_dict(), OURS.to_dict()
    for name, label in FACTOR_LABELS.items():
        rows.append(
            f"| {label} | {describe_value(name, paper[name])} | "
            f"{describe_value(name, ours[name])} |"
        )
    return rows


def made_by(command: str, sessions: Sequence[dict]) -> list[str]:
    """How the folder was made: the one command, or each session's when they differ (an
    ablation grows over sessions with different ``--cells`` / ``--tasks``, or a session has a
    note). A session's ``note`` (written by a stopped invocation, or by hand into
    sessions.json) is quoted."""
    recorded = [s.get("command") for s in sessions]
    noted = any(s.get("note") for s in sessions)  # e.g. a session stopped by Ctrl-C
    if (not any(recorded) or set(recorded) == {command}) and not noted:
        return [f"Made by: `{command}`"]
    lines = ["Made by these invocations, in order (each resumes the folder and adds its runs):", ""]
    for number, (session, cmd) in enumerate(zip(sessions, recorded, strict=True), start=1):
        took = f"{float(session.get('wall_s', 0.0)) / 60:.0f} min"
        if session.get("note"):
            took += f"; {session['note']}"
        lines.append(f"{number}. `{cmd}` ({took})" if cmd else f"{number}. not recorded ({took})")
    return [*lines, "", f"This table: `{command}`"]


def _env_name(env_id: str) -> str:
    """``rov_envs/PlanningSine-v0`` -> ``PlanningSine``."""
    return env_id.split("/")[-1].rsplit("-v", 1)[0]


def _transfer_sources(tasks: Sequence[str]) -> str:
    """One sentence per planning task: which runs its SPNN learns from."""
    sentences = []
    for task in tasks:
        env_id, agent, prior_tasks = TASKS[task]
        if prior_tasks:
            sources = " and ".join(_env_name(TASKS[t][0]) for t in prior_tasks)
            sentences.append(
                f" {_env_name(env_id)} is learned by {agent.upper()} from the cell's own seed-0 "
                f"{sources} runs."
            )
    return "".join(sentences)


def render_report(
    results: StudyResults, config: AblationConfig, command: str, sessions: Sequence[dict]
) -> str:
    """The whole report.md text."""
    budget = config.budget
    tasks = [t for t in TASKS if t in config.tasks]
    lines = [
        "# Training set-up ablation",
        "",
        *made_by(command, sessions),
        "",
        f"Budget `{config.budget_name}`: training episodes "
        + ", ".join(f"{TASK_LABELS[t]} {budget.episodes[t]}" for t in tasks)
        + f"; {budget.eval_episodes} evaluation episodes per run on its own task with the "
        "evaluation library's start noise (1 m, 5 deg; evaluation seeds 10000+, apart from the "
        f"training seeds 0..{config.seeds - 1}).{_transfer_sources(tasks)}",
        "",
        "Each entry: evaluation success pooled over seeds [95 % interval: the hull of the "
        "pooled episodes' Wilson interval and the Student-t interval of the mean per-seed rate, "
        "since whole runs succeed or fail] (per-seed rates); training episode of the first "
        "success, median over the seeds that had one (seeds with one / runs); mean training "
        "wall time per run (mean CPU time per run, training and evaluation).",
        "",
        "## The two set-ups",
        "",
        *_setup_rows(),
        "",
        "## Results",
        "",
        "| cell | set-up | " + " | ".join(TASK_LABELS[t] for t in tasks) + " |",
        "|---|---|" + "---|" * len(tasks),
    ]
    for name in config.cells:
        cell = cell_of(name)
        entries = []
        for task in tasks:
            if TASKS[task][1] == "dsac" and cell.prior_share != 1.0:
                # only the seed-0 source columns of the planning runs are trained at this share
                column = runs_summary(results, [reduced_column_id(name, task)])
                entries.append(
                    "as ours"
                    if column is None
                    else f"seed-0 column at {cell.prior_share:g} of the budget: "
                    + _entry(column, 1)
                )
                continue
            entries.append(
                _entry(cell_task_summary(results, name, task, config.seeds), config.seeds)
            )
        lines.append(f"| `{name}` | {cell.describe()} | " + " | ".join(entries) + " |")
    wall = sum(float(s.get("wall_s", 0.0)) for s in sessions)
    jobs = sorted({int(s.get("jobs", 0)) for s in sessions})
    clock = (
        f"{wall / 60:.0f} min (--jobs {', '.join(map(str, jobs))})"
        if sessions
        else "not recorded (every invocation was interrupted; the per-run times above stand)"
    )
    lines += [
        "",
        f"Runs finished: {len(results.runs)}; not finished or not run: {len(results.missing)}; "
        f"failed: {len(results.failures)}. Wall clock of the invocations that ran them: {clock}.",
    ]
    return "\n".join(lines) + "\n"
