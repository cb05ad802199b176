"""A diagnostic: a study's SPNN policies with the gate's switch changed after training, on the
training task and the new layouts of Figure 20 (or among obstacles drawn afresh).

Eq. 15's hard gate hands control to the obstacle-avoidance column when the nearest obstacle is
within d_th. Changing d_th in a trained policy asks whether the new layouts fail because the
gate switches too late or too early. ``--hysteresis H`` gives the switch a memory instead
(:class:`sb3_pnn.progressive.switch_memory.SwitchMemory`): once the avoidance column has
control it keeps it until the nearest reading is beyond d_th + H (each episode starts
memoryless; a soft gate holds the avoidance column's weight until then). The 180-degree sonar
loses an obstacle when the vehicle turns its back to it, and
eq. 15's memoryless switch then hands control back to the path follower, which turns the
vehicle back toward the obstacle.

Each run is played as the study evaluated it, apart from what is asked: on each task with the
env keywords of the run's own evaluation (``eval.json``), through the switch memory and
NoReversal its spec names (``spnn_play_memory``, ``spnn_play_no_reversal``); ``--hysteresis``
replaces the spec's memory (0: none), NoReversal stays as the run was played. Episodes run on
the validation seeds (20000+, never the study's evaluation seeds 10000+), deterministic
actions; nothing is chosen here. ``--drawn-layouts`` replaces the new layouts by the training
task among obstacles drawn afresh by the ``scatter`` generator (the validation measure of
generalization of :mod:`.drawn_layouts`, whose figures the row at the run's own d_th repeats).
Prints, per task, d_th and H, the success rate over the seeds' episodes, per seed, the return,
the route kept and how the episodes ended.

Usage: python -m sb3_pnn.reproduce.tools.spnn_switch_distance STUDY --path straight
    [--d-th 12.5 8 16 20] [--hysteresis 0 10] [--drawn-layouts] [--episodes 30]
    [--seeds 0 1 2 3 4]
"""

from __future__ import annotations

import argparse
import json
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import torch as th

from sb3_pnn.common.callbacks import DRAWN_VALIDATION_LAYOUT, VALIDATION_SEED
from sb3_pnn.common.checks import is_finite_number
from sb3_pnn.evaluation import evaluate_policy_on_task
from sb3_pnn.evaluation.played import played_through
from sb3_pnn.reproduce.tools.replay import run_eval_task, run_model, run_play

#: The evaluations of ``eval.json`` that are not a planning layout (the path without obstacles).
NOT_A_LAYOUT = ("path_following",)


