"""Parallel execution in dependency order, resume after an interruption, failures."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from reproduce_standins import failing_prior_work, fake_work

from sb3_pnn.reproduce.executor import execute
from sb3_pnn.reproduce.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.store import RunStore

HERE = Path(__file__).parent


def _snapshot(out: Path) -> dict[str, tuple[float, str]]:
    """run id -> (manifest mtime, manifest text) of the finished runs."""
    return {
        d.name: ((d / "manifest.json").stat().st_mtime_ns, (d / "manifest.json").read_text())
        for d in (out / "runs").iterdir()
        if not d.name.startswith(".")
    }


def test_interrupted_study_resumes_without_redoing_runs(tmp_path) -> None:
    plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    store = RunStore(tmp_path)
    store.open()
    first = execute(plan, store, fake_work, jobs=2, quiet=True, max_new_runs=5)
    store.close()
    assert len(first.done) == 5 and not first.failed
    before = _snapshot(tmp_path)
    assert set(before) == set(first.done)

    store = RunStore(tmp_path)
    store.open()
    second = execute(plan, store, fake_work, jobs=2, quiet=True)
    store.close()
    assert sorted(second.skipped_finished) == sorted(first.done)
    assert set(second.done).isdisjoint(first.done)
    assert len(second.done) + len(first.done) == len(plan)
    after = _snapshot(tmp_path)
    for run_id, value in before.items():
        assert after[run_id] == value  # not redone, not rewritten


def test_failed_prior_blocks_its_dependents_and_is_retried(tmp_path) -> None:
    plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    store = RunStore(tmp_path)
    store.open()
    summary = execute(plan, store, failing_prior_work, jobs=2, quiet=True)
    assert list(summary.failed) == ["prior-pf_straight-s0"]
    straight_learners = {s.run_id for s in plan if s.path == "straight" and s.deps}
    assert set(summary.blocked) == straight_learners
    assert "stand-in failure" in store.failures()["prior-pf_straight-s0"]["error"]
    again = execute(plan, store, fake_work, jobs=2, quiet=True)
    assert sorted(again.done) == sorted(["prior-pf_straight-s0", *straight_learners])
    assert store.failures() == {}
    store.close()


def test_bad_jobs(tmp_path) -> None:
    store = RunStore(tmp_path)
    with pytest.raises(ValueError, match="jobs=0"):
        execute([], store, fake_work, jobs=0)


def test_killed_study_resumes(tmp_path) -> None:
    """Kill a running study (process group, SIGKILL) and finish it with a second call."""
    out = tmp_path / "study"
    args = ["--tiny", "--seeds", "1", "--jobs", "2", "--no-progress", "--out", str(out)]
    code = (
        f"import sys; sys.path.insert(0, {str(HERE)!r}); "
        "from reproduce_standins import fake_work; from sb3_pnn.reproduce.cli import main; "
        f"main({args!r}, work=fake_work)"
    )
    env = {**os.environ, "REPRODUCE_STANDIN_SLEEP": "0.4"}
    proc = subprocess.Popen([sys.executable, "-c", code], env=env, start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    deadline = time.time() + 60
    try:
        while time.time() < deadline:
            runs = out / "runs"
            if runs.is_dir() and sum(1 for d in runs.iterdir() if not d.name.startswith(".")) >= 3:
                break
            time.sleep(0.05)
        else:
            pytest.fail("the study did not finish 3 runs within 60 s")
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    time.sleep(0.5)  # let orphaned workers (if any) notice
    before = _snapshot(out)
    plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    assert 3 <= len(before) < len(plan)
    store = RunStore(out)
    store.open()
    summary = execute(plan, store, fake_work, jobs=2, quiet=True)
    store.close()
    assert not summary.failed and len(summary.done) == len(plan) - len(before)
    after = _snapshot(out)
    assert len(after) == len(plan)
    for run_id, value in before.items():
        assert after[run_id] == value
    assert not [d for d in (out / "runs").iterdir() if d.name.startswith(".tmp-")]
