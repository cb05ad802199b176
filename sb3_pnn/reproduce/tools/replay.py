"""What the diagnostics that replay a study's policies share: the study / path / task arguments,
one run's model with the env it was evaluated in, and how episodes ended, as one table cell."""

from __future__ import annotations

import argparse
import json
from collections import Counter
from pathlib import Path
from typing import Any

import gymnasium as gym

import rov_envs  # noqa: F401  (registers the tasks)
from sb3_pnn import DiscreteSAC
from sb3_pnn.baselines import BASELINE_NAMES, make_baseline
from sb3_pnn.common.checks import float_in, positive_int


def task_parser(doc: str, episodes: int) -> argparse.ArgumentParser:
    """A parser described by ``doc``'s first line, with the study folder, ``--path``, ``--env``
    (the task to replay on) and ``--episodes`` (per seed; ``episodes`` by default)."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("study", type=Path)
    parser.add_argument("--path", choices=["straight", "sine"], default="straight")
    parser.add_argument("--env", default=None, help="task (default: the path's planning task)")
    parser.add_argument("--episodes", type=positive_int("--episodes"), default=episodes)
    return parser


def task_id(parser: argparse.ArgumentParser, args: argparse.Namespace) -> str:
    """``--env``, or the path's planning task; a task that is not registered stops the
    command with a message."""
    env_id = args.env or f"rov_envs/Planning{args.path.capitalize()}-v0"
    if env_id not in gym.registry:
        parser.error(f"--env {env_id!r} is not a registered task: expected an rov_envs/... id")
    return env_id


def run_folders(
    study: Path, agent: str, path: str, seeds: list[int] | None
) -> list[tuple[int, Path]]:
    """``(seed, folder)`` of a study's runs of ``agent`` on planning path ``path``: one per
    training seed (``seeds`` None: every such run the study holds, in seed order), or the one
    run of a PID baseline (no training seed; listed as seed 0)."""
    if agent in BASELINE_NAMES:
        return [(0, study / "runs" / f"{agent}-{path}")]
    if seeds is None:
        prefix = f"{agent}-{path}-s"
        names = (p.name for p in (study / "runs").glob(f"{prefix}*"))
        seeds = sorted(int(n[len(prefix) :]) for n in names if n[len(prefix) :].isdigit())
    return [(seed, study / "runs" / f"{agent}-{path}-s{seed}") for seed in seeds]


def run_eval_task(
    parser: argparse.ArgumentParser, run: Path, task: str = "original"
) -> tuple[str, dict[str, Any]]:
    """``(env_id, env keywords)`` of the run's evaluation on ``task`` (a learner's or
    baseline's ``"original"`` planning task or ``"path_following"``, a source column's
    ``"own"``); a run without it stops the command."""
    eval_file = run / "eval.json"
    if not eval_file.is_file():
        parser.error(f"{eval_file} does not exist: expected a finished run of a study")
    tasks = json.loads(eval_file.read_text())
    if task not in tasks:
        parser.error(f"{eval_file} has no {task!r} evaluation: expected one of {sorted(tasks)}")
    return str(tasks[task].get("env_id", "")), dict(tasks[task]["env_kwargs"])


def run_env_kwargs(
    parser: argparse.ArgumentParser, run: Path, task: str = "original"
) -> dict[str, Any]:
    """The env keywords of the run's evaluation on ``task`` (see :func:`run_eval_task`)."""
    return run_eval_task(parser, run, task)[1]


def run_model(
    parser: argparse.ArgumentParser, run: Path, kept_by: str | None = None
) -> DiscreteSAC | None:
    """The run's kept model (with ``kept_by``, the policy that ranking kept of the same training:
    ``model_by_<ranking>.zip``, saved by runs with ``keep_best_also``), None for a PID
    baseline's run (its manifest names the baseline); a missing model stops the command with a
    message."""
    from sb3_pnn.reproduce.running.work import kept_model_name

    manifest = run / "manifest.json"
    baseline = json.loads(manifest.read_text()).get("agent") if manifest.exists() else None
    if baseline in BASELINE_NAMES:
        return None
    path = run / kept_model_name(kept_by)
    if not path.exists():
        hint = (
            "expected a study's run folder"
            if kept_by is None
            else f"expected a run trained with --set keep_best_also={kept_by}"
        )
        parser.error(f"{path} does not exist: {hint}")
    return DiscreteSAC.load(path, device="cpu")


