"""keep_best_also: further rankings of the learners' checks keep their own policies of the same
training, saved beside the kept one, and the replay tools read them with ``--kept-by``."""

from __future__ import annotations

import json

import gymnasium as gym
import pytest

import rov_envs  # noqa: F401
import sb3_pnn.evaluation
from sb3_pnn import DiscreteSAC
from sb3_pnn.common.callbacks import VALIDATION_SEED
from sb3_pnn.reproduce.planning.plan import RunSpec, StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import OURS, PAPER, parse_setup_changes
from sb3_pnn.reproduce.running.work import run_work
from sb3_pnn.reproduce.tools import drawn_layouts, fresh_route

ENV = "rov_envs/PathFollowingStraight-v0"
PLANNING = "rov_envs/PlanningStraight-v0"


def test_the_factor_reaches_the_learners_checks_alone_and_keeps_every_default_hash() -> None:
    assert OURS.keep_best_also == "" == PAPER.keep_best_also
    setup = OURS.with_(keep_best_also="route, last")
    assert setup.learner_keep_best_also() == ("route", "last")
    for agent, path in (("spnn", "sine"), ("pnn", "straight"), ("sac_single", "sine")):
        checks = setup.validation(learner=True, path=path, agent=agent)
        assert checks["also_rank_by"] == "route,last"
    assert setup.validation(column="oa") == OURS.validation(column="oa")  # columns unchanged
    assert "also_rank_by" not in OURS.validation(learner=True, path="sine", agent="spnn")
    default = {spec.run_id: spec.config_hash() for spec in build_plan(StudyConfig(seeds=1))}
    also = (("keep_best_also", "route"),)
    changed = {
        spec.run_id
        for spec in build_plan(StudyConfig(seeds=1, setup_changes=also))
        if spec.config_hash() != default[spec.run_id]
    }
    assert changed and all(run_id.split("-")[0] in ("spnn", "pnn", "sac_multi", "sac_single")
                           for run_id in changed)  # fmt: skip
    assert parse_setup_changes(["keep_best_also=route,last"]) == {"keep_best_also": "route,last"}


@pytest.mark.parametrize(
    ("value", "match"),
    [
        ("route,nearest", "'nearest' is not a ranking"),
        ("route,route", "a ranking named twice"),
        (3, "expected comma-separated rankings"),
    ],
)
def test_bad_rankings_are_refused_by_name(value, match) -> None:
    with pytest.raises(ValueError, match=rf"keep_best_also={value!r} is not allowed: .*{match}"):
        OURS.with_(keep_best_also=value)


def test_the_factor_needs_the_checks() -> None:
    with pytest.raises(ValueError, match="keep_best_also='route' is not allowed with keep_best"):
        OURS.with_(keep_best=False, keep_best_also="route")


def test_a_run_saves_each_rankings_policy_beside_the_kept_one(tmp_path) -> None:
    """model.zip replays the return-best check and model_by_route.zip the route-best check of
    the same training, exactly; validation.json names both checks."""
    spec = RunSpec(
        "spnn-straight-s0", "transfer", "dsac", None, ENV, seed=0, episodes=4,
        eval_tasks=(("own", ENV, {}),), eval_episodes=2,
        sac_kwargs={"learning_starts": 50, "policy_kwargs": {"net_arch": [8]}},
        env_kwargs={"start_noise": [1.0, 0.1]},
        validation={"every": 1, "episodes": 2, "also_rank_by": "route,last"},
    )  # fmt: skip
    run_work(spec, tmp_path, {})
    record = json.loads((tmp_path / "validation.json").read_text())
    history = record["history"]
    by_return = max(history, key=lambda h: (h["success_rate"], h["mean_return"]))
    by_route = max(history, key=lambda h: (h["success_rate"], -h["mean_abs_cross_track"]))
    assert record["best_episode"] == by_return["episode"]
    assert record["best_episode_by"] == {"route": by_route["episode"], "last": 4}
    for name, check in (("model.zip", by_return), ("model_by_route.zip", by_route)):
        saved = DiscreteSAC.load(tmp_path / name, device="cpu")
        again = sb3_pnn.evaluation.evaluate_policy_on_task(
            saved, ENV, n_episodes=2, seed=VALIDATION_SEED
        )
        assert again.mean_abs_cross_track == pytest.approx(check["mean_abs_cross_track"])
        assert again.mean_return == pytest.approx(check["mean_return"])
    assert (tmp_path / "model_by_last.zip").is_file()


def _planning_run(study, names):
    """A finished SPNN straight run folder of seed 0 whose files ``names`` hold different
    untrained policies of PlanningStraight (seeds 0, 1, ...)."""
    run = study / "runs" / "spnn-straight-s0"
    run.mkdir(parents=True)
    (run / "manifest.json").write_text(json.dumps({"agent": "spnn", "spec": {}}))
    tasks = {"original": {"env_id": PLANNING, "env_kwargs": {}}}
    tasks["path_following"] = {"env_id": "rov_envs/PathFollowingStraight-v0", "env_kwargs": {}}
    (run / "eval.json").write_text(json.dumps(tasks))
    for seed, name in enumerate(names):
        model = DiscreteSAC("MultiInputPolicy", gym.make(PLANNING), seed=seed,
                            policy_kwargs={"net_arch": [8]}, device="cpu")  # fmt: skip
        model.save(run / name)
    return run


def test_drawn_layouts_replays_the_policy_the_ranking_kept(tmp_path, capsys) -> None:
    """With ``--kept-by route`` the tool replays model_by_route.zip: the run's model.zip is
    not a checkpoint here, so reading it would stop the command."""
    run = _planning_run(tmp_path, ["model_by_route.zip"])
    (run / "model.zip").write_bytes(b"not a checkpoint")
    argv = [str(tmp_path), "--seeds", "0", "--episodes", "2", "--kept-by", "route"]
    assert drawn_layouts.main(argv) == 0
    out = capsys.readouterr().out
    model = DiscreteSAC.load(run / "model_by_route.zip", device="cpu")
    drawn = sb3_pnn.evaluation.evaluate_policy_on_task(
        model, PLANNING, 2, VALIDATION_SEED, env_kwargs={"layout": "scatter"}
    )
    ends = ", ".join(f"{k} {v}" for k, v in sorted(drawn.end_reasons.items()))
    assert f"| 0 | {100 * drawn.success_rate:.0f} % | {ends} |" in out
    with pytest.raises(ValueError):  # without --kept-by: the run's own model.zip, not readable
        drawn_layouts.main(argv[:-2])


def test_a_ranking_the_run_did_not_keep_stops_the_tools_with_a_message(tmp_path, capsys) -> None:
    _planning_run(tmp_path, ["model.zip"])
    for main in (drawn_layouts.main, fresh_route.main):
        with pytest.raises(SystemExit) as stop:
            main([str(tmp_path), "--seeds", "0", "--episodes", "1", "--kept-by", "last"])
        assert stop.value.code == 2
        assert (
            "spnn-straight-s0/model_by_last.zip does not exist: expected a run trained with "
            "--set keep_best_also=last"
        ) in capsys.readouterr().err
