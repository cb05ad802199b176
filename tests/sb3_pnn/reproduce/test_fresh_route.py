"""The fresh-seed route diagnostic: own task and path alone, per run, beside a second study."""

from __future__ import annotations

import json

import pytest

from sb3_pnn.evaluation import evaluate_policy_on_task
from sb3_pnn.reproduce.tools.fresh_route import FRESH_SEED, main


def _pid_run(study, env_kwargs: dict) -> None:
    run = study / "runs" / "adaptive_pid-straight"
    run.mkdir(parents=True)
    (run / "manifest.json").write_text(json.dumps({"agent": "adaptive_pid"}))
    tasks = {
        "original": {"env_id": "rov_envs/PlanningStraight-v0", "env_kwargs": env_kwargs},
        "path_following": {"env_id": "rov_envs/PathFollowingStraight-v0", "env_kwargs": {}},
    }
    (run / "eval.json").write_text(json.dumps(tasks))


def test_runs_are_replayed_on_fresh_seeds_beside_a_second_study(tmp_path, capsys) -> None:
    """The figures are the evaluation's on seeds 40000+ with the run's own env keywords; the
    change of mean abs(g) compares the two studies' runs of the same seed."""
    _pid_run(tmp_path / "a", {"obstacles": []})
    _pid_run(tmp_path / "b", {})
    argv = [str(tmp_path / "a"), "--agent", "adaptive_pid", "--episodes", "2"]
    assert main([*argv, "--against", str(tmp_path / "b")]) == 0
    out = capsys.readouterr().out
    alone = evaluate_policy_on_task(
        "adaptive_pid", "PlanningStraight-v0", 2, seed=FRESH_SEED, env_kwargs={"obstacles": []}
    )
    among = evaluate_policy_on_task("adaptive_pid", "PlanningStraight-v0", 2, seed=FRESH_SEED)
    row = out.splitlines()[2]
    assert row.startswith("| 0 | 100 %, " + f"{among.mean_abs_cross_track:.2f} m")
    assert f"100 %, {alone.mean_abs_cross_track:.2f} m" in row
    change = 100 * (alone.mean_abs_cross_track / among.mean_abs_cross_track - 1)
    assert out.splitlines()[-1] == (
        f"mean abs(g) change: original {change:+.1f} %, path_following +0.0 %"
    )


def test_a_study_without_the_run_is_a_usage_error(tmp_path, capsys) -> None:
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), "--agent", "spnn", "--seeds", "0"])
    assert stop.value.code == 2
    assert "holds no run of --agent 'spnn' on the straight path" in capsys.readouterr().err


def test_pf_column_replays_the_path_following_column_on_its_own_task(tmp_path, capsys) -> None:
    """--agent pf_column reads the runs prior-pf_PATH-sN and replays only their "own" task."""
    run = tmp_path / "runs" / "prior-pf_sine-s3"
    run.mkdir(parents=True)
    (run / "manifest.json").write_text(json.dumps({"agent": "adaptive_pid"}))
    own = {"env_id": "rov_envs/PathFollowingSine-v0", "env_kwargs": {}}
    (run / "eval.json").write_text(json.dumps({"own": own}))
    argv = [str(tmp_path), "--agent", "pf_column", "--path", "sine", "--episodes", "2"]
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    expected = evaluate_policy_on_task("adaptive_pid", "PathFollowingSine-v0", 2, seed=FRESH_SEED)
    assert lines[0] == f"| seed | {tmp_path}: own task |"
    assert lines[2].startswith(f"| 3 | 100 %, {expected.mean_abs_cross_track:.2f} m")
    assert lines[2].count("|") == 3
