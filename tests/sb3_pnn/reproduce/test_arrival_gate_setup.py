"""The factor ``planning_arrival_gate`` reaches the planning tasks' runs and nothing else."""

from __future__ import annotations

import pytest

from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import OURS, parse_setup_changes
from sb3_pnn.reproduce.tools.replay import gated


def _plan(*changes: str) -> dict:
    config = StudyConfig(seeds=1, setup_changes=tuple(parse_setup_changes(list(changes)).items()))
    return {run.run_id: run for run in build_plan(config)}


def _gates(run) -> set:
    """arrival_gate as the run trains (a baseline does not) and as each evaluation reads it."""
    kwargs = [task[2] for task in run.eval_tasks]
    if run.kind != "baseline":
        kwargs.append(run.env_kwargs)
    return {k.get("arrival_gate") for k in kwargs}


def test_the_default_names_no_gate_and_keeps_every_hash() -> None:
    default = _plan()
    assert all(_gates(run) == {None} for run in default.values() if run.env_id)
    unchanged = _plan("planning_arrival_gate=0")
    assert {k: r.config_hash() for k, r in unchanged.items()} == {
        k: r.config_hash() for k, r in default.items()
    }


def test_the_gate_reaches_the_learners_and_the_baselines_evaluation_alone() -> None:
    default, gate = _plan(), _plan("planning_arrival_gate=5")
    for run_id, run in gate.items():
        reached = run.kind in ("transfer", "baseline")
        assert _gates(run) == ({5.0} if reached else {None}), run_id
        assert (run.config_hash() != default[run_id].config_hash()) == reached, run_id


@pytest.mark.parametrize("bad", [-1.0, 1.0, 101.0, True])
def test_a_bad_gate_is_refused_with_its_value(bad) -> None:
    with pytest.raises(ValueError, match=r"planning_arrival_gate=.* is not allowed: expected 0"):
        OURS.with_(planning_arrival_gate=bad)


def test_the_tools_replay_with_the_gate_or_as_evaluated() -> None:
    kwargs = {"control_period": 1.0}
    assert gated(kwargs, None) == kwargs
    assert gated(kwargs, 5.0) == {"control_period": 1.0, "arrival_gate": 5.0}
    assert kwargs == {"control_period": 1.0}  # not changed in place
    assert gated({"control_period": 1.0, "arrival_gate": 5.0}, "none") == kwargs


def test_the_path_following_gate_reaches_the_path_following_columns_alone() -> None:
    default, gate = _plan(), _plan("pf_arrival_gate=5")
    for run_id, run in gate.items():
        column = run_id.startswith("prior-pf_")
        assert _gates(run) == ({5.0} if column else {None}), run_id
        if not run.deps:  # a learner's own hash does not read its columns' (the store does)
            assert (run.config_hash() != default[run_id].config_hash()) == column, run_id


def test_a_bad_path_following_gate_is_refused_with_its_value() -> None:
    with pytest.raises(ValueError, match=r"pf_arrival_gate=150.0 is not allowed: expected 0"):
        OURS.with_(pf_arrival_gate=150.0)