def add_kept_by_option(parser: argparse.ArgumentParser) -> None:
    """``--kept-by RANKING``: replay the study's learners' policies kept by that further ranking
    (``keep_best_also``) instead of those the study kept (a second study compared against
    stays as kept)."""
    from sb3_pnn.common.callbacks import RANKINGS

    parser.add_argument(
        "--kept-by",
        choices=list(RANKINGS),
        default=None,
        help="replay the policies this ranking kept (runs trained with --set keep_best_also)",
    )


def run_play(run: Path) -> dict[str, Any]:
    """The ``play`` of the run's spec (its manifest): how the study evaluated the trained model
    (``switch_memory`` m, ``no_reversal``); empty for a folder without a manifest or a run made
    before ``play`` existed (played as trained)."""
    manifest = run / "manifest.json"
    spec = json.loads(manifest.read_text()).get("spec") or {} if manifest.is_file() else {}
    return dict(spec.get("play") or {})


def run_played(
    parser: argparse.ArgumentParser, run: Path, model: Any, no_reversal: bool | None = None
) -> Any:
    """The run's kept ``model`` played as the study evaluated it (its spec's ``play``: SPNN
    through a switch memory and / or without immediate turn reversals where named,
    :func:`sb3_pnn.reproduce.running.work.played`); ``no_reversal`` True / False replays it
    with / without :class:`sb3_pnn.evaluation.NoReversal` whatever the spec named. A run folder
    without a manifest plays as trained."""
    from sb3_pnn.reproduce.running.work import played

    play = run_play(run)
    if no_reversal is not None:
        play["no_reversal"] = no_reversal
    return played(play, model)


def add_no_reversal_option(parser: argparse.ArgumentParser) -> None:
    """``--no-reversal on|off``: replay every run with or without NoReversal (default: as the
    study played it), on both sides of a comparison."""
    parser.add_argument(
        "--no-reversal",
        choices=["on", "off"],
        default=None,
        help="replay the runs with (on) or without (off) sb3_pnn.evaluation.NoReversal "
        "(default: as the study played each run; the study's spnn_play_no_reversal)",
    )


def no_reversal_of(args: argparse.Namespace) -> bool | None:
    """``--no-reversal``'s value as :func:`run_played` takes it."""
    return None if args.no_reversal is None else args.no_reversal == "on"


def _gate_value(text: str) -> float | str:
    """``--arrival-gate``'s value: metres in [2, 100], or ``"none"`` (no gate)."""
    if text == "none":
        return text
    return float_in("--arrival-gate", 2.0, 100.0, "m from the target point, or none")(text)


def add_arrival_gate_option(parser: argparse.ArgumentParser) -> None:
    """``--arrival-gate M|none``: replay every run with rov_envs' ``arrival_gate`` M (the end of
    the path counts as arrival only within M m of the target) or without one, on both sides of
    a comparison."""
    parser.add_argument(
        "--arrival-gate",
        type=_gate_value,
        default=None,
        metavar="M",
        help="replay with the end of the path counted as arrival only within M m (2-100) of the "
        "target point, a miss failing; none: without a gate (default: as each run was "
        "evaluated)",
    )


def gated(env_kwargs: dict[str, Any], gate: float | str | None) -> dict[str, Any]:
    """``env_kwargs`` with ``arrival_gate`` set to ``gate``, removed for ``"none"`` (None:
    unchanged)."""
    out = dict(env_kwargs)
    if gate == "none":
        out.pop("arrival_gate", None)
    elif gate is not None:
        out["arrival_gate"] = float(gate)
    return out


def run_baseline(run: Path, env: gym.Env) -> Any:
    """The PID baseline a baseline's run evaluated (its manifest names it), bound to ``env``."""
    return make_baseline(json.loads((run / "manifest.json").read_text())["agent"], env)


def run_policy(parser: argparse.ArgumentParser, run: Path, env: gym.Env) -> Any:
    """The run's policy: its kept model, or the PID baseline the run evaluated, bound to
    ``env``; a missing model stops the command with a message."""
    model = run_model(parser, run)
    return run_baseline(run, env) if model is None else model


def load_run(parser: argparse.ArgumentParser, run: Path, env_id: str) -> tuple[Any, gym.Env]:
    """The run's policy (its model, or the PID baseline the run evaluated) and ``env_id`` made
    with the env keywords of the run's evaluation; a missing run stops the command with a
    message (the model's first)."""
    model = run_model(parser, run)
    env = gym.make(env_id, **run_env_kwargs(parser, run))
    return (run_baseline(run, env) if model is None else model), env


def ended(ends: Counter) -> str:
    """How episodes ended, most frequent first: "success 19, off_path 1"."""
    return ", ".join(f"{k} {v}" for k, v in ends.most_common())
