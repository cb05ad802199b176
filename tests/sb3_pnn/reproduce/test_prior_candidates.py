"""Source columns chosen among candidates (``prior_candidates``): the plan, the choice, a study."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import OURS, PAPER
from sb3_pnn.reproduce.running.work import run_work


def _plan(k: int, **kwargs):
    kwargs.setdefault("prior_per_seed", False)  # one shared set unless a test asks for more
    config = StudyConfig(budget_name="tiny", setup_changes=(("prior_candidates", k),), **kwargs)
    return {s.run_id: s for s in build_plan(config)}


@pytest.mark.parametrize("prior_per_seed", [True, False])
def test_one_candidate_plans_the_study_as_before(prior_per_seed) -> None:
    config = StudyConfig(budget_name="tiny", seeds=2, prior_per_seed=prior_per_seed)
    before = {s.run_id: s for s in build_plan(config)}
    after = _plan(1, seeds=2, prior_per_seed=prior_per_seed)
    assert {i: s.config_hash() for i, s in after.items()} == {
        i: s.config_hash() for i, s in before.items()
    }


def test_each_column_is_trained_k_times_and_the_transfer_runs_read_the_choice() -> None:
    plan = _plan(3, seeds=2)
    plain = {
        s.run_id: s
        for s in build_plan(StudyConfig(budget_name="tiny", seeds=2, prior_per_seed=False))
    }
    for name in ("pf_straight", "pf_sine", "oa"):
        candidates = [f"prior-{name}-s{j}" for j in range(3)]
        for j, rid in enumerate(candidates):  # the same runs as per-seed columns of seeds 0-2
            assert plan[rid].kind == "prior" and plan[rid].seed == j
        select = plan[f"prior-{name}-best3-s0"]
        assert select.kind == "select" and select.deps == tuple(candidates)
        assert plain["prior-" + name + "-s0"].config_hash() == plan[candidates[0]].config_hash()
    order = list(plan)
    for spec in plan.values():
        assert all(order.index(d) < order.index(spec.run_id) for d in spec.deps)
    assert plan["spnn-sine-s1"].deps == ("prior-pf_sine-best3-s0", "prior-oa-best3-s0")
    assert plan["pnn-straight-s0"].deps == ("prior-pf_straight-best3-s0", "prior-oa-best3-s0")
    assert plan["sac_single-sine-s0"].deps == ()
    # with a column set per seed, seed s's candidates are seeds 3s, 3s + 1, 3s + 2
    per_seed = _plan(3, seeds=2, prior_per_seed=True)
    assert per_seed["prior-oa-best3-s1"].deps == ("prior-oa-s3", "prior-oa-s4", "prior-oa-s5")
    assert per_seed["spnn-straight-s1"].deps[1] == "prior-oa-best3-s1"


def test_the_straight_path_following_column_alone_can_be_the_best_of_two() -> None:
    """prior_candidates_pf_straight / prior_keep_best_by_pf_straight reach that column and the
    learners of the straight path; every other run keeps its spec (and hash)."""
    changes = (
        ("prior_candidates_pf_straight", 2),
        ("prior_keep_best_by_pf_straight", "discounted"),
    )
    plan = {s.run_id: s for s in build_plan(StudyConfig(seeds=2, setup_changes=changes))}
    default = {s.run_id: s for s in build_plan(StudyConfig(seeds=2))}
    for s in (1, 2, 3):  # set 1's candidates are seeds 2 and 3, ranked by the discounted return
        assert plan[f"prior-pf_straight-s{s}"].validation["rank_by"] == "discounted"
    assert plan["prior-pf_straight-best2-s1"].deps == (
        "prior-pf_straight-s2",
        "prior-pf_straight-s3",
    )
    assert plan["spnn-straight-s1"].deps == ("prior-pf_straight-best2-s1", "prior-oa-s1")
    assert plan["pnn-straight-s0"].deps == ("prior-pf_straight-best2-s0", "prior-oa-s0")
    assert plan["sac_multi-straight-s1"].deps == ("prior-pf_straight-best2-s1",)
    reached = {i for i, spec in plan.items() if "straight" in i and spec.kind != "baseline"}
    reached -= {"sac_single-straight-s0", "sac_single-straight-s1"}
    for run_id, spec in plan.items():
        if run_id not in reached:
            assert spec.config_hash() == default[run_id].config_hash(), run_id
    assert not [i for i in plan if "best2" in i and "pf_straight" not in i]
    # None falls back to the other columns' values, so both refinements at 1 / "return" are
    # the default study
    same = OURS.with_(prior_candidates_pf_straight=1, prior_keep_best_by_pf_straight="return")
    assert same.column_candidates("pf_straight") == 1
    assert OURS.with_(prior_candidates=3).column_candidates("pf_straight") == 3
    assert OURS.with_(prior_candidates_pf_straight=2).column_candidates("oa") == 1
    with pytest.raises(ValueError, match="prior_candidates_pf_straight=2 is not allowed with keep"):
        PAPER.with_(prior_candidates_pf_straight=2)
    with pytest.raises(ValueError, match="prior_candidates_pf_straight=0 is not allowed: expected"):
        OURS.with_(prior_candidates_pf_straight=0)
    with pytest.raises(ValueError, match="prior_keep_best_by_pf_straight='gap' is not allowed"):
        OURS.with_(prior_keep_best_by_pf_straight="gap")


def test_candidates_need_validation_checks() -> None:
    with pytest.raises(ValueError, match="prior_candidates=3 is not allowed with keep_best off"):
        PAPER.with_(prior_candidates=3)
    with pytest.raises(ValueError, match="prior_candidates=0 is not allowed"):
        OURS.with_(prior_candidates=0)


def _candidate(folder, history, tag, kept):
    """A finished candidate whose callback kept the check at episode ``kept``."""
    folder.mkdir()
    (folder / "validation.json").write_text(json.dumps({"history": history, "best_episode": kept}))
    (folder / "model.zip").write_text(tag)
    (folder / "eval.json").write_text(json.dumps({"own": tag}))


def _check(episode, success, ret):
    return {"episode": episode, "success_rate": success, "mean_return": ret}


def test_the_candidate_with_the_best_kept_check_is_copied(tmp_path) -> None:
    spec = _plan(3, seeds=1)["prior-oa-best3-s0"]
    deps = {d: tmp_path / d for d in spec.deps}
    # kept checks: (0.9, 500), (1.0, 210), (1.0, 230): success first, then return
    _candidate(deps[spec.deps[0]], [_check(25, 0.9, 500.0), _check(50, 0.5, 600.0)], "a", 25)
    _candidate(deps[spec.deps[1]], [_check(25, 1.0, 210.0), _check(50, 0.8, 400.0)], "b", 25)
    _candidate(deps[spec.deps[2]], [_check(25, 0.2, 900.0), _check(50, 1.0, 230.0)], "c", 50)
    out = tmp_path / "out"
    out.mkdir()
    info = run_work(spec, out, deps)
    assert info["chosen"] == "prior-oa-s2"
    assert (out / "model.zip").read_text() == "c"
    assert json.loads((out / "eval.json").read_text()) == {"own": "c"}
    table = json.loads((out / "selection.json").read_text())
    assert table["chosen"] == "prior-oa-s2"
    assert table["candidates"]["prior-oa-s0"] == {"success_rate": 0.9, "mean_return": 500.0}


def test_candidates_kept_by_the_discounted_return_are_ranked_and_recorded_by_it(tmp_path) -> None:
    spec = _plan(2, seeds=1)["prior-pf_straight-best2-s0"]
    deps = {d: tmp_path / d for d in spec.deps}
    # the first candidate has the larger return, the second the larger discounted return
    for dep, tag, ret, disc in ((spec.deps[0], "a", 390.0, 60.0), (spec.deps[1], "b", 320.0, 80.0)):
        check = {**_check(50, 1.0, ret), "mean_discounted_return": disc}
        _candidate(deps[dep], [check], tag, 50)
        record = json.loads((deps[dep] / "validation.json").read_text())
        (deps[dep] / "validation.json").write_text(json.dumps({**record, "rank_by": "discounted"}))
    out = tmp_path / "out"
    out.mkdir()
    assert run_work(spec, out, deps)["chosen"] == "prior-pf_straight-s1"
    table = json.loads((out / "selection.json").read_text())["candidates"]
    assert table["prior-pf_straight-s0"] == {"success_rate": 1.0, "mean_discounted_return": 60.0}
    assert table["prior-pf_straight-s1"] == {"success_rate": 1.0, "mean_discounted_return": 80.0}


def test_ties_and_budgets_shorter_than_a_check_go_to_the_first_candidate(tmp_path) -> None:
    spec = _plan(2, seeds=1)["prior-pf_sine-best2-s0"]
    deps = {d: tmp_path / d for d in spec.deps}
    for tag, dep in zip("ab", spec.deps, strict=True):
        _candidate(deps[dep], [_check(25, 1.0, 300.0)], tag, 25)
    out = tmp_path / "out"
    out.mkdir()
    assert run_work(spec, out, deps)["chosen"] == "prior-pf_sine-s0"
    # a candidate that never validated ranks below one that did; none validated: the first
    (deps[spec.deps[0]] / "validation.json").write_text(
        json.dumps({"history": [], "best_episode": None})
    )
    assert run_work(spec, out, deps)["chosen"] == "prior-pf_sine-s1"
    (deps[spec.deps[1]] / "validation.json").write_text(
        json.dumps({"history": [], "best_episode": None})
    )
    assert run_work(spec, out, deps)["chosen"] == "prior-pf_sine-s0"
    table = json.loads((out / "selection.json").read_text())["candidates"]
    assert table == {"prior-pf_sine-s0": None, "prior-pf_sine-s1": None}
    (deps[spec.deps[1]] / "validation.json").unlink()
    with pytest.raises(ValueError, match="has no validation.json"):
        run_work(spec, out, deps)


@pytest.mark.slow
def test_tiny_real_study_with_two_candidates(tmp_path) -> None:
    out = tmp_path / "study"
    proc = subprocess.run(
        [sys.executable, "-m", "sb3_pnn.reproduce", "--tiny", "--seeds", "1", "--jobs", "2",
         "--agents", "spnn", "--set", "prior_candidates=2", "--shared-priors", "--no-progress",
         "--out", str(out)],
        capture_output=True, text=True, timeout=240,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr
    report = (out / "report.md").read_text()
    assert "failed: 0" in report
    chosen = json.loads((out / "runs" / "prior-oa-best2-s0" / "selection.json").read_text())
    assert chosen["chosen"] in ("prior-oa-s0", "prior-oa-s1")
    assert "each column the best of 2 training runs" in report
    assert "not the draw of these columns" in report  # one shared set: what the intervals cover
    assert f"prior-oa-best2-s0 = {chosen['chosen']}" in report
    copied = (out / "runs" / "prior-oa-best2-s0" / "model.zip").read_bytes()
    assert copied == (out / "runs" / chosen["chosen"] / "model.zip").read_bytes()
    assert (out / "runs" / "spnn-straight-s0" / "model.zip").is_file()


def test_the_report_names_which_columns_were_chosen_among_candidates() -> None:
    from types import SimpleNamespace

    from sb3_pnn.reproduce.reporting.report import _selection_text

    def run(run_id, chosen):
        return SimpleNamespace(spec=SimpleNamespace(run_id=run_id), manifest={"chosen": chosen})

    selects = [run("prior-pf_straight-best2-s0", "prior-pf_straight-s1")]
    results = SimpleNamespace(select=lambda kind: selects if kind == "select" else [])
    assert _selection_text(results, OURS) == ""
    text = _selection_text(results, OURS.with_(prior_candidates_pf_straight=2))
    assert text == (
        ", the pf_straight column the best of 2 training runs on validation episodes of its own "
        "task (prior-pf_straight-best2-s0 = prior-pf_straight-s1)"
    )
    assert "each column the best of 3" in _selection_text(results, OURS.with_(prior_candidates=3))
