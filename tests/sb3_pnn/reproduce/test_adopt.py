"""Adopting finished runs of an older study folder (sb3_pnn.reproduce.running.adopt)."""

from __future__ import annotations

import json

import pytest
from reproduce_helpers import fake_work

from sb3_pnn.reproduce.planning.plan import RunSpec, StudyConfig, build_plan
from sb3_pnn.reproduce.running.adopt import adopt_runs, legacy_hash, main
from sb3_pnn.reproduce.running.store import RunStore


def _old_study(path, plan, stamp) -> RunStore:
    """A study folder whose runs were committed with ``stamp(spec)`` as their hash."""
    store = RunStore(path)
    store.open()
    for spec in plan:
        tmp = store.begin(spec)
        (tmp / "model.zip").write_text(spec.run_id)
        store.commit(spec, tmp, {"wall_s": 1.0})
        manifest = store.manifest(spec.run_id)
        manifest["config_hash"] = stamp(spec)
        (store.run_dir(spec.run_id) / "manifest.json").write_text(json.dumps(manifest))
    store.close()
    return store


def test_legacy_runs_with_the_same_spec_are_adopted_and_marked(tmp_path) -> None:
    from rov_envs.sim.tasks import TASKS_REVISION

    old_plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    _old_study(tmp_path / "old", old_plan, legacy_hash)
    new = RunStore(tmp_path / "new")
    new.open()
    plan = build_plan(StudyConfig(budget_name="tiny", seeds=2))
    adopted, skipped = adopt_runs(tmp_path / "old", new, plan, TASKS_REVISION)
    assert adopted == [s.run_id for s in old_plan]
    assert set(skipped.values()) == {"not in the old folder"}  # the seed-1 runs
    for spec in old_plan:
        assert new.is_done(spec)  # today's hash: the study will reuse it
        manifest = new.manifest(spec.run_id)
        assert manifest["adopted"]["stored_hash"] == legacy_hash(spec)
        assert manifest["adopted"]["stated_tasks_revision"] == TASKS_REVISION
        assert (new.run_dir(spec.run_id) / "model.zip").read_text() == spec.run_id
    again, skipped = adopt_runs(tmp_path / "old", new, plan, TASKS_REVISION)
    assert again == [] and skipped[old_plan[0].run_id] == "already in the new folder"
    new.close()


def test_other_specs_hashes_and_revisions_are_refused(tmp_path) -> None:
    from rov_envs.sim.tasks import TASKS_REVISION

    old_plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    _old_study(tmp_path / "old", old_plan, lambda spec: "0123456789abcdef")
    new = RunStore(tmp_path / "new")
    new.open()
    adopted, skipped = adopt_runs(tmp_path / "old", new, old_plan, TASKS_REVISION)
    assert adopted == [] and all("neither the legacy" in why for why in skipped.values())
    other_budget = build_plan(StudyConfig(budget_name="quick", seeds=1))
    adopted, skipped = adopt_runs(tmp_path / "old", new, other_budget, TASKS_REVISION)
    assert adopted == [] and "spec differs in episodes" in skipped[other_budget[0].run_id]
    with pytest.raises(ValueError, match=f"revision {TASKS_REVISION}"):
        adopt_runs(tmp_path / "old", new, old_plan, TASKS_REVISION - 1)
    new.close()


def test_runs_whose_prior_is_planned_differently_are_not_adopted(tmp_path) -> None:
    """A transfer run's hash names its priors by run id only: with the avoidance column's task
    changed, the SPNN and PNN runs (which read it) must be retrained with it, the others not."""
    from rov_envs.sim.tasks import TASKS_REVISION
    from sb3_pnn.reproduce.planning.setups import OURS

    other = "avoidance" if OURS.oa_layout == "scatter" else "scatter"

    old_plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    _old_study(tmp_path / "old", old_plan, lambda spec: spec.config_hash())
    new = RunStore(tmp_path / "new")
    new.open()
    plan = build_plan(
        StudyConfig(budget_name="tiny", seeds=1, setup_changes=(("oa_layout", other),))
    )
    adopted, skipped = adopt_runs(tmp_path / "old", new, plan, TASKS_REVISION)
    readers = {s.run_id for s in plan if "prior-oa-s0" in s.deps}
    assert readers and {"spnn-straight-s0", "spnn-sine-s0", "pnn-straight-s0"} <= readers
    assert skipped["prior-oa-s0"].startswith("spec differs in")
    for run_id in readers:
        why = skipped[run_id]
        assert why.startswith("its prior prior-oa-s0 would not be adopted (spec differs")
    assert set(adopted) == {s.run_id for s in plan} - readers - {"prior-oa-s0"}
    assert "sac_multi-straight-s0" in adopted and "prior-pf_straight-s0" in adopted
    new.close()


