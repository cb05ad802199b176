"""Helpers of the rl-zoo command tests: run ``python -m sb3_pnn.<command>`` in a folder."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from sb3_pnn.zoo.cli import TRAIN_PROG, train_main
from sb3_pnn.zoo.errors import USAGE_EXIT_CODE
from sb3_pnn.zoo.errors import run_cli as guarded

REPO = Path(__file__).resolve().parents[3]
PF_ENV = "rov_envs/PathFollowingStraight-v0"
OA_ENV = "rov_envs/ObstacleAvoidance-v0"
PLAN_ENV = "rov_envs/PlanningStraight-v0"

# Tiny budgets: 3 s episodes (30 steps), small networks, one update per step after 20 steps.
TINY = [
    "--num-threads",
    "1",
    "--eval-freq",
    "-1",
    "--seed",
    "1",
    "--env-kwargs",
    "max_episode_seconds:3",
    "-params",
    "learning_starts:20",
    "train_freq:1",
    "gradient_steps:1",
    "batch_size:32",
    "buffer_size:2000",
    "policy_kwargs:dict(net_arch=[32,32])",
]


def cli_env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(REPO), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    env.update(OMP_NUM_THREADS="1", MKL_NUM_THREADS="1", MPLBACKEND="Agg")
    env.pop("SB3_PNN_TRACEBACK", None)
    return env


def run_cli(
    command: str, *args: str, cwd: Path, timeout: float = 240, check: bool = True
) -> subprocess.CompletedProcess[str]:
    """``python -m sb3_pnn.<command> args...`` in ``cwd``; fails the test with its output."""
    result = subprocess.run(
        [sys.executable, "-m", f"sb3_pnn.{command}", *args],
        cwd=cwd,
        env=cli_env(),
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    if check and result.returncode != 0:
        pytest.fail(
            f"sb3_pnn.{command} {' '.join(args)} exited {result.returncode}\n"
            f"stdout:\n{result.stdout[-4000:]}\nstderr:\n{result.stderr[-4000:]}"
        )
    return result


def fails(capsys: pytest.CaptureFixture[str], main, prog: str, argv: list[str]) -> str:
    with pytest.raises(SystemExit) as exit_info:
        guarded(lambda: main(argv), prog)
    assert exit_info.value.code == USAGE_EXIT_CODE
    err = capsys.readouterr().err.strip().splitlines()
    assert err, "no message on stderr"
    assert err[-1].startswith(f"{prog}: error: ")
    assert not any("Traceback" in line for line in err)
    return err[-1]


@pytest.fixture
def in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


def train_fails(capsys, argv: list[str]) -> str:
    return fails(capsys, train_main, TRAIN_PROG, argv)
