"""``python -m sb3_pnn.reproduce``: run the study of section 4.3 and write figures and report.md.

Usage::

    python -m sb3_pnn.reproduce [--quick] [--seeds N] [--jobs J] [--out DIR] [--episodes E]
                                [--eval-episodes N] [--agents A,B] [--shared-priors]
                                [--no-progress]
                                [--setup {ours,paper}] [--set FACTOR=VALUE ...]
    python -m sb3_pnn.reproduce --ablation ...   (see :mod:`.ablation_cli`)

The study (see :mod:`.plan`) trains the source columns, then SAC-Single, SAC-Multi, PNN and SPNN
on both planning tasks for ``--seeds`` seeds, evaluates them and both PID controllers, and writes
``DIR/report.md`` and ``DIR/figures/``. Interrupt it at any time: the next call with the same
arguments and ``--out`` resumes, skipping finished runs (:mod:`.store`). Bad arguments exit with
status 2 and a one-line message.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sb3_pnn.common.checks import positive_int
from sb3_pnn.reproduce.planning.plan import AGENTS, BUDGETS, StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import SETUPS, parse_setup_changes
from sb3_pnn.reproduce.running.executor import add_executor_arguments, pool_from_arguments
from sb3_pnn.reproduce.running.store import (
    RunStore,
    StudyConflictError,
    open_store_or_exit,
    write_json_atomic,
)

DEFAULT_OUT = "results/study"
#: Training seeds per budget when --seeds is not given.
DEFAULT_SEEDS = {"full": 5, "quick": 2, "tiny": 2}
SESSIONS = "sessions.json"


def _budget_text(name: str, seeds: int) -> str:
    """A budget of :mod:`.plan` in words (the help text quotes the plan, never a copy of it)."""
    budget = BUDGETS[name]
    priors = " / ".join(f"{n} {k}" for k, n in budget.prior_episodes.items())
    agents = " / ".join(f"{n} {path}" for path, n in budget.transfer_episodes.items())
    return f"priors {priors}, agents {agents}, evaluation {budget.eval_episodes}, {seeds} seed(s)"


def make_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m sb3_pnn.reproduce",
        description="Reproduce Pan et al. (2025) section 4.3: train PNN, SPNN, SAC-Single and "
        "SAC-Multi on the BlueROV2 planning tasks, evaluate them and the PID baselines, and "
        "write figures 10-20 and report.md.",
        epilog="Budgets (training episodes per run, evaluation episodes per policy and task): "
        f"full = {_budget_text('full', DEFAULT_SEEDS['full'])}; --quick = "
        f"{_budget_text('quick', DEFAULT_SEEDS['quick'])}. Measured wall times: "
        "docs/benchmarks.md; report.md gives this study's own. A killed study resumes when rerun "
        "with the same arguments; a changed budget needs another --out.",
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="smoke test: checks that the study runs end to end; its report gives no verdicts",
    )
    parser.add_argument(
        "--seeds",
        type=positive_int("--seeds"),
        default=None,
        help=f"training seeds per agent and task (default {DEFAULT_SEEDS['full']}; "
        f"{DEFAULT_SEEDS['quick']} with --quick)",
    )
    add_executor_arguments(parser)
    parser.add_argument(
        "--out", default=None, help=f"output folder (default {DEFAULT_OUT}, or results/quick)"
    )
    parser.add_argument(
        "--episodes",
        type=positive_int("--episodes"),
        default=None,
        help="training episodes of every agent on the planning tasks",
    )
    parser.add_argument(
        "--eval-episodes",
        type=positive_int("--eval-episodes"),
        default=None,
        help="evaluation episodes per policy and task",
    )
    parser.add_argument(
        "--agents",
        default=",".join(AGENTS),
        help=f"comma list of the learners to train (default all: {','.join(AGENTS)}); the "
        "source columns they need and both PID baselines always run",
    )
    priors = parser.add_mutually_exclusive_group()
    priors.add_argument(
        "--prior-per-seed",
        dest="prior_per_seed",
        action="store_true",
        default=True,
        help="train one set of source columns per seed, so the intervals cover their draw "
        "(default)",
    )
    priors.add_argument(
        "--shared-priors",
        dest="prior_per_seed",
        action="store_false",
        help="train one set of source columns (seed 0) and give it to every seed",
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument(
        "--report-only",
        action="store_true",
        help="only redraw the figures and report.md from the runs finished in --out",
    )
    parser.add_argument(
        "--setup",
        choices=sorted(SETUPS),
        default="ours",
        help="training set-up: 'ours' (default; each departure from the paper measured in "
        "docs/ablation/report.md) or 'paper' (the paper read literally); see "
        "sb3_pnn/reproduce/planning/setups.py",
    )
    parser.add_argument(
        "--set",
        nargs="+",
        default=[],
        metavar="FACTOR=VALUE",
        help="change factors of the set-up, e.g. --set updates=step:4 keep_best=false "
        "(factors: sb3_pnn/reproduce/planning/setups.py; report.md lists the set-up used)",
    )
    parser.add_argument(
        "--ablation",
        action="store_true",
        help="run the set-up ablation instead (options: python -m sb3_pnn.reproduce --ablation "
        "--help)",
    )
    parser.add_argument("--tiny", action="store_true", help=argparse.SUPPRESS)  # tests only
    return parser


def config_from_args(args: argparse.Namespace) -> StudyConfig:
    """The study asked for; ValueError (naming the bad value) for a bad ``--set``."""
    budget = "tiny" if args.tiny else ("quick" if args.quick else "full")
    seeds = args.seeds if args.seeds is not None else DEFAULT_SEEDS[budget]
    return StudyConfig(
        budget_name=budget,
        seeds=seeds,
        episodes=args.episodes,
        eval_episodes=args.eval_episodes,
        prior_per_seed=args.prior_per_seed,
        agents=tuple(a.strip() for a in args.agents.split(",") if a.strip()),
        setup_name=args.setup,
        setup_changes=tuple(parse_setup_changes(args.set).items()),
    )


def parse_study_args(
    argv: Sequence[str],
) -> tuple[argparse.ArgumentParser, argparse.Namespace, StudyConfig]:
    """Parser, parsed arguments and the study they ask for; a bad ``--set`` exits through
    ``parser.error`` (status 2)."""
    parser = make_parser()
    args = parser.parse_args(argv)
    try:
        config = config_from_args(args)
    except ValueError as error:
        parser.error(str(error))
    return parser, args, config


def out_folder(args: argparse.Namespace) -> Path:
    """The study folder: ``--out``, else the default for the budget."""
    return Path(args.out or ("results/quick" if args.quick else DEFAULT_OUT))


def _load_sessions(out: Path) -> list[dict[str, Any]]:
    import json

    path = out / SESSIONS
    return json.loads(path.read_text()) if path.is_file() else []


def finish(out: Path, config: StudyConfig, plan: list[Any], store: RunStore, jobs: int) -> Path:
    """Figures and report.md from whatever has finished in ``out``."""
    from sb3_pnn.reproduce.reporting.figures import make_figures
    from sb3_pnn.reproduce.reporting.report import write_report
    from sb3_pnn.reproduce.running.results import load_results

    results = load_results(plan, store)
    figures = make_figures(results, out / "figures")
    report = out / "report.md"
    write_report(results, config, figures, _load_sessions(out), report, jobs)
    return report


def main(argv: Sequence[str] | None = None, work: Any = None) -> int:
    """Entry point; ``work`` replaces the real run function (tests only)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if "--ablation" in argv:
        from sb3_pnn.reproduce.ablation.cli import main as ablation_main

        return ablation_main([a for a in argv if a != "--ablation"], work=work)
    parser, args, config = parse_study_args(argv)
    out = out_folder(args)
    store = open_store_or_exit(parser, out)
    try:
        from sb3_pnn.reproduce.running.executor import execute

        if work is None:
            from sb3_pnn.reproduce.running.work import run_work as work
        plan = build_plan(config)
        pool, jobs = None, args.jobs or os.cpu_count() or 1
        if not args.report_only:
            try:
                pool, jobs = pool_from_arguments(args, store, work)
            except RuntimeError as error:  # Ray missing, unreachable or without a free CPU
                print(f"{parser.prog}: error: {error}", file=sys.stderr)
                return 2
        print(
            f"study: {len(plan)} runs ({config.budget_name} budget, {config.seeds} seed(s), "
            f"--jobs {jobs}, {args.executor} executor) in {os.fspath(out)}",
            flush=True,
        )
        if args.report_only:
            if not any(store.is_done(spec) for spec in plan):
                print(
                    f"error: --report-only: {os.fspath(out)} holds no finished run of this study "
                    "(same --seeds, --set and budget as when it ran?)",
                    file=sys.stderr,
                )
                return 2
            report = finish(out, config, plan, store, jobs)
            print(f"report: {os.fspath(report.resolve())}", flush=True)
            return 0
        started = time.time()
        try:
            summary = execute(plan, store, work, jobs, quiet=args.no_progress, pool=pool)
        except StudyConflictError as error:
            print(f"error: {error}", file=sys.stderr)
            return 2
        sessions = _load_sessions(out)
        sessions.append(summary.session_record(started, jobs, args.executor))
        write_json_atomic(out / SESSIONS, sessions)
        if summary.stopped:
            print(
                summary.stopped_message(),
                file=sys.stderr,
                flush=True,
            )
            return 130
        print(
            f"runs: {len(summary.done)} done now, "
            f"{len(summary.skipped_finished)} finished earlier, "
            f"{len(summary.failed)} failed, {len(summary.blocked)} blocked by a failed prior "
            f"({summary.wall_s / 60:.1f} min)",
            flush=True,
        )
        drawing = time.time()
        report = finish(out, config, plan, store, jobs)
        print(
            f"figures and report drawn in {time.time() - drawing:.0f} s; "
            f"total {(time.time() - started) / 60:.1f} min",
            flush=True,
        )
    finally:
        store.close()
    print(f"report: {os.fspath(report.resolve())}", flush=True)
    print(f"figures: {os.fspath((out / 'figures').resolve())}", flush=True)
    return 1 if summary.failed or summary.blocked else 0
