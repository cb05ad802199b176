"""How closely and how fast a study's kept policies keep their route, on fresh validation seeds.

For each run this evaluates the kept policy on its own planning task and on the path without
obstacles (the run's ``"original"`` and ``"path_following"`` evaluation tasks, with their env
keywords) on seeds 40000+, apart from the checks' seeds (20000+ and 30000+) and the study's
evaluation seeds (10000+): a route measure that nothing was chosen on. It prints per run the
success, mean abs(g), mean abs(a_c) and mean time to the target of both tasks, and their means
over the runs. ``--against BASE`` prints a second study's runs of the same seeds beside them and
the relative change of the mean abs(g) (the route rules of docs/ablation sections 22-32).
``--no-reversal on|off`` replays every run with or without :class:`sb3_pnn.evaluation.NoReversal`
(default: as the study played it). ``--arrival-gate M`` replays with the 5 m (or M m) arrival gate;
``--return-by NAME`` / ``--return-column STUDY`` let a PID baseline or a path-following column
steer in open water off the path (:mod:`sb3_pnn.reproduce.tools.return_controller`).
``--kept-by RANKING`` replays the policies that ranking kept of the same training (runs trained
with ``--set keep_best_also=RANKING``); BASE's stay as kept.
``--agent pf_column`` measures the path's path-following source column instead, on its own
task (the column's ``"own"`` evaluation task: the path without obstacles) on the same seeds.

Usage: python -m sb3_pnn.reproduce.tools.fresh_route STUDY --agent spnn --path straight
    [--seeds 0 1 2] [--episodes 50] [--against BASE_STUDY] [--no-reversal on|off]
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
import torch as th

from sb3_pnn.baselines import BASELINE_NAMES
from sb3_pnn.common.checks import positive_int
from sb3_pnn.evaluation import evaluate_policy_on_task
from sb3_pnn.reproduce.tools.replay import (
    add_arrival_gate_option,
    add_kept_by_option,
    add_no_reversal_option,
    gated,
    no_reversal_of,
    run_eval_task,
    run_folders,
    run_model,
    run_played,
)
from sb3_pnn.reproduce.tools.return_controller import add_return_options, returned

#: First seed of the fresh validation episodes.
FRESH_SEED = 40_000
#: The run's evaluation tasks that are replayed: its own planning task, the path alone.
TASKS = ("original", "path_following")
#: ``--agent`` value for the path's path-following source column (its runs ``prior-pf_PATH-sN``),
#: replayed on its own evaluation task alone.
PF_COLUMN = "pf_column"
COLUMN_TASKS = ("own",)
#: The table's heading of each replayed task.
TASK_HEADERS = {"original": "own task", "path_following": "no obstacles", "own": "own task"}


def tasks_of(agent: str) -> tuple[str, ...]:
    """The evaluation tasks replayed for ``--agent agent``."""
    return COLUMN_TASKS if agent == PF_COLUMN else TASKS


def folders(study: Path, agent: str, path: str, seeds: list[int] | None) -> list[tuple[int, Path]]:
    """``(seed, folder)`` of the study's runs of ``agent`` on ``path`` (:func:`run_folders`;
    for :data:`PF_COLUMN`, the path's path-following columns)."""
    if agent == PF_COLUMN:
        return run_folders(study, "prior", f"pf_{path}", seeds)
    return run_folders(study, agent, path, seeds)


def add_run_arguments(parser: argparse.ArgumentParser) -> None:
    """The study folder, ``--agent`` (a learner, a PID baseline or :data:`PF_COLUMN`),
    ``--path`` and ``--seeds`` (default: every seed the study holds)."""
    parser.add_argument("study", type=Path)
    parser.add_argument(
        "--agent",
        default="spnn",
        help=f"a learner, a PID baseline or {PF_COLUMN} (the path's path-following column)",
    )
    parser.add_argument("--path", choices=["straight", "sine"], default="straight")
    parser.add_argument("--seeds", type=int, nargs="*", default=None)


def chosen_runs(
    parser: argparse.ArgumentParser, args: argparse.Namespace
) -> list[tuple[int, Path]]:
    """:func:`folders` of the arguments of :func:`add_run_arguments`; a study without such a
    run stops the command with a usage error."""
    runs = folders(args.study, args.agent, args.path, args.seeds)
    if not runs or not runs[0][1].is_dir():
        parser.error(
            f"{args.study / 'runs'} holds no run of --agent {args.agent!r} on the {args.path} "
            f"path: expected a study folder and a learner, {PF_COLUMN} or one of "
            f"{list(BASELINE_NAMES)}"
        )
    return runs


