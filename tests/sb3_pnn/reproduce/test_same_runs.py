"""sb3_pnn/reproduce/tools/same_runs.py: runs that measured the same things are the same, timing
fields aside; any other difference, or a run finished on one side only, is reported (exit 1)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path


def _run(study: Path, run_id: str, success: float, wall: float, cpu: float) -> None:
    folder = study / "runs" / run_id
    folder.mkdir(parents=True)
    (folder / "manifest.json").write_text(json.dumps({"run_id": run_id, "cpu_s": cpu}))
    evaluation = {"original": {"success_rate": success, "wall_time_s": wall}}
    (folder / "eval.json").write_text(json.dumps(evaluation))
    (folder / "validation.json").write_text(json.dumps({"history": [{"success_rate": success}]}))


def _compare(a: Path, b: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "sb3_pnn.reproduce.tools.same_runs", str(a), str(b)],
        capture_output=True,
        text=True,
    )


def test_only_timing_differs_then_the_runs_are_the_same(tmp_path: Path) -> None:
    a, b = tmp_path / "a", tmp_path / "b"
    _run(a, "pnn-straight-s0", 1.0, wall=0.08, cpu=300.0)
    _run(b, "pnn-straight-s0", 1.0, wall=0.09, cpu=250.0)
    result = _compare(a, b)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "1 of 1 runs the same" in result.stdout
    assert "300.0 ->   250.0" in result.stdout


def test_a_different_result_or_a_missing_run_is_reported(tmp_path: Path) -> None:
    a, b = tmp_path / "a", tmp_path / "b"
    _run(a, "pnn-straight-s0", 1.0, wall=0.08, cpu=300.0)
    _run(b, "pnn-straight-s0", 0.9, wall=0.08, cpu=300.0)
    _run(a, "spnn-sine-s0", 1.0, wall=0.08, cpu=300.0)
    result = _compare(a, b)
    assert result.returncode == 1
    assert "DIFFERS: eval.json, validation.json" in result.stdout
    assert "spnn-sine-s0                 finished in one folder only" in result.stdout
    assert "0 of 2 runs the same" in result.stdout
