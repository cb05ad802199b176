"""tools.spnn_switch_distance: each run replayed as the study evaluated it (its own env keywords
and play), with only the switch asked changed; bad arguments and missing runs stop with a
message."""

from __future__ import annotations

import json
from types import SimpleNamespace

import pytest

from sb3_pnn.evaluation.no_reversal import NoReversal
from sb3_pnn.progressive.gates import DistanceGate
from sb3_pnn.progressive.switch_memory import SwitchMemory
from sb3_pnn.reproduce.tools import spnn_switch_distance
from sb3_pnn.reproduce.tools.spnn_switch_distance import main

STRAIGHT = "rov_envs/PlanningStraight-v0"
DENSE = "rov_envs/PlanningStraightDense-v0"


def _study(tmp_path, play):
    """A study folder with one SPNN run evaluated on its task, the path and a new layout."""
    run = tmp_path / "runs" / "spnn-straight-s0"
    run.mkdir(parents=True)
    own = {"control_period": 1.0, "goal_distance": 25.0}
    evals = {
        "original": {"env_id": STRAIGHT, "env_kwargs": own},
        "path_following": {"env_id": STRAIGHT, "env_kwargs": {**own, "obstacles": []}},
        "dense": {"env_id": DENSE, "env_kwargs": own},
    }
    (run / "eval.json").write_text(json.dumps(evals))
    (run / "manifest.json").write_text(json.dumps({"spec": {"play": play}}))
    return own


@pytest.fixture
def replayed(monkeypatch):
    """Replace the model and the episodes: record what each call would play, and where."""
    gate = DistanceGate("hard", d_th=12.5, sonar_range=25.0)
    model = SimpleNamespace(policy=SimpleNamespace(actor=SimpleNamespace(gate=gate)))
    calls = []

    def fake_evaluate(policy, env_id, n_episodes, seed, env_kwargs):
        memory = policy.wrapped if isinstance(policy, NoReversal) else policy
        calls.append(
            {
                "env_id": env_id,
                "env_kwargs": env_kwargs,
                "seed": seed,
                "no_reversal": isinstance(policy, NoReversal),
                "memory": memory.hysteresis if isinstance(memory, SwitchMemory) else None,
                "d_th": memory.d_th if isinstance(memory, SwitchMemory) else gate.d_th,
            }
        )
        return SimpleNamespace(
            success_rate=1.0,
            mean_return=0.0,
            mean_abs_cross_track=0.0,
            mean_abs_heading_error=0.0,
            end_reasons={"success": n_episodes},
        )

    monkeypatch.setattr(spnn_switch_distance, "run_model", lambda parser, run: model)
    monkeypatch.setattr(spnn_switch_distance, "evaluate_policy_on_task", fake_evaluate)
    return calls


def test_runs_are_replayed_with_their_own_env_keywords_and_play(tmp_path, replayed) -> None:
    """Without --hysteresis a run plays through the memory and NoReversal its spec names, on its
    own task and the new layouts it was evaluated on (not the path without obstacles), with the
    env keywords of that evaluation, on the validation seeds."""
    own = _study(tmp_path, {"switch_memory": 10.0, "no_reversal": True})
    assert main([str(tmp_path), "--seeds", "0", "--d-th", "8", "--episodes", "2"]) == 0
    assert [(c["env_id"], c["env_kwargs"]) for c in replayed] == [(STRAIGHT, own), (DENSE, own)]
    for call in replayed:
        assert (call["seed"], call["no_reversal"], call["memory"], call["d_th"]) == (
            20000,
            True,
            10.0,
            8.0,
        )


def test_hysteresis_replaces_the_runs_memory_and_keeps_its_no_reversal(tmp_path, replayed):
    _study(tmp_path, {"switch_memory": 10.0, "no_reversal": True})
    argv = [str(tmp_path), "--seeds", "0", "--d-th", "12.5", "--hysteresis", "0", "4"]
    assert main([*argv, "--drawn-layouts", "--episodes", "2"]) == 0
    assert [c["memory"] for c in replayed] == [None, None, 4.0, 4.0]
    assert all(c["no_reversal"] for c in replayed)
    assert [c["env_kwargs"].get("layout") for c in replayed] == [None, "scatter"] * 2


def test_a_run_played_as_trained_stays_unwrapped(tmp_path, replayed) -> None:
    _study(tmp_path, {})
    assert main([str(tmp_path), "--seeds", "0", "--d-th", "12.5", "--episodes", "1"]) == 0
    assert {(c["no_reversal"], c["memory"]) for c in replayed} == {(False, None)}


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--hysteresis", "-1"], "argument --hysteresis: -1 is not allowed"),
        (["--hysteresis", "inf"], "argument --hysteresis: inf is not allowed"),
        (["--hysteresis", "far"], "argument --hysteresis: far is not allowed"),
        (["--d-th", "nan"], "--d-th nan is not allowed"),
        (["--seeds", "-2"], "--seeds [-2] is not allowed"),
        (["--episodes", "0"], "--episodes 0 is not allowed"),
    ],
)
def test_bad_arguments_stop_with_a_message(tmp_path, capsys, args, message) -> None:
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), *args])
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


def test_a_missing_run_stops_with_a_message(tmp_path, capsys) -> None:
    with pytest.raises(SystemExit):
        main([str(tmp_path), "--seeds", "0"])
    assert "spnn-straight-s0/eval.json does not exist" in capsys.readouterr().err
