"""Parallel execution in dependency order, resume after an interruption, failures."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path

import pytest
from reproduce_helpers import failing_prior_work, fake_work

from sb3_pnn.reproduce.cli import main
from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.running.executor import LocalPool, execute, run_one
from sb3_pnn.reproduce.running.store import RunStore

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


def test_a_prior_trained_again_differently_conflicts_with_the_runs_that_read_it(tmp_path) -> None:
    """Each run's manifest records its priors' configuration hashes; when a prior's folder is
    removed and the prior trained again under a changed factor (its learners' own specs
    unchanged), resuming refuses the learners that read the old prior instead of pairing them
    with the new one."""
    import shutil

    from sb3_pnn.reproduce.running.store import StudyConflictError

    plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    store = RunStore(tmp_path)
    store.open()
    execute(plan, store, fake_work, jobs=2, quiet=True)
    learner = next(s for s in plan if "prior-pf_sine-s0" in s.deps)
    recorded = store.manifest(learner.run_id)["deps_hashes"]
    assert recorded["prior-pf_sine-s0"] == store.manifest("prior-pf_sine-s0")["config_hash"]
    assert execute(plan, store, fake_work, jobs=2, quiet=True).done == []  # resumes as before
    shutil.rmtree(store.run_dir("prior-pf_sine-s0"))
    changed = build_plan(
        StudyConfig(budget_name="tiny", seeds=1, setup_changes=(("pf_sine_budget", 3.0),))
    )
    assert next(s for s in changed if s.run_id == learner.run_id) == learner
    with pytest.raises(StudyConflictError, match=r"trained on prior 'prior-pf_sine-s0'"):
        execute(changed, store, fake_work, jobs=2, quiet=True)
    store.close()


def test_bad_jobs(tmp_path) -> None:
    store = RunStore(tmp_path)
    with pytest.raises(ValueError, match="jobs=0"):
        execute([], store, fake_work, jobs=0)


def _study_args(out: Path) -> list[str]:
    return ["--tiny", "--seeds", "1", "--jobs", "2", "--no-progress", "--out", str(out)]


def _start_study_and_wait_for_runs(out: Path, n_runs: int = 3) -> subprocess.Popen:
    """A stand-in study (0.4 s per run) in a process group of its own, once ``n_runs`` of its
    runs are finished (the test fails after 60 s); the caller signals the group. The study
    handles Ctrl-C as one started from a terminal does, also where the tests themselves run
    in the background (whose children inherit SIGINT ignored)."""
    code = (
        "import signal; signal.signal(signal.SIGINT, signal.default_int_handler); "
        f"import sys; sys.path.insert(0, {str(HERE)!r}); "
        "from reproduce_helpers import fake_work; from sb3_pnn.reproduce.cli import main; "
        f"sys.exit(main({_study_args(out)!r}, work=fake_work))"
    )
    env = {**os.environ, "REPRODUCE_STANDIN_SLEEP": "0.4"}
    proc = subprocess.Popen(
        [sys.executable, "-c", code],
        env=env,
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.time() + 60
    runs = out / "runs"
    while time.time() < deadline:
        if runs.is_dir() and sum(1 for d in runs.iterdir() if not d.name.startswith(".")) >= n_runs:
            return proc
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    pytest.fail(f"the study did not finish {n_runs} runs within 60 s")


def test_killed_study_resumes(tmp_path) -> None:
    """Kill a running study (process group, SIGKILL) and finish it with a second call."""
    out = tmp_path / "study"
    proc = _start_study_and_wait_for_runs(out)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.communicate()
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


def _stop_study(proc: subprocess.Popen, send) -> str:
    """``send(pid)`` a signal to the study, wait for it to end (SIGKILL to its group after
    60 s) and return what it printed on stderr."""
    try:
        send(proc.pid)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    return err


def test_ctrl_c_records_the_session_and_the_same_command_resumes(tmp_path) -> None:
    """Ctrl-C (SIGINT to the process group, as a terminal sends it) ends the invocation with
    exit code 130 and a session marked stopped that counts the runs it committed; the same
    command then finishes the study."""
    out = tmp_path / "study"
    proc = _start_study_and_wait_for_runs(out)
    err = _stop_study(proc, lambda pid: os.killpg(pid, signal.SIGINT))
    assert proc.returncode == 130, err
    assert "stopped after" in err and "the same command resumes" in err
    sessions = json.loads((out / "sessions.json").read_text())
    assert len(sessions) == 1 and sessions[0]["stopped"] is True
    assert "stopped by the user" in sessions[0]["note"]
    # every run its workers committed counts, also those that ended after the interrupt
    assert sessions[0]["runs_done"] == len(_snapshot(out)) >= 3
    assert not (out / "report.md").exists()
    plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    assert main(_study_args(out), work=fake_work) == 0
    sessions = json.loads((out / "sessions.json").read_text())
    assert len(sessions) == 2 and "stopped" not in sessions[1]
    assert len(_snapshot(out)) == len(plan)
    assert "stopped" in (out / "report.md").read_text()  # the report names the stopped session
    assert not [d for d in (out / "runs").iterdir() if d.name.startswith(".tmp-")]


def test_sigterm_stops_like_ctrl_c_and_lets_the_runs_in_flight_commit(tmp_path) -> None:
    """SIGTERM to the main process alone (a scheduler's stop; a background job ignores SIGINT):
    exit code 130, a stopped session that counts every committed run, and no run cut short
    (the workers were not signalled, so their runs in flight finish and commit)."""
    out = tmp_path / "study"
    proc = _start_study_and_wait_for_runs(out)
    err = _stop_study(proc, lambda pid: os.kill(pid, signal.SIGTERM))
    assert proc.returncode == 130, err
    sessions = json.loads((out / "sessions.json").read_text())
    assert sessions[0]["stopped"] is True and sessions[0]["runs_failed"] == 0
    assert sessions[0]["runs_done"] == len(_snapshot(out)) >= 3
    assert not [d for d in (out / "runs").iterdir() if d.name.startswith(".tmp-")]


class _CommitThenInterruptPool:
    """A pool whose runs commit at once, in this process, and whose wait is interrupted (as by
    Ctrl-C) before it reports any of them: the window between a worker's commit and the
    executor's bookkeeping."""

    def __init__(self, store: RunStore) -> None:
        self.store = store

    def submit(self, spec):
        return run_one(fake_work, spec.to_dict(), os.fspath(self.store.out))

    def wait(self, handles):
        raise KeyboardInterrupt

    def close(self) -> None:
        pass


def test_ctrl_c_counts_runs_committed_before_their_report(tmp_path) -> None:
    plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    store = RunStore(tmp_path)
    store.open()
    summary = execute(
        plan, store, fake_work, jobs=2, quiet=True, pool=_CommitThenInterruptPool(store)
    )
    store.close()
    assert summary.stopped
    assert len(summary.done) == 2 and sorted(summary.done) == sorted(_snapshot(tmp_path))


def test_a_worker_that_died_after_its_commit_counts_its_run_done(tmp_path) -> None:
    """A worker interrupted while it sends its result back breaks the pool after committing:
    the run is done, and no failure is recorded for it."""
    plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    spec = plan[0]
    store = RunStore(tmp_path)
    store.open()
    pool = LocalPool(store, fake_work, jobs=1)
    try:
        run_one(fake_work, spec.to_dict(), os.fspath(tmp_path))
        broken: Future = Future()
        broken.set_exception(BrokenProcessPool("a worker ended abruptly"))
        assert pool.outcome(broken, spec) == ("done", "")
        assert store.failures() == {}
        other = plan[1]
        assert pool.outcome(broken, other)[0] == "failed"  # not committed: a real failure
        assert other.run_id in store.failures()
    finally:
        pool.close()
        store.close()


def test_eta_counts_episodes_not_runs(tmp_path, monkeypatch) -> None:
    """The time left scales with the episodes still to train: a first short run that took 10 s
    for 1 of 11 episodes leaves 100 s, not 10 s per remaining run."""
    from sb3_pnn.reproduce.planning.plan import RunSpec
    from sb3_pnn.reproduce.running import executor

    specs = [
        RunSpec(run_id="short", kind="prior", agent="sac", path=None, env_id=None, seed=0,
                episodes=1),
        RunSpec(run_id="long", kind="prior", agent="sac", path=None, env_id=None, seed=0,
                episodes=10),
    ]  # fmt: skip
    store = RunStore(tmp_path)
    store.open()
    clock = [1000.0]
    monkeypatch.setattr(executor.time, "time", lambda: clock[0])
    schedule = executor._Schedule(specs, store, quiet=True)
    assert schedule.eta() == "eta after the first run"
    clock[0] += 10.0
    schedule.settle("short", "done", "")
    assert schedule.eta() == "eta 0:01:40"
    store.close()
