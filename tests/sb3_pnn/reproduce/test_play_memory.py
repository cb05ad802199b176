"""spnn_play_memory: the study evaluates SPNN's hard-switch runs through SwitchMemory; their
training, validation checks and every other run stay as they were."""

from __future__ import annotations

import argparse
import json
from types import SimpleNamespace

import pytest

from sb3_pnn.progressive.gates import DistanceGate
from sb3_pnn.progressive.switch_memory import SwitchMemory
from sb3_pnn.reproduce.planning.plan import RunSpec, StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import OURS, parse_setup_changes
from sb3_pnn.reproduce.running.work import played
from sb3_pnn.reproduce.tools.replay import run_played


def _plan(changes: tuple = ()) -> dict[str, RunSpec]:
    """The tiny plan with ``changes``, its runs played without NoReversal (tested apart)."""
    unreversed = (("spnn_play_no_reversal", "neither"), ("pnn_play_no_reversal", "neither"))
    unreversed = (*unreversed, *changes)
    config = StudyConfig(budget_name="tiny", seeds=1, setup_changes=unreversed)
    return {s.run_id: s for s in build_plan(config)}


def test_only_spnns_hard_switch_runs_are_played_with_memory_and_train_as_before() -> None:
    default, memory = _plan((("spnn_play_memory", None),)), _plan((("spnn_play_memory", 10.0),))
    for run_id, spec in default.items():
        other = memory[run_id]
        remembered = run_id == "spnn-straight-s0"  # the sine path's gate is the soft one
        assert other.play == ({"switch_memory": 10.0} if remembered else {}), run_id
        assert (spec.config_hash() != other.config_hash()) == remembered, run_id
        # what trains and what keeps the policy is the same spec
        for name in ("sac_kwargs", "env_kwargs", "validation", "eval_tasks", "deps"):
            assert getattr(spec, name) == getattr(other, name), (run_id, name)
    assert "play" not in default["spnn-straight-s0"].to_dict()  # older runs keep their hash
    spec = memory["spnn-straight-s0"]
    assert RunSpec.from_dict(spec.to_dict()) == spec
    hard_sine = _plan((("spnn_play_memory", 10.0), ("spnn_gate_sine", None)))
    assert hard_sine["spnn-sine-s0"].play == {"switch_memory": 10.0}


def test_bad_memories_are_refused_by_name() -> None:
    assert parse_setup_changes(["spnn_play_memory=10"]) == {"spnn_play_memory": 10.0}
    for bad in (-1.0, 0.0, float("nan"), 500.0):
        with pytest.raises(ValueError, match=r"spnn_play_memory=.* is not allowed: expected a"):
            OURS.with_(spnn_play_memory=bad)
    with pytest.raises(ValueError, match=r"spnn_play_memory=10.0 is not allowed with spnn_switch"):
        OURS.with_(spnn_play_memory=10.0, spnn_switch_memory=5.0)


def test_played_wraps_the_trained_model_in_the_named_memory() -> None:
    """The study's evaluation plays the model through SwitchMemory (its behaviour is tested in
    tests/sb3_pnn/progressive/test_switch_memory.py), or as trained when no memory is named."""
    gate = DistanceGate("hard", d_th=12.5, sonar_range=25.0)
    model = SimpleNamespace(policy=SimpleNamespace(actor=SimpleNamespace(gate=gate)))
    policy = played(_plan((("spnn_play_memory", 10.0),))["spnn-straight-s0"].play, model)
    assert isinstance(policy, SwitchMemory)
    assert (policy.model, policy.hysteresis, policy.d_th) == (model, 10.0, 12.5)
    assert played(_plan((("spnn_play_memory", None),))["spnn-straight-s0"].play, model) is model


def test_the_tools_replay_a_run_as_the_study_evaluated_it(tmp_path) -> None:
    """tools.drawn_layouts and tools.fresh_route play a run through the memory its spec names;
    runs made before ``play`` existed play as trained."""
    gate = DistanceGate("hard", d_th=12.5, sonar_range=25.0)
    model = SimpleNamespace(policy=SimpleNamespace(actor=SimpleNamespace(gate=gate)))
    spec = _plan((("spnn_play_memory", 10.0),))["spnn-straight-s0"]
    (tmp_path / "manifest.json").write_text(json.dumps({"spec": spec.to_dict()}))
    policy = run_played(argparse.ArgumentParser(), tmp_path, model)
    assert isinstance(policy, SwitchMemory) and policy.hysteresis == 10.0
    (tmp_path / "manifest.json").write_text(json.dumps({"spec": {"run_id": "spnn-straight-s0"}}))
    assert run_played(argparse.ArgumentParser(), tmp_path, model) is model