def _hysteresis(text: str) -> float:
    """A distance in metres, finite and >= 0 (argparse type of ``--hysteresis``)."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not is_finite_number(value) or value < 0:
        raise argparse.ArgumentTypeError(
            f"{text} is not allowed: expected a finite distance >= 0 (m)"
        )
    return value


def add_hysteresis_argument(
    parser: argparse.ArgumentParser, default: list[float] | None = None
) -> None:
    """``--hysteresis H [H ...]`` (m), one row per value; 0 is eq. 15's memoryless switch;
    ``default`` when not given (None: as each run was played)."""
    parser.add_argument(
        "--hysteresis",
        type=_hysteresis,
        nargs="+",
        default=default,
        metavar="H",
        help="once the avoidance column has control, keep it until the nearest obstacle is "
        "beyond d_th + H (m); 0: eq. 15's memoryless switch; several values: one row each "
        "(default: as the study played each run)",
    )


def run_tasks(
    parser: argparse.ArgumentParser, run: Path, drawn: bool
) -> list[tuple[str, str, dict[str, Any]]]:
    """(label, env id, env keywords) of the tasks to replay ``run`` on, each with the env
    keywords of the run's own evaluation: its planning task, then the new layouts it was
    evaluated on, or (``drawn``) its planning task among obstacles drawn afresh."""
    env_id, kwargs = run_eval_task(parser, run, "original")
    tasks = [("original", env_id, kwargs)]
    if drawn:
        return [*tasks, ("drawn", env_id, {**kwargs, "layout": DRAWN_VALIDATION_LAYOUT})]
    names = json.loads((run / "eval.json").read_text())
    for label in names:
        if label != "original" and label not in NOT_A_LAYOUT:
            tasks.append((label, *run_eval_task(parser, run, label)))
    return tasks


def play_with(model: Any, play: dict[str, Any], hysteresis: float | None) -> Any:
    """``model`` played as the run's spec ``play`` names, the switch memory replaced by
    ``hysteresis`` m (0: none) unless None; the memory's d_th is the gate's (as set)."""
    memory = play.get("switch_memory") if hysteresis is None else (hysteresis or None)
    return played_through(model, memory, bool(play.get("no_reversal")))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("study", type=Path)
    parser.add_argument("--path", choices=["straight", "sine"], default="straight")
    parser.add_argument("--d-th", type=float, nargs="+", default=[12.5, 8.0, 16.0, 20.0])
    add_hysteresis_argument(parser)
    parser.add_argument(
        "--drawn-layouts",
        action="store_true",
        help=f"the training task among obstacles drawn afresh ({DRAWN_VALIDATION_LAYOUT!r}) "
        "instead of the new layouts",
    )
    parser.add_argument("--episodes", type=int, default=30)
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    args = parser.parse_args(argv)
    if args.episodes < 1:
        parser.error(f"--episodes {args.episodes} is not allowed: expected an integer >= 1")
    if any(s < 0 for s in args.seeds):
        parser.error(f"--seeds {args.seeds} is not allowed: expected training seeds >= 0")
    for value in args.d_th:
        if not is_finite_number(value) or value < 0:
            parser.error(f"--d-th {value} is not allowed: expected finite distances >= 0 (m)")
    th.set_num_threads(1)
    hysteresis_values: list[float | None] = args.hysteresis or [None]
    rows: dict[tuple[str, float, str], dict[str, Any]] = {}
    for seed in args.seeds:
        run = args.study / "runs" / f"spnn-{args.path}-s{seed}"
        tasks = run_tasks(parser, run, args.drawn_layouts)
        model = run_model(parser, run)
        gate = getattr(getattr(getattr(model, "policy", None), "actor", None), "gate", None)
        if not hasattr(gate, "d_th"):
            parser.error(f"{run} is not an SPNN run with a distance gate")
        if gate.mode == "learned" and args.hysteresis:
            parser.error(
                f"{run} has a learned gate: --hysteresis needs a distance gate (eq. 15's "
                "hard switch or the soft gate)"
            )
        play = run_play(run)
        for d_th in args.d_th:
            gate.d_th = d_th  # the actor's gate decides the actions
            for hysteresis in hysteresis_values:
                policy = play_with(model, play, hysteresis)
                shown = "as played" if hysteresis is None else f"{hysteresis:g}"
                for label, env_id, env_kwargs in tasks:
                    result = evaluate_policy_on_task(
                        policy,
                        env_id,
                        n_episodes=args.episodes,
                        seed=VALIDATION_SEED,
                        env_kwargs=env_kwargs,
                    )
                    row = rows.setdefault(
                        (label, d_th, shown),
                        {"rates": [], "returns": [], "g": [], "ac": [], "ends": Counter()},
                    )
                    row["rates"].append(round(100 * result.success_rate))
                    row["returns"].append(result.mean_return)
                    row["g"].append(result.mean_abs_cross_track)
                    row["ac"].append(np.degrees(result.mean_abs_heading_error))
                    row["ends"].update(result.end_reasons)
    print(f"SPNN, {args.path} path, {args.episodes} validation episodes per seed and task")
    print(
        "| task | d_th (m) | hysteresis (m) | success | per seed | return | mean abs(g), "
        "abs(a_c) | episodes ended by |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for (label, d_th, hysteresis), row in rows.items():
        ended = ", ".join(f"{k} {v}" for k, v in row["ends"].most_common())
        print(
            f"| {label} | {d_th:g} | {hysteresis} | {np.mean(row['rates']):.0f} % | "
            f"{' '.join(map(str, row['rates']))} | {np.mean(row['returns']):.0f} | "
            f"{np.mean(row['g']):.2f} m, {np.mean(row['ac']):.1f} deg | {ended} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
