"""``python -m sb3_pnn.evaluate``: table, JSON output, model zips, and one-line errors (exit 2)."""

from __future__ import annotations

import json
import subprocess
import sys

import gymnasium as gym
import pytest

import rov_envs  # noqa: F401
from sb3_pnn.evaluation.__main__ import PROG, run


def test_baseline_table_and_json(tmp_path, capsys):
    out = tmp_path / "r.json"
    rc = run(["--model", "pid", "--env", "PathFollowingSine-v0", "--episodes", "2",
              "--seed", "3", "--record", "1", "--out", str(out)])  # fmt: skip
    assert rc == 0
    text = capsys.readouterr().out
    assert "success rate" in text and "100.0 %" in text and "rov_envs/PathFollowingSine-v0" in text
    data = json.loads(out.read_text())
    assert data["n_episodes"] == 2 and data["seed"] == 3 and len(data["trajectories"]) == 1


def test_model_zip_is_loaded(tmp_path, capsys):
    from sb3_pnn import DiscreteSAC

    env = gym.make("rov_envs/PathFollowingStraight-v0")
    DiscreteSAC("MultiInputPolicy", env, policy_kwargs={"net_arch": [8]}, seed=0).save(
        tmp_path / "m.zip"
    )
    rc = run(["--model", str(tmp_path / "m"), "--env", "PathFollowingStraight-v0",
              "--episodes", "2"])  # fmt: skip
    assert rc == 0
    assert "policy" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["--model", "pid", "--env", "NoSuchTask-v0"], "--env"),
        (["--model", "/no/such/model.zip", "--env", "PlanningSine-v0"], "no such file"),
        (["--model", "pid", "--env", "PlanningSine-v0", "--episodes", "0"], "--episodes"),
        (["--model", "pid", "--env", "PlanningSine-v0", "--seed", "-2"], "--seed"),
    ],
)
def test_bad_input_gives_one_line_and_exit_code_2(argv, needle, capsys):
    assert run(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith(f"{PROG}: error:") and needle in err


@pytest.mark.parametrize(
    ("argv", "suggestion"),
    [
        (["--model", "pid", "--env", "PlanningStrait-v0"], "did you mean 'PlanningStraight-v0'?"),
        (["--model", "adaptive_pd", "--env", "PlanningSine-v0"], "did you mean 'adaptive_pid'?"),
    ],
)
def test_mistyped_names_get_a_suggestion(argv, suggestion, capsys):
    assert run(argv) == 2
    assert suggestion in capsys.readouterr().err


def test_model_of_another_task_is_refused_before_it_runs(tmp_path, capsys):
    from sb3_pnn import DiscreteSAC

    env = gym.make("rov_envs/PlanningStraight-v0")
    DiscreteSAC("MultiInputPolicy", env, policy_kwargs={"net_arch": [8]}).save(tmp_path / "spnn")
    argv = ["--model", str(tmp_path / "spnn.zip"), "--env", "PathFollowingStraight-v0"]
    assert run(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert "policy 'spnn' was trained with the observation space Dict(" in err
    assert "missing there: 'goal', 'sonar'" in err
    assert "but rov_envs/PathFollowingStraight-v0 has Dict('motion'" in err


def test_not_a_model_zip_is_a_usage_error(tmp_path, capsys):
    bad = tmp_path / "bad.zip"
    bad.write_bytes(b"not a zip")
    assert run(["--model", str(bad), "--env", "PlanningSine-v0"]) == 2
    assert "cannot load" in capsys.readouterr().err


def test_module_entry_point_exit_code():
    proc = subprocess.run(
        [sys.executable, "-m", "sb3_pnn.evaluate", "--model", "pid", "--env", "Nope-v0"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2 and proc.stderr.strip().startswith(f"{PROG}: error: --env")


@pytest.mark.parametrize(("argv", "threads"), [([], 1), (["--num-threads", "2"], 2)])
def test_torch_runs_on_one_thread_unless_told(argv, threads, capsys):
    import torch

    before = torch.get_num_threads()
    try:
        torch.set_num_threads(3)
        assert (
            run(["--model", "pid", "--env", "PathFollowingSine-v0", "--episodes", "1", *argv]) == 0
        )
        assert torch.get_num_threads() == threads
    finally:
        torch.set_num_threads(before)


def test_zero_threads_is_a_usage_error(capsys):
    argv = ["--model", "pid", "--env", "PathFollowingSine-v0", "--num-threads", "0"]
    assert run(argv) == 2
    assert "--num-threads 0" in capsys.readouterr().err


def test_switch_memory_needs_an_spnn_with_a_hard_switch(tmp_path, capsys):
    """--switch-memory plays SPNN's hard switch with a memory; a model without that gate (or a
    negative distance) is refused by name before any episode runs."""
    from sb3_pnn import DiscreteSAC

    env = gym.make("rov_envs/PathFollowingStraight-v0")
    DiscreteSAC("MultiInputPolicy", env, policy_kwargs={"net_arch": [8]}).save(tmp_path / "m")
    argv = ["--model", str(tmp_path / "m.zip"), "--env", "PathFollowingStraight-v0"]
    assert run([*argv, "--switch-memory", "10"]) == 2
    err = capsys.readouterr().err
    assert "--switch-memory 10.0: SwitchMemory needs an SPNN whose gate is eq. 15's hard" in err


def test_no_reversal_plays_a_model_and_refuses_a_baseline(tmp_path, capsys):
    """--no-reversal plays a model through NoReversal; a PID baseline (no model) is refused."""
    from sb3_pnn import DiscreteSAC

    env = gym.make("rov_envs/PathFollowingStraight-v0")
    DiscreteSAC("MultiInputPolicy", env, policy_kwargs={"net_arch": [8]}).save(tmp_path / "m")
    out = tmp_path / "r.json"
    argv = ["--model", str(tmp_path / "m.zip"), "--env", "PathFollowingStraight-v0",
            "--episodes", "2", "--no-reversal", "--out", str(out)]  # fmt: skip
    assert run(argv) == 0
    assert json.loads(out.read_text())["n_episodes"] == 2
    assert run(["--model", "pid", "--env", "PathFollowingStraight-v0", "--no-reversal"]) == 2
    assert "--no-reversal needs a trained model's zip; got the baseline 'pid'" in (
        capsys.readouterr().err
    )