def route(
    parser: argparse.ArgumentParser,
    run: Path,
    episodes: int,
    tasks: tuple[str, ...] = TASKS,
    no_reversal: bool | None = None,
    arrival_gate: float | None = None,
    return_to: tuple[argparse.ArgumentParser, argparse.Namespace] | None = None,
    kept_by: str | None = None,
) -> dict[str, dict]:
    """Per task of ``tasks``: success, mean abs(g) (m), mean abs(a_c) (deg), mean time to the
    target (s; None without a success) of the run's kept policy on seeds 40000+, played as the
    study evaluated it (a switch memory where its spec names one; ``no_reversal`` as
    :func:`sb3_pnn.reproduce.tools.replay.run_played`; ``arrival_gate`` as
    :func:`sb3_pnn.reproduce.tools.replay.gated`; ``return_to`` (the parser and its arguments)
    through :func:`sb3_pnn.reproduce.tools.return_controller.returned`; ``kept_by``: the policy
    that further ranking kept, :func:`sb3_pnn.reproduce.tools.replay.run_model`)."""
    evaluated = {task: run_eval_task(parser, run, task) for task in tasks}
    model = run_model(parser, run, kept_by)
    agent = json.loads((run / "manifest.json").read_text())["agent"]
    policy = agent if model is None else run_played(parser, run, model, no_reversal)
    out = {}
    for task, (env_id, env_kwargs) in evaluated.items():
        env_kwargs = gated(env_kwargs, arrival_gate)
        played = (
            policy if return_to is None else returned(*return_to, policy, env_id, env_kwargs, run)
        )
        result = evaluate_policy_on_task(
            played, env_id, n_episodes=episodes, seed=FRESH_SEED, env_kwargs=env_kwargs
        )
        out[task] = {
            "success": result.success_rate,
            "g": result.mean_abs_cross_track,
            "ac": math.degrees(result.mean_abs_heading_error),
            "time": result.mean_time_to_target,
        }
    return out


def cells(measure: dict[str, dict]) -> list[str]:
    """Table cells of one run's :func:`route`: per task "success, |g|, |a_c|, time"."""
    return [
        f"{100 * m['success']:.0f} %, {m['g']:.2f} m, {m['ac']:.1f} deg, "
        + ("-" if m["time"] is None else f"{m['time']:.0f} s")
        for m in measure.values()
    ]


def means(measures: list[dict[str, dict]]) -> dict[str, dict]:
    """The mean over runs of every figure of :func:`route` (times over the runs that have one)."""
    out = {}
    for task in measures[0]:
        rows = [m[task] for m in measures]
        times = [r["time"] for r in rows if r["time"] is not None]
        out[task] = {key: float(np.mean([r[key] for r in rows])) for key in ("success", "g", "ac")}
        out[task]["time"] = float(np.mean(times)) if times else None
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_run_arguments(parser)
    parser.add_argument("--episodes", type=positive_int("--episodes"), default=50)
    parser.add_argument("--against", type=Path, default=None, help="a second study to compare")
    add_no_reversal_option(parser)
    add_arrival_gate_option(parser)
    add_return_options(parser)
    add_kept_by_option(parser)
    args = parser.parse_args(argv)
    th.set_num_threads(1)
    runs = chosen_runs(parser, args)
    tasks = tasks_of(args.agent)
    studies = [args.study] if args.against is None else [args.against, args.study]
    kept = f" (kept by {args.kept_by})" if args.kept_by else ""
    labels = [f"{study}{kept if i == len(studies) - 1 else ''}" for i, study in enumerate(studies)]
    header = ["seed"]
    for label in labels:
        header += [f"{label}: {TASK_HEADERS[task]}" for task in tasks]
    print("| " + " | ".join(header) + " |\n|" + "---|" * len(header))
    measured: list[list[dict]] = [[] for _ in studies]
    for seed, _ in runs:
        row = [str(seed)]
        for i, study in enumerate(studies):
            run = folders(study, args.agent, args.path, [seed])[0][1]
            measured[i].append(
                route(
                    parser,
                    run,
                    args.episodes,
                    tasks,
                    no_reversal_of(args),
                    args.arrival_gate,
                    (parser, args),
                    args.kept_by if i == len(studies) - 1 else None,  # the study, not BASE
                )
            )
            row += cells(measured[i][-1])
        print("| " + " | ".join(row) + " |")
    summary = [means(m) for m in measured]
    for label, mean in zip(labels, summary, strict=True):
        print(f"mean over {len(runs)} run(s), {label}: " + "; ".join(cells(mean)))
    if args.against is not None:
        base, arm = summary
        print(
            "mean abs(g) change: "
            + ", ".join(
                f"{task} {100 * (arm[task]['g'] / base[task]['g'] - 1):+.1f} %" for task in tasks
            )
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
