"""Distributed tuning on a real PostgreSQL server (scripts/start_postgres.sh starts one).

Two workers share one study; a worker killed mid-trial (SIGKILL) leaves its trial RUNNING until
the heartbeat grace period passes, after which the next worker to start a trial marks it FAIL and
the study goes on.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
import uuid
from pathlib import Path

import optuna
import pytest
from zoo_helpers import TINY, cli_env, run_cli

from sb3_pnn.zoo.tuning import create_storage

URL = os.environ.get(
    "SB3_PNN_POSTGRES_URL", "postgresql://sb3pnn:sb3pnn@127.0.0.1:5432/sb3pnn_test"
)
ENV = "rov_envs/PathFollowingStraight-v0"


def _reachable() -> str | None:
    try:
        import psycopg2
    except ImportError:
        return "psycopg2 is not installed (pip install psycopg2-binary)"
    try:
        psycopg2.connect(URL, connect_timeout=3).close()
    except psycopg2.Error as error:
        reason = " ".join(str(error).split())[:160]
        return f"no PostgreSQL server at {URL} (run scripts/start_postgres.sh): {reason}"
    return None


_SKIP = _reachable()
pytestmark = [
    pytest.mark.postgres,
    pytest.mark.slow,
    pytest.mark.skipif(_SKIP is not None, reason=_SKIP or ""),
]


def worker_args(study: str, n_trials: int, n_timesteps: int) -> list[str]:
    return [
        "--algo", "dsac", "--env", ENV, "-f", "logs", "-optimize",
        "--storage", URL, "--study-name", study, "--n-trials", str(n_trials),
        "-n", str(n_timesteps), "--n-evaluations", "1", "--eval-episodes", "1",
        "--no-optim-plots", "--heartbeat-interval", "1", "--grace-period", "2", *TINY,
    ]  # fmt: skip


def load(study: str) -> optuna.Study:
    return optuna.load_study(storage=create_storage(URL, heartbeat_interval=1), study_name=study)


def test_two_workers_share_one_study(tmp_path: Path) -> None:
    study = f"share_{uuid.uuid4().hex[:8]}"
    workers = [
        subprocess.Popen(
            [sys.executable, "-m", "sb3_pnn.train", *worker_args(study, 3, 60)],
            cwd=tmp_path,
            env=cli_env(),
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        for _ in range(2)
    ]
    outputs = [w.communicate(timeout=300)[0] for w in workers]
    for worker, output in zip(workers, outputs):
        assert worker.returncode == 0, output[-3000:]
        assert f"Study '{study}' in postgresql://sb3pnn:***@" in output  # password hidden
    trials = load(study).trials
    assert sorted(t.number for t in trials) == list(range(6))
    assert all(t.state == optuna.trial.TrialState.COMPLETE for t in trials)


def test_killed_worker_trial_is_marked_failed_and_the_study_goes_on(tmp_path: Path) -> None:
    study = f"kill_{uuid.uuid4().hex[:8]}"
    victim = subprocess.Popen(
        [sys.executable, "-m", "sb3_pnn.train", *worker_args(study, 1, 200_000)],
        cwd=tmp_path,
        env=cli_env(),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        deadline = time.monotonic() + 120
        running: list[optuna.trial.FrozenTrial] = []
        while time.monotonic() < deadline and not running:
            time.sleep(1.0)
            assert victim.poll() is None, "the victim worker ended before it was killed"
            try:
                running = load(study).get_trials(states=(optuna.trial.TrialState.RUNNING,))
            except KeyError:  # study not created yet
                continue
        assert running, "the victim never started a trial"
        time.sleep(1.5)  # let it record heartbeats mid-trial
    finally:
        victim.send_signal(signal.SIGKILL)
        victim.wait(timeout=30)
    assert victim.returncode == -signal.SIGKILL
    killed = running[0].number
    assert load(study).trials[killed].state == optuna.trial.TrialState.RUNNING  # nobody noticed yet

    result = run_cli("train", *worker_args(study, 2, 60), cwd=tmp_path, timeout=300)
    trials = load(study).trials
    assert trials[killed].state == optuna.trial.TrialState.FAIL
    others = [t for t in trials if t.number != killed]
    assert len(others) == 2 and all(t.state == optuna.trial.TrialState.COMPLETE for t in others)
    assert "Best trial:" in result.stdout
