"""Are two study folders' runs the same runs? Compares, run by run, what a run measured.

For every run finished in both folders: its eval.json (without the ``wall_time_s`` timing
fields), validation.json and episodes.json must be equal; prints one line per run with both
CPU times, and the count. Exit status 1 if any run differs or is missing from one folder.

Usage: python -m sb3_pnn.reproduce.tools.same_runs STUDY_A STUDY_B
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

COMPARED = ("eval.json", "validation.json", "episodes.json")


def without_timing(value: Any) -> Any:
    """``value`` without any ``wall_time_s`` entry, at any depth."""
    if isinstance(value, dict):
        return {k: without_timing(v) for k, v in value.items() if k != "wall_time_s"}
    if isinstance(value, list):
        return [without_timing(v) for v in value]
    return value


def differences(run_a: Path, run_b: Path) -> list[str]:
    """The compared files that differ (or exist on one side only)."""
    bad = []
    for name in COMPARED:
        a, b = run_a / name, run_b / name
        if not a.exists() and not b.exists():
            continue
        if not (a.exists() and b.exists()):
            bad.append(f"{name} (one side only)")
        elif without_timing(json.loads(a.read_text())) != without_timing(json.loads(b.read_text())):
            bad.append(name)
    return bad


def finished(study: Path) -> set[str]:
    return {p.parent.name for p in (study / "runs").glob("*/manifest.json")}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("study_a", type=Path)
    parser.add_argument("study_b", type=Path)
    args = parser.parse_args()
    runs_a, runs_b = finished(args.study_a), finished(args.study_b)
    if not runs_a or not runs_b:
        parser.error("both folders need finished runs (runs/*/manifest.json)")
    same = 0
    for run in sorted(runs_a & runs_b):
        bad = differences(args.study_a / "runs" / run, args.study_b / "runs" / run)
        cpu = [
            json.loads((study / "runs" / run / "manifest.json").read_text()).get("cpu_s", 0.0)
            for study in (args.study_a, args.study_b)
        ]
        verdict = "same" if not bad else "DIFFERS: " + ", ".join(bad)
        print(f"{run:28s} {verdict:36s} CPU s {cpu[0]:7.1f} -> {cpu[1]:7.1f}")
        same += not bad
    only = sorted(runs_a ^ runs_b)
    for run in only:
        print(f"{run:28s} finished in one folder only")
    print(f"{same} of {len(runs_a | runs_b)} runs the same")
    return 0 if same == len(runs_a | runs_b) else 1


if __name__ == "__main__":
    sys.exit(main())
