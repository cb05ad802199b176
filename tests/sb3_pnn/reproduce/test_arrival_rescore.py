"""tools.arrival_rescore: a study's evaluation replayed with an arrival gate."""

from __future__ import annotations

import json

import pytest

from sb3_pnn.evaluation.evaluate import evaluate_policy_on_task
from sb3_pnn.reproduce.tools.arrival_rescore import main

ENV = "rov_envs/PathFollowingStraight-v0"


def _pid_study(tmp_path, start_noise=(12.0, 0.0)):
    """A study folder whose adaptive PID run was evaluated on the straight path without
    obstacles from starts up to tens of metres off the path, so that some episodes reach the
    end of the path far from the target."""
    run = tmp_path / "runs" / "adaptive_pid-straight"
    run.mkdir(parents=True)
    (run / "manifest.json").write_text(json.dumps({"agent": "adaptive_pid"}))
    kwargs = {"control_period": 1.0, "length": 10.0}
    result = evaluate_policy_on_task(
        "adaptive_pid", ENV, 6, 10000, start_noise=start_noise, env_kwargs=kwargs
    )
    (run / "eval.json").write_text(json.dumps({"path_following": result.to_dict()}))
    return result, kwargs


def test_the_evaluation_is_replayed_on_its_own_episodes_with_the_gate(tmp_path, capsys):
    evaluated, kwargs = _pid_study(tmp_path)
    assert main([str(tmp_path), "--arrival-gate", "2", "--agents", "adaptive_pid"]) == 0
    out = capsys.readouterr().out
    gated = evaluate_policy_on_task(
        "adaptive_pid",
        ENV,
        6,
        10000,
        start_noise=(12.0, 0.0),
        env_kwargs={**kwargs, "arrival_gate": 2.0},
    )
    assert gated.success_rate < evaluated.success_rate  # the gate fails some ends here
    assert (
        f"| adaptive_pid | straight | path_following | {100 * evaluated.success_rate:.1f} % | "
        f"{100 * gated.success_rate:.1f} % | {100 * gated.success_rate:.0f} |"
    ) in out


def test_a_gate_and_a_study_with_runs_are_required(tmp_path, capsys):
    with pytest.raises(SystemExit):
        main([str(tmp_path)])
    assert "--arrival-gate" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main([str(tmp_path), "--arrival-gate", "1"])
    assert "--arrival-gate must be a number in [2, 100]" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main([str(tmp_path), "--arrival-gate", "5"])
    assert "holds no run of" in capsys.readouterr().err
