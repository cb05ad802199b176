"""``python -m sb3_pnn.reproduce --ablation``: train the ablation's cells, write its report.md.

Usage::

    python -m sb3_pnn.reproduce --ablation [--quick] [--seeds N] [--jobs J] [--out DIR]
                                           [--cells A,B,...] [--tasks T,...] [--list]

Cells and tasks are those of :mod:`.ablation`; ``--list`` prints them. Like the study, it resumes
when rerun with the same arguments and ``--out`` (finished runs are kept), so a long ablation
can be made in several sessions, and ``--cells`` / ``--tasks`` add to an existing folder.
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sb3_pnn.common.checks import positive_int
from sb3_pnn.reproduce.ablation.catalog import (
    BUDGETS,
    CELLS,
    DEFAULT_TASKS,
    TASKS,
    AblationConfig,
    build_ablation_plan,
    cell_of,
)
from sb3_pnn.reproduce.running.executor import add_executor_arguments
from sb3_pnn.reproduce.running.store import (
    StudyConflictError,
    open_store_or_exit,
    write_json_atomic,
)

DEFAULT_OUT = "results/ablation"
SESSIONS = "sessions.json"


def _names(kind: str, known: Sequence[str]) -> Any:
    def parse(text: str) -> tuple[str, ...]:
        names = tuple(n.strip() for n in text.split(",") if n.strip())
        for name in names:
            if kind == "cell":
                try:
                    cell_of(name)
                except ValueError as error:
                    raise argparse.ArgumentTypeError(str(error)) from None
            elif name not in known:
                raise argparse.ArgumentTypeError(
                    f"{kind} {name!r} is unknown; expected some of {', '.join(known)}"
                )
        if not names:
            raise argparse.ArgumentTypeError(
                f"no {kind} given; expected some of {', '.join(known)}"
            )
        return names

    return parse


def make_parser() -> argparse.ArgumentParser:
    full = BUDGETS["full"]
    parser = argparse.ArgumentParser(
        prog="python -m sb3_pnn.reproduce --ablation",
        description="Train each set-up cell of the ablation (the paper's set-up, one factor "
        "changed at a time, the study's set-up, one factor put back at a time) on the source "
        "tasks and PlanningStraight (PlanningSine when asked for), and tabulate success, first "
        "success and cost.",
        epilog="Full budget: "
        + ", ".join(f"{t} {n}" for t, n in full.episodes.items())
        + f" training episodes, {full.eval_episodes} evaluation episodes per run.",
    )
    parser.add_argument("--quick", action="store_true", help="smoke test: small budgets")
    parser.add_argument(
        "--seeds", type=positive_int("--seeds"), default=3, help="seeds per cell (default 3)"
    )
    add_executor_arguments(parser)
    parser.add_argument("--out", default=DEFAULT_OUT, help=f"folder (default {DEFAULT_OUT})")
    parser.add_argument(
        "--cells",
        type=_names("cell", list(CELLS)),
        default=tuple(CELLS),
        help="comma list: catalog cells (--list) or composites such as "
        "ours+updates=step:4+prior_updates=step:1+motion_obs=off",
    )
    parser.add_argument(
        "--tasks",
        type=_names("task", list(TASKS)),
        default=DEFAULT_TASKS,
        help=f"comma list of {', '.join(TASKS)} (default {','.join(DEFAULT_TASKS)})",
    )
    parser.add_argument("--list", action="store_true", help="print the cells and tasks, then stop")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument(
        "--report-only", action="store_true", help="only rewrite report.md from finished runs"
    )
    parser.add_argument("--tiny", action="store_true", help=argparse.SUPPRESS)  # tests only
    return parser


def main(argv: Sequence[str], work: Any = None) -> int:
    """Entry point (``argv`` without ``--ablation``); ``work`` replaces the real run (tests)."""
    from sb3_pnn.common.atomic import write_text_atomic
    from sb3_pnn.reproduce.ablation.report import render_report
    from sb3_pnn.reproduce.running.executor import execute, pool_from_arguments
    from sb3_pnn.reproduce.running.results import load_results

    parser = make_parser()
    args = parser.parse_args(argv)
    if args.list:
        for name, cell in CELLS.items():
            print(f"{name}: {cell.describe()}")
        print("tasks: " + ", ".join(TASKS))
        return 0
    budget = "tiny" if args.tiny else ("quick" if args.quick else "full")
    config = AblationConfig(budget, args.seeds, args.cells, args.tasks)
    out = Path(args.out)
    store = open_store_or_exit(parser, out)
    try:
        plan = build_ablation_plan(config)
        print(f"ablation: {len(plan)} runs ({budget} budget) in {os.fspath(out)}", flush=True)
        sessions_path = out / SESSIONS
        sessions = json.loads(sessions_path.read_text()) if sessions_path.is_file() else []
        shown = [a for a in argv if a != "--report-only"]
        command = ("python -m sb3_pnn.reproduce --ablation " + shlex.join(shown)).strip()
        failed = 0
        if not args.report_only:
            if work is None:
                from sb3_pnn.reproduce.running.work import run_work as work
            try:
                pool, jobs = pool_from_arguments(args, store, work)
            except RuntimeError as error:  # Ray missing, unreachable or without a free CPU
                parser.exit(2, f"{parser.prog}: error: {error}\n")
            started = time.time()
            try:
                summary = execute(plan, store, work, jobs, quiet=args.no_progress, pool=pool)
            except StudyConflictError as error:
                parser.exit(2, f"error: {error}\n")
            record = summary.session_record(started, jobs, args.executor)
            sessions.append({**record, "command": command})
            write_json_atomic(sessions_path, sessions)
            if summary.stopped:
                print(
                    summary.stopped_message(),
                    file=sys.stderr,
                    flush=True,
                )
                return 130
            print(
                f"runs: {len(summary.done)} done now, {len(summary.skipped_finished)} earlier, "
                f"{len(summary.failed)} failed, {len(summary.blocked)} blocked",
                flush=True,
            )
            failed = len(summary.failed) + len(summary.blocked)
        text = render_report(load_results(plan, store), config, command, sessions)
        write_text_atomic(out / "report.md", text)
    finally:
        store.close()
    print(f"report: {os.fspath((out / 'report.md').resolve())}", flush=True)
    return 1 if failed else 0