def test_command_line_adopts_and_names_bad_folders(tmp_path, capsys) -> None:
    from rov_envs.sim.tasks import TASKS_REVISION

    old_plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    _old_study(tmp_path / "old", old_plan, legacy_hash)
    rev = str(TASKS_REVISION)
    args = ["--from", str(tmp_path / "old"), "--made-with-tasks-revision", rev, "--"]
    assert main([*args, "--tiny", "--seeds", "1", "--out", str(tmp_path / "new")]) == 0
    assert f"adopted {len(old_plan)} run(s)" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["--from", str(tmp_path / "nowhere"), "--made-with-tasks-revision", rev, "--"])
    assert "is not a study folder" in capsys.readouterr().err
    wrong = ["--from", str(tmp_path / "old"), "--made-with-tasks-revision", str(TASKS_REVISION + 1)]
    with pytest.raises(SystemExit):
        main([*wrong, "--", "--tiny", "--out", str(tmp_path / "other")])
    assert f"today's task definitions are revision {TASKS_REVISION}" in capsys.readouterr().err
    assert not (tmp_path / "other").exists()  # refused before the folder is made


def test_report_names_the_adopted_runs(tmp_path, capsys) -> None:
    from rov_envs.sim.tasks import TASKS_REVISION
    from sb3_pnn.reproduce.cli import main as study_main

    study = ["--tiny", "--seeds", "1", "--eval-episodes", "10", "--jobs", "1", "--no-progress"]
    old = tmp_path / "old"
    assert study_main([*study, "--out", str(old)], work=fake_work) == 0
    for manifest in old.glob("runs/*/manifest.json"):  # made before the revision was hashed
        data = json.loads(manifest.read_text())
        data["config_hash"] = legacy_hash(RunSpec.from_dict(data["spec"]))
        manifest.write_text(json.dumps(data))
    new = tmp_path / "new"
    args = ["--from", str(old), "--made-with-tasks-revision", str(TASKS_REVISION), "--"]
    assert main([*args, *study, "--out", str(new)]) == 0
    assert study_main([*study, "--report-only", "--out", str(new)], work=fake_work) == 0
    report = (new / "report.md").read_text()
    assert "adopted unchanged from ../old " in report  # relative: no machine's absolute path
    assert str(tmp_path) not in report.split("## Cost per run")[0].split("- runs finished")[1]
    assert "missing: 0" in report and "over 1 invocation(s)" in report  # the old one's


def test_adopting_from_two_folders_counts_each_invocation_once(tmp_path) -> None:
    """A study put together from two older ones (here: PNN's critic setting per path, taken
    from a study with the Q-columns everywhere and one with them nowhere, which had itself
    adopted the first one's other runs) lists every invocation that made its runs, once."""
    from rov_envs.sim.tasks import TASKS_REVISION
    from sb3_pnn.reproduce.cli import main as study_main

    study = ["--tiny", "--seeds", "1", "--eval-episodes", "10", "--jobs", "1", "--no-progress"]
    on, off, new = tmp_path / "on", tmp_path / "off", tmp_path / "new"
    rev = ["--made-with-tasks-revision", str(TASKS_REVISION), "--"]
    assert study_main([*study, "--set", "pnn_critic_priors=true", "--out", str(on)], fake_work) == 0
    off_study = [*study, "--set", "pnn_critic_priors=false", "--out", str(off)]
    assert main(["--from", str(on), *rev, *off_study]) == 0
    assert study_main(off_study, work=fake_work) == 0  # trains the two PNN runs
    assert len(json.loads((off / "sessions.json").read_text())) == 2
    assert main(["--from", str(on), *rev, *study, "--out", str(new)]) == 0
    assert main(["--from", str(off), *rev, *study, "--out", str(new)]) == 0
    sessions = json.loads((new / "sessions.json").read_text())
    assert [s["adopted_from"] for s in sessions] == [str(on), str(off)]
    assert study_main([*study, "--out", str(new)], work=fake_work) == 0
    report = (new / "report.md").read_text()
    assert "missing: 0" in report and "over 3 invocation(s)" in report  # on, off, this one
    assert "adopted unchanged from ../off, ../on" in report


