"""The drawn-layout validation measure: a run's kept policy among scatter-drawn obstacles."""

from __future__ import annotations

import json

import pytest

from sb3_pnn.evaluation.evaluate import evaluate_policy_on_task
from sb3_pnn.reproduce.tools.drawn_layouts import main


def _pid_run(tmp_path, env_kwargs):
    run = tmp_path / "runs" / "adaptive_pid-straight"
    run.mkdir(parents=True)
    (run / "manifest.json").write_text(json.dumps({"agent": "adaptive_pid"}))
    (run / "eval.json").write_text(json.dumps({"original": {"env_kwargs": env_kwargs}}))


def test_a_run_is_replayed_among_drawn_obstacles_on_validation_seeds(tmp_path, capsys):
    """The success printed is the run's policy on its task with layout='scatter' and the run's
    env keywords, episodes from the validation seed 20000; not the task's fixed obstacles."""
    _pid_run(tmp_path, {"control_period": 0.5})
    assert main([str(tmp_path), "--agent", "adaptive_pid", "--episodes", "3"]) == 0
    out = capsys.readouterr().out
    env = "rov_envs/PlanningStraight-v0"
    drawn = evaluate_policy_on_task(
        "adaptive_pid", env, 3, 20000, env_kwargs={"control_period": 0.5, "layout": "scatter"}
    )
    assert f"| 0 | {100 * drawn.success_rate:.0f} % |" in out
    assert f"mean success {100 * drawn.success_rate:.1f} % over 1 run(s)" in out
    fixed = evaluate_policy_on_task(
        "adaptive_pid", env, 3, 20000, env_kwargs={"control_period": 0.5}
    )
    assert fixed.success_rate != drawn.success_rate  # so the line above tells the layouts apart


def test_against_a_second_study_prints_the_difference_of_the_means(tmp_path, capsys):
    """``--against``: both studies' runs replayed on the same drawn fields; the same policy
    and env keywords in both give a difference of exactly 0, and one run per side gives no
    interval (it cannot tell how much runs of one set-up differ)."""
    study, base = tmp_path / "arm", tmp_path / "base"
    for folder in (study, base):
        _pid_run(folder, {"control_period": 0.5})
    argv = [str(study), "--agent", "adaptive_pid", "--episodes", "2", "--against", str(base)]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert f"| seed | {base} | {study} |" in out
    assert "difference +0.0 points, no interval (one run per side)" in out


def test_a_missing_run_or_model_stops_with_a_message(tmp_path, capsys):
    """(The task arguments are the replay tools' shared parser, tested with action_reversals.)"""
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), "--seeds", "0"])
    assert stop.value.code == 2
    assert "spnn-straight-s0/eval.json does not exist: expected a finished run" in (
        capsys.readouterr().err
    )
    run = tmp_path / "runs" / "spnn-straight-s0"
    run.mkdir(parents=True)
    (run / "eval.json").write_text(json.dumps({"original": {"env_kwargs": {}}}))
    with pytest.raises(SystemExit):
        main([str(tmp_path), "--seeds", "0"])
    assert "spnn-straight-s0/model.zip does not exist" in capsys.readouterr().err


@pytest.mark.parametrize("value", ["0", "1.5", "wide"])
def test_a_bad_gate_bound_is_refused_by_name(tmp_path, capsys, value):
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), "--gate-corridor", value])
    assert stop.value.code == 2
    assert f"{value!r} is not allowed: expected a fraction of d_L in (0, 1], or none" in (
        capsys.readouterr().err
    )


def test_a_gate_bound_needs_a_policy_with_a_distance_gate(tmp_path, capsys):
    _pid_run(tmp_path, {"control_period": 0.5})
    with pytest.raises(SystemExit):
        main(
            [str(tmp_path), "--agent", "adaptive_pid", "--episodes", "1", "--gate-corridor", "0.9"]
        )
    assert "--gate-corridor needs SPNN runs with a distance gate" in capsys.readouterr().err


def test_an_arrival_gate_replays_the_runs_with_the_gate(tmp_path, capsys):
    """``--arrival-gate 5``: the run's env keywords plus arrival_gate=5 (a PID ends on its path,
    so the printed figure is that of the gated task, computed here alike)."""
    _pid_run(tmp_path, {"control_period": 1.0})
    argv = [str(tmp_path), "--agent", "adaptive_pid", "--episodes", "3", "--arrival-gate", "5"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    gated = evaluate_policy_on_task(
        "adaptive_pid",
        "rov_envs/PlanningStraight-v0",
        3,
        20000,
        env_kwargs={"control_period": 1.0, "layout": "scatter", "arrival_gate": 5.0},
    )
    ends = ", ".join(f"{k} {v}" for k, v in sorted(gated.end_reasons.items()))
    assert f"| 0 | {100 * gated.success_rate:.0f} % | {ends} |" in out


@pytest.mark.parametrize(
    ("option", "value", "message"),
    [
        (
            "--arrival-gate",
            "1",
            "--arrival-gate must be a number in [2, 100] (m from the target point, or none)",
        ),
        (
            "--arrival-gate",
            "far",
            "--arrival-gate must be a number in [2, 100] (m from the target point, or none)",
        ),
        ("--d-th", "0", "--d-th must be a number in (0, 100] (m), got '0'"),
    ],
)
def test_a_bad_replay_option_is_refused_by_name(tmp_path, capsys, option, value, message):
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), option, value])
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


def test_a_switch_distance_needs_a_policy_with_a_distance_gate(tmp_path, capsys):
    _pid_run(tmp_path, {"control_period": 0.5})
    with pytest.raises(SystemExit):
        main([str(tmp_path), "--agent", "adaptive_pid", "--episodes", "1", "--d-th", "10"])
    assert "--d-th needs SPNN runs with a distance gate" in capsys.readouterr().err
