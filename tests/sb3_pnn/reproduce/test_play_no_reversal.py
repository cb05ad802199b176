"""spnn_play_no_reversal / pnn_play_no_reversal: the study evaluates SPNN's / PNN's runs on
the named paths through NoReversal (after the switch memory where one is named); training,
validation checks and every other run stay as they were."""

from __future__ import annotations

import argparse
import json
from types import SimpleNamespace

import pytest

from sb3_pnn.evaluation import NoReversal
from sb3_pnn.progressive.gates import DistanceGate
from sb3_pnn.progressive.switch_memory import SwitchMemory
from sb3_pnn.reproduce.planning.plan import RunSpec, StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import OURS, PAPER, parse_setup_changes
from sb3_pnn.reproduce.running.work import played
from sb3_pnn.reproduce.tools.replay import add_no_reversal_option, no_reversal_of, run_played


def _plan(changes: tuple = ()) -> dict[str, RunSpec]:
    config = StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes)
    return {s.run_id: s for s in build_plan(config)}


def test_the_default_plays_spnns_sine_runs_without_reversals_and_trains_them_as_before() -> None:
    assert (OURS.spnn_play_no_reversal, PAPER.spnn_play_no_reversal) == ("sine", "neither")
    default, off = _plan(), _plan((("spnn_play_no_reversal", "neither"),))
    for run_id, spec in default.items():
        other = off[run_id]
        reversing = run_id == "spnn-sine-s0"
        assert (spec.config_hash() != other.config_hash()) == reversing, run_id
        for name in ("sac_kwargs", "env_kwargs", "validation", "eval_tasks", "deps"):
            assert getattr(spec, name) == getattr(other, name), (run_id, name)
    assert default["spnn-sine-s0"].play == {"no_reversal": True}
    assert off["spnn-sine-s0"].play == {}
    assert default["spnn-straight-s0"].play == {"switch_memory": 10.0}  # its own play factor
    both = _plan((("spnn_play_no_reversal", "both"),))
    assert both["spnn-straight-s0"].play == {"switch_memory": 10.0, "no_reversal": True}
    others = {k: s.play for k, s in both.items() if not k.startswith("spnn-")}
    assert others == {k: default[k].play for k in others}  # PNN's sine runs: its own factor
    spec = default["spnn-sine-s0"]
    assert RunSpec.from_dict(spec.to_dict()) == spec


def test_bad_values_are_refused_by_name() -> None:
    assert parse_setup_changes(["spnn_play_no_reversal=true"]) == {"spnn_play_no_reversal": True}
    assert OURS.with_(spnn_play_no_reversal=False).spnn_play_no_reversal == "neither"
    with pytest.raises(ValueError, match=r"spnn_play_no_reversal='curvy' is not allowed"):
        OURS.with_(spnn_play_no_reversal="curvy")


def test_played_and_the_tools_wrap_the_memory_then_no_reversal(tmp_path) -> None:
    gate = DistanceGate("hard", d_th=12.5, sonar_range=25.0)
    model = SimpleNamespace(policy=SimpleNamespace(actor=SimpleNamespace(gate=gate)))
    policy = played({"switch_memory": 10.0, "no_reversal": True}, model)
    assert isinstance(policy, NoReversal) and isinstance(policy.wrapped, SwitchMemory)
    assert policy.wrapped.model is model
    alone = played({"no_reversal": True}, model)
    assert isinstance(alone, NoReversal) and alone.wrapped is model
    assert played({}, model) is model
    spec = _plan()["spnn-sine-s0"]
    (tmp_path / "manifest.json").write_text(json.dumps({"spec": spec.to_dict()}))
    replayed = run_played(argparse.ArgumentParser(), tmp_path, model)
    assert isinstance(replayed, NoReversal) and replayed.wrapped is model
    # the tools' --no-reversal replays a run with or without it, whatever its spec named
    assert run_played(argparse.ArgumentParser(), tmp_path, model, no_reversal=False) is model
    straight = _plan()["spnn-straight-s0"]
    (tmp_path / "manifest.json").write_text(json.dumps({"spec": straight.to_dict()}))
    forced = run_played(argparse.ArgumentParser(), tmp_path, model, no_reversal=True)
    assert isinstance(forced, NoReversal) and isinstance(forced.wrapped, SwitchMemory)
    parser = argparse.ArgumentParser()
    add_no_reversal_option(parser)
    assert [no_reversal_of(parser.parse_args(a)) for a in ([], ["--no-reversal", "on"])] == [
        None,
        True,
    ]
    assert no_reversal_of(parser.parse_args(["--no-reversal", "off"])) is False


def test_learners_play_no_reversal_plays_every_learner_alike_on_its_paths() -> None:
    """Figure 20's learners played alike: every learner's sine runs through NoReversal, the
    straight runs, the baselines and the source columns as before; training specs unchanged."""
    default = _plan()
    alike = _plan((("learners_play_no_reversal", "sine"),))
    learners = {"sac_single-sine-s0", "sac_multi-sine-s0"}  # PNN and SPNN already play so
    for run_id, spec in default.items():
        other = alike[run_id]
        assert (spec.config_hash() != other.config_hash()) == (run_id in learners), run_id
        for name in ("sac_kwargs", "env_kwargs", "validation", "eval_tasks", "deps"):
            assert getattr(spec, name) == getattr(other, name), (run_id, name)
    played_so = learners | {"spnn-sine-s0", "pnn-sine-s0"}
    assert all(alike[r].play == {"no_reversal": True} for r in played_so)
    assert PAPER.learners_play_no_reversal == OURS.learners_play_no_reversal == "neither"


def test_pnn_play_no_reversal_plays_pnns_sine_runs_so_and_trains_them_as_before() -> None:
    """PNN's own play factor: on by default on the sinusoid (docs/ablation section 67), off in
    the paper's set-up; only PNN's runs on the named paths change, and only in ``play``."""
    assert (OURS.pnn_play_no_reversal, PAPER.pnn_play_no_reversal) == ("sine", "neither")
    default, off = _plan(), _plan((("pnn_play_no_reversal", "neither"),))
    for run_id, spec in default.items():
        other = off[run_id]
        assert (spec.config_hash() != other.config_hash()) == (run_id == "pnn-sine-s0"), run_id
        for name in ("sac_kwargs", "env_kwargs", "validation", "eval_tasks", "deps"):
            assert getattr(spec, name) == getattr(other, name), (run_id, name)
    assert (default["pnn-sine-s0"].play, off["pnn-sine-s0"].play) == ({"no_reversal": True}, {})
    both = _plan((("pnn_play_no_reversal", "both"),))
    assert both["pnn-straight-s0"].play == {"no_reversal": True}
    assert both["spnn-straight-s0"].play == {"switch_memory": 10.0}  # SPNN's own factors
    with pytest.raises(ValueError, match=r"pnn_play_no_reversal='curvy' is not allowed"):
        OURS.with_(pnn_play_no_reversal="curvy")