def test_a_run_whose_play_changed_is_adopted_and_evaluated_again(tmp_path, monkeypatch) -> None:
    """spnn_play_no_reversal changed: SPNN's sine run differs in ``play`` alone, so it is
    adopted with its files and evaluated again as the new spec plays it; every other run is
    adopted unchanged, and a run whose training spec differs is still refused."""
    from rov_envs.sim.tasks import TASKS_REVISION
    from sb3_pnn.reproduce.running import adopt

    before = (("spnn_play_no_reversal", "neither"),)
    old_plan = build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=before))
    _old_study(tmp_path / "old", old_plan, lambda spec: spec.config_hash())
    evaluated = []

    def fake_evaluation(spec, folder):
        evaluated.append((spec.run_id, spec.play, (folder / "model.zip").read_text()))
        (folder / "eval.json").write_text("{}")
        return {"eval_s": 0.5, "success_rates": {"original": 1.0}}

    monkeypatch.setattr(adopt, "evaluate_again", fake_evaluation)
    new = RunStore(tmp_path / "new")
    new.open()
    plan = build_plan(StudyConfig(budget_name="tiny", seeds=1))
    adopted, skipped = adopt_runs(tmp_path / "old", new, plan, TASKS_REVISION)
    assert sorted(adopted) == sorted(s.run_id for s in plan) and not skipped
    assert evaluated == [("spnn-sine-s0", {"no_reversal": True}, "spnn-sine-s0")]
    replayed = new.manifest("spnn-sine-s0")
    assert replayed["adopted"]["evaluated_again"] == {
        "play_before": {},
        "play": {"no_reversal": True},
    }
    assert replayed["success_rates"] == {"original": 1.0} and replayed["wall_s"] == 1.0
    assert new.is_done(next(s for s in plan if s.run_id == "spnn-sine-s0"))
    assert "evaluated_again" not in new.manifest("spnn-straight-s0")["adopted"]
    new.close()
    other = RunStore(tmp_path / "other")
    other.open()
    longer = build_plan(StudyConfig(budget_name="quick", seeds=1))
    adopted, skipped = adopt_runs(tmp_path / "old", other, longer, TASKS_REVISION)
    assert adopted == [] and "spec differs in" in skipped["spnn-sine-s0"]
    other.close()


def test_evaluating_again_writes_the_new_plays_results(tmp_path) -> None:
    """The kept model in the run's folder, played as the new spec names (NoReversal here),
    on the spec's evaluation tasks: eval.json holds each task's episodes."""
    import gymnasium as gym

    from sb3_pnn import DiscreteSAC
    from sb3_pnn.reproduce.planning.plan import PLANNING_ENVS
    from sb3_pnn.reproduce.running.adopt import evaluate_again

    spec = next(s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1)) if s.agent == "pnn")
    spec = RunSpec.from_dict({**spec.to_dict(), "play": {"no_reversal": True}})
    env = gym.make(PLANNING_ENVS[spec.path], **spec.env_kwargs)
    DiscreteSAC("MultiInputPolicy", env, policy_kwargs={"net_arch": [8]}, seed=0).save(
        tmp_path / "model.zip"
    )
    info = evaluate_again(spec, tmp_path)
    results = json.loads((tmp_path / "eval.json").read_text())
    assert set(results) == {label for label, _, _ in spec.eval_tasks}
    assert all(r["n_episodes"] == spec.eval_episodes for r in results.values())
    assert set(info["success_rates"]) == set(results)


def test_the_report_counts_the_runs_evaluated_again(tmp_path) -> None:
    from types import SimpleNamespace

    from sb3_pnn.reproduce.reporting.report import _adopted_text

    origin = str(tmp_path / "old" / "runs" / "x")
    runs = {
        "a": SimpleNamespace(manifest={"adopted": {"from": origin}}),
        "b": SimpleNamespace(manifest={"adopted": {"from": origin, "evaluated_again": {}}}),
        "c": SimpleNamespace(manifest={}),
    }
    text = _adopted_text(SimpleNamespace(runs=runs), tmp_path / "new")
    assert (
        "2 of them adopted unchanged (1 of them evaluated again as newly played) from ../old"
        in (text)
    )
