"""The factors ``progress_along`` and ``planning_progress_along`` reach the runs they name."""

from __future__ import annotations

import pytest

from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import OURS, parse_setup_changes


def _plan(*changes: str) -> dict:
    config = StudyConfig(seeds=1, setup_changes=tuple(parse_setup_changes(list(changes)).items()))
    return {run.run_id: run for run in build_plan(config)}


def _along(run) -> set:
    """progress_along as the run trains (a PID baseline does not) and as each of its
    evaluation tasks reads it."""
    kwargs = [task[2] for task in run.eval_tasks]
    if run.kind != "baseline":
        kwargs.append(run.env_kwargs)
    return {k.get("progress_along") for k in kwargs}


def test_the_default_names_no_progress_direction() -> None:
    """Named only off the tangent, so that every run keeps its hash."""
    assert all(_along(run) == {None} for run in _plan().values() if run.env_id)


def test_planning_progress_along_reaches_the_learners_alone() -> None:
    default, course = _plan(), _plan("planning_progress_along=course")
    for run_id, run in course.items():
        learner = run.kind == "transfer"
        assert _along(run) == ({"course"} if learner else _along(default[run_id]))
        assert (run.config_hash() != default[run_id].config_hash()) == learner


def test_progress_along_reaches_every_task_and_the_planning_factor_can_put_it_back() -> None:
    course = _plan("progress_along=course")
    assert all(_along(run) == {"course"} for run in course.values() if run.env_id)
    back = _plan("progress_along=course", "planning_progress_along=path")
    for run in back.values():
        if run.env_id:
            assert _along(run) == ({"path"} if run.kind == "transfer" else {"course"})


@pytest.mark.parametrize("name", ["progress_along", "planning_progress_along"])
def test_a_bad_direction_is_refused_with_its_name(name) -> None:
    with pytest.raises(ValueError, match=f"{name}='los' is not allowed: expected 'path'"):
        OURS.with_(**{name: "los"})


def test_pf_progress_weighted_reaches_the_path_following_columns_alone() -> None:
    """Off: the path-following columns train and are evaluated on eq. 18/19 as written; every
    other run keeps its hash (the learners' and the avoidance column's reward is unchanged)."""
    default, unweighted = _plan(), _plan("pf_progress_weighted=off")
    for run_id, run in unweighted.items():
        column = run_id.startswith("prior-pf_")
        kwargs = [task[2] for task in run.eval_tasks] + ([run.env_kwargs] if run.env_kwargs else [])
        assert {k.get("progress_weighted") for k in kwargs} == ({False} if column else {True})
        assert (run.config_hash() != default[run_id].config_hash()) == column
    same = _plan("pf_progress_weighted=on")  # as progress_weighted: named nowhere
    assert {r: s.config_hash() for r, s in same.items()} == {
        r: s.config_hash() for r, s in default.items()
    }


@pytest.mark.parametrize("text", ["3", "maybe"])
def test_pf_progress_weighted_takes_on_off_or_null(text) -> None:
    with pytest.raises(ValueError, match="pf_progress_weighted=off \\(on / off, or null\\)"):
        parse_setup_changes([f"pf_progress_weighted={text}"])
    assert parse_setup_changes(["pf_progress_weighted=null"]) == {"pf_progress_weighted": None}
