"""KeepBestOnValidation: checks on schedule, keeps the best weights, and the study uses it."""

from __future__ import annotations

import json
from types import SimpleNamespace

import gymnasium as gym
import pytest
import torch as th

import rov_envs  # noqa: F401
import sb3_pnn.evaluation
from sb3_pnn import DiscreteSAC
from sb3_pnn.common.callbacks import (
    DRAWN_VALIDATION_SEED,
    VALIDATION_SEED,
    KeepBestOnValidation,
    validation_rank,
)
from sb3_pnn.reproduce.planning.plan import RunSpec
from sb3_pnn.reproduce.planning.setups import OURS, PAPER, VALIDATION_EPISODES, VALIDATION_EVERY
from sb3_pnn.reproduce.running.work import run_work

ENV = "rov_envs/PathFollowingStraight-v0"


def _model() -> DiscreteSAC:
    env = gym.make(ENV)
    return DiscreteSAC("MultiInputPolicy", env, policy_kwargs={"net_arch": [8]}, seed=0)


def _result(
    rate: float,
    ret: float,
    g: float = 1.0,
    time: float | None = 100.0,
    discounted: float | None = None,
) -> SimpleNamespace:
    """What the callback reads of an evaluation: success, return, mean abs(g), mean abs(a_c),
    mean time to the target, mean discounted return."""
    return SimpleNamespace(
        success_rate=rate,
        mean_return=ret,
        mean_abs_cross_track=g,
        mean_abs_heading_error=0.1,
        mean_time_to_target=time,
        mean_discounted_return=discounted,
    )


def _first_weight(model: DiscreteSAC) -> th.Tensor:
    return next(iter(model.policy.state_dict().values())).clone()


def _checks_of_changing_weights(keeper: KeepBestOnValidation, model: DiscreteSAC, n: int):
    """Run ``n`` checks, changing the weights before each (so that each check sees its own) and
    counting them as training episodes 1..n; the first weight tensor at each check."""
    snapshots = []
    for i in range(n):
        with th.no_grad():
            for p in model.policy.parameters():
                p.add_(1.0)
        snapshots.append(_first_weight(model))
        keeper.episodes = i + 1
        keeper.check()
    return snapshots


def test_restore_brings_back_the_weights_of_the_best_check(monkeypatch) -> None:
    scores = iter([(0.2, 5.0), (0.6, -1.0), (0.6, -3.0), (0.4, 9.0)])
    calls = []

    def fake_evaluate(policy, env_id, n_episodes, seed, env_kwargs):
        calls.append((env_id, n_episodes, seed, env_kwargs))
        rate, ret = next(scores)
        return _result(rate, ret)

    monkeypatch.setattr(sb3_pnn.evaluation, "evaluate_policy_on_task", fake_evaluate)
    model = _model()
    keeper = KeepBestOnValidation(ENV, every=2, n_episodes=7, env_kwargs={"motion_obs": True})
    keeper.init_callback(model)
    snapshots = _checks_of_changing_weights(keeper, model, 4)
    assert calls[0] == (ENV, 7, VALIDATION_SEED, {"motion_obs": True})
    # 0.6 beats 0.2; the later 0.6 has a lower mean return; 0.4 is worse: the second is kept
    assert [h["success_rate"] for h in keeper.history] == [0.2, 0.6, 0.6, 0.4]
    assert keeper.restore()
    assert th.equal(_first_weight(model), snapshots[1])
    assert keeper.to_dict()["history"][1]["mean_return"] == -1.0


def test_the_checks_grid_leaves_training_unchanged() -> None:
    """Checking every episode or every third trains the same weights (checks read the policy
    and draw nothing from the training's random streams), and the checks they share agree:
    a finer grid (``pf_validation_every``) only selects among more moments of one run."""
    runs = {}
    for every in (1, 3):
        model = _model()
        keeper = KeepBestOnValidation(ENV, every=every, n_episodes=2, restore_at_end=False)
        model.learn(600, callback=keeper)
        runs[every] = (model.policy.state_dict(), {h["episode"]: h for h in keeper.history})
    (fine_weights, fine), (coarse_weights, coarse) = runs[1], runs[3]
    assert all(th.equal(fine_weights[k], coarse_weights[k]) for k in fine_weights)
    assert coarse and all(coarse[e] == fine[e] for e in coarse)


def test_checks_every_n_episodes_during_learn() -> None:
    model = _model()
    keeper = KeepBestOnValidation(ENV, every=1, n_episodes=2)
    assert not keeper.restore()  # nothing kept yet: nothing changes
    model.learn(600, callback=keeper)  # the untrained policy ends episodes early
    assert keeper.episodes >= 1
    assert [h["episode"] for h in keeper.history] == list(range(1, keeper.episodes + 1))
    assert keeper.best_episode in {h["episode"] for h in keeper.history}


@pytest.mark.parametrize("bad", [0, -1, 1.5, True])
def test_bad_schedule_refused(bad) -> None:
    with pytest.raises(ValueError, match=f"every={bad!r} is not allowed"):
        KeepBestOnValidation(ENV, every=bad, n_episodes=3)


def test_setups_and_specs() -> None:
    assert PAPER.validation() == {}  # the paper: the policy at the end of the budget
    assert OURS.validation() == {"every": VALIDATION_EVERY, "episodes": VALIDATION_EPISODES}
    spec = RunSpec("r", "prior", "dsac", None, ENV, 0, 3)
    assert "validation" not in spec.to_dict()  # old runs keep their hash
    kept = RunSpec("r", "prior", "dsac", None, ENV, 0, 3, validation={"every": 1, "episodes": 2})
    assert RunSpec.from_dict(kept.to_dict()) == kept
    assert kept.config_hash() != spec.config_hash()


def test_study_run_saves_the_kept_policy(tmp_path) -> None:
    spec = RunSpec(
        "prior-pf_straight-s0", "prior", "dsac", None, ENV, seed=0, episodes=3,
        eval_tasks=(("own", ENV, {}),), eval_episodes=2,
        sac_kwargs={"learning_starts": 50, "policy_kwargs": {"net_arch": [8]}},
        env_kwargs={"start_noise": [1.0, 0.1]}, validation={"every": 1, "episodes": 2},
    )  # fmt: skip
    info = run_work(spec, tmp_path, {})
    record = json.loads((tmp_path / "validation.json").read_text())
    assert len(record["history"]) == 3 and record["every"] == 1
    assert info["kept_episode"] == record["best_episode"]
    best = max(record["history"], key=lambda h: (h["success_rate"], h["mean_return"]))
    assert record["best_episode"] == best["episode"]
    # the saved model replays the kept policy's validation score exactly
    saved = DiscreteSAC.load(tmp_path / "model.zip", device="cpu")
    again = sb3_pnn.evaluation.evaluate_policy_on_task(
        saved, ENV, n_episodes=2, seed=VALIDATION_SEED
    )
    assert again.mean_return == pytest.approx(best["mean_return"])


def test_drawn_checks_rank_between_own_success_and_return(monkeypatch) -> None:
    # own-task (success, return) and drawn-obstacle success of four checks
    own = iter([(1.0, 50.0), (1.0, 10.0), (0.9, 90.0), (1.0, 5.0)])
    drawn = iter([0.2, 0.6, 0.9, 0.6])
    calls = []

    def fake_evaluate(policy, env_id, n_episodes, seed, env_kwargs):
        calls.append((n_episodes, seed, env_kwargs))
        if "layout" in env_kwargs:
            return _result(next(drawn), 0.0)
        rate, ret = next(own)
        return _result(rate, ret)

    monkeypatch.setattr(sb3_pnn.evaluation, "evaluate_policy_on_task", fake_evaluate)
    model = _model()
    keeper = KeepBestOnValidation(
        ENV, every=1, n_episodes=7, env_kwargs={"motion_obs": True}, drawn_episodes=5
    )
    keeper.init_callback(model)
    snapshots = _checks_of_changing_weights(keeper, model, 4)
    # the drawn episodes: the same task among scatter obstacles, on their own seeds
    assert calls[1] == (5, DRAWN_VALIDATION_SEED, {"motion_obs": True, "layout": "scatter"})
    # check 2 (drawn 0.6) beats check 1 (0.2) despite its lower return; check 3's 0.9 does not
    # count (its own-task success is lower); check 4 ties check 2 on both rates, lower return
    assert keeper.restore() and th.equal(_first_weight(model), snapshots[1])
    record = keeper.to_dict()
    assert [h["drawn_success_rate"] for h in record["history"]] == [0.2, 0.6, 0.9, 0.6]
    assert record["drawn_episodes"] == 5 and record["drawn_seed"] == DRAWN_VALIDATION_SEED


def test_ranks_without_drawn_checks_are_unchanged() -> None:
    check = {"success_rate": 0.5, "mean_return": 3.0}
    assert validation_rank(check) == (0.5, 3.0)
    assert validation_rank({**check, "drawn_success_rate": 0.25}) == (0.5, 0.25, 3.0)
    with pytest.raises(ValueError, match="drawn_episodes=-1 is not allowed"):
        KeepBestOnValidation(ENV, drawn_episodes=-1)
    # a bad generator is refused when the run starts, not at its first check
    with pytest.raises(ValueError, match="drawn_layout='nope' is not allowed: expected one of"):
        KeepBestOnValidation(ENV, drawn_episodes=5, drawn_layout="nope")


def test_keep_best_drawn_reaches_the_learners_only() -> None:
    from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan

    setup = OURS.with_(keep_best_drawn=30)
    assert setup.validation() == OURS.validation()  # the source columns: unchanged
    assert setup.validation(learner=True)["drawn_episodes"] == 30
    assert OURS.validation(learner=True) == OURS.validation()  # default: the study's hashes
    plan = build_plan(StudyConfig(seeds=1, setup_changes=(("keep_best_drawn", 30),)))
    for spec in plan:
        drawn = spec.validation.get("drawn_episodes")
        assert drawn == (30 if spec.kind == "transfer" else None), spec.run_id
    with pytest.raises(ValueError, match="keep_best_drawn=30 is not allowed with keep_best off"):
        PAPER.with_(keep_best_drawn=30)
    with pytest.raises(
        ValueError, match=r"keep_best_drawn=-1 is not allowed: expected an integer >= 0$"
    ):
        OURS.with_(keep_best_drawn=-1)


def _ranked_checks(monkeypatch, own: list[tuple], rank_by: str):
    """A keeper ranking by ``rank_by`` after one check per ``own`` entry (the evaluation's
    (success, return, ...) as :func:`_result` takes them): (keeper, model, weight snapshots)."""
    results = iter(own)
    monkeypatch.setattr(
        sb3_pnn.evaluation, "evaluate_policy_on_task", lambda *a, **k: _result(*next(results))
    )
    model = _model()
    keeper = KeepBestOnValidation(ENV, every=1, n_episodes=3, rank_by=rank_by)
    keeper.init_callback(model)
    return keeper, model, _checks_of_changing_weights(keeper, model, len(own))


def test_route_ranking_keeps_the_closest_route_among_the_best_successes(monkeypatch) -> None:
    # own-task (success, return, mean abs(g)) of four checks
    own = [(1.0, 50.0, 3.0), (1.0, 10.0, 1.5), (0.9, 90.0, 0.5), (1.0, 60.0, 1.5)]
    keeper, model, snapshots = _ranked_checks(monkeypatch, own, "route")
    # check 2 keeps the route closest among the 100 % checks (check 3's 0.5 m fails more;
    # check 4 only ties it, whatever its return): by return, check 4 would be kept
    assert keeper.restore() and th.equal(_first_weight(model), snapshots[1])
    record = keeper.to_dict()
    assert record["rank_by"] == "route" and record["best_episode"] == 2
    assert [h["mean_abs_cross_track"] for h in record["history"]] == [3.0, 1.5, 0.5, 1.5]
    by_return = max(record["history"], key=validation_rank)
    assert by_return["episode"] == 4
    assert "rank_by" not in KeepBestOnValidation(ENV).to_dict()  # the default's record


def test_route_ranking_refuses_bad_values_and_records_without_the_route() -> None:
    with pytest.raises(ValueError, match=r"rank_by='closest' is not allowed: expected one of"):
        KeepBestOnValidation(ENV, rank_by="closest")
    with pytest.raises(ValueError, match="has no 'mean_abs_cross_track'"):
        validation_rank({"success_rate": 1.0, "mean_return": 3.0}, "route")
    check = {"success_rate": 1.0, "mean_return": 3.0, "mean_abs_cross_track": 2.0}
    assert validation_rank(check, "route") == (1.0, -2.0)
    assert validation_rank({**check, "drawn_success_rate": 0.5}, "route") == (1.0, 0.5, -2.0)


def test_route_bound_keeps_the_best_return_among_the_checks_within_it(monkeypatch) -> None:
    # own-task (success, return, mean abs(g)) of five checks
    own = [(1.0, 90.0, 3.0), (1.0, 40.0, 1.2), (1.0, 60.0, 1.9), (0.9, 99.0, 0.5)]
    own.append((1.0, 50.0, 1.0))
    results = iter(own)
    monkeypatch.setattr(
        sb3_pnn.evaluation, "evaluate_policy_on_task", lambda *a, **k: _result(*next(results))
    )
    model = _model()
    keeper = KeepBestOnValidation(ENV, every=1, n_episodes=3, route_bound=2.0)
    keeper.init_callback(model)
    snapshots = _checks_of_changing_weights(keeper, model, len(own))
    # check 3 earns the most of the 100 % checks within 2 m: check 1 earns more on a 3 m route,
    # check 4 is closer and earns more but fails an episode, check 5 is closer but earns less
    assert keeper.restore() and th.equal(_first_weight(model), snapshots[2])
    record = keeper.to_dict()
    assert record["route_bound"] == 2.0 and record["best_episode"] == 3
    assert "rank_by" not in record  # the return still ranks within the bound
    # without the bound check 1 is kept; by route alone check 5, whatever it earns
    assert max(record["history"], key=validation_rank)["episode"] == 1
    assert max(record["history"], key=lambda c: validation_rank(c, "route"))["episode"] == 5
    assert "route_bound" not in KeepBestOnValidation(ENV).to_dict()  # the default's record


def test_route_bound_falls_back_to_the_ranking_when_no_check_keeps_it() -> None:
    wide = {"success_rate": 1.0, "mean_return": 80.0, "mean_abs_cross_track": 3.0}
    wider = {"success_rate": 1.0, "mean_return": 70.0, "mean_abs_cross_track": 4.0}
    assert validation_rank(wide, route_bound=2.0) == (1.0, 0.0, 80.0)
    assert validation_rank(wide, route_bound=2.0) > validation_rank(wider, route_bound=2.0)
    # the bound ranks below the drawn success and above the return
    drawn = {**wide, "drawn_success_rate": 0.5}
    assert validation_rank(drawn, route_bound=3.0) == (1.0, 0.5, 1.0, 80.0)
    for bad in (0, -1.0, float("nan"), True, "2"):
        with pytest.raises(ValueError, match=r"route_bound=.* is not allowed: expected a mean"):
            KeepBestOnValidation(ENV, route_bound=bad)
        with pytest.raises(ValueError, match=r"route_bound=.* is not allowed"):
            validation_rank(wide, route_bound=bad)


def test_keep_best_route_bound_reaches_the_learners_only() -> None:
    from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
    from sb3_pnn.reproduce.planning.setups import parse_setup_changes

    assert OURS.keep_best_route_bound is None  # not the default (docs/ablation section 101)
    setup = OURS.with_(keep_best_route_bound=2.0)
    assert setup.validation() == OURS.validation()  # the source columns: unchanged
    assert setup.validation(learner=True)["route_bound"] == 2.0
    assert "route_bound" not in OURS.validation(learner=True)  # off: the study's hashes
    plan = build_plan(StudyConfig(seeds=1, setup_changes=(("keep_best_route_bound", 3.0),)))
    for spec in plan:
        bound = spec.validation.get("route_bound")
        assert bound == (3.0 if spec.kind == "transfer" else None), spec.run_id
    assert parse_setup_changes(["keep_best_route_bound=2"]) == {"keep_best_route_bound": 2.0}
    assert parse_setup_changes(["keep_best_route_bound=null"]) == {"keep_best_route_bound": None}
    # without keep_best nothing is checked, so the bound changes no run (the ablation's cell
    # that puts keep_best back keeps the default bound)
    assert setup.with_(keep_best=False).validation(learner=True) == {}
    with pytest.raises(ValueError, match=r"keep_best_route_bound=-1.0 is not allowed: expected"):
        OURS.with_(keep_best_route_bound=-1.0)


def test_keep_best_route_bound_sine_bounds_the_sine_runs_alone() -> None:
    from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
    from sb3_pnn.reproduce.planning.setups import parse_setup_changes

    setup = OURS.with_(keep_best_route_bound_sine=2.0)
    assert setup.validation(learner=True, path="sine")["route_bound"] == 2.0
    assert "route_bound" not in setup.validation(learner=True, path="straight")
    assert setup.validation(column="oa") == OURS.validation(column="oa")  # columns unchanged
    with pytest.raises(ValueError, match=r"keep_best_route_bound_sine=2.0 depends on the path"):
        setup.validation(learner=True)
    # None takes keep_best_route_bound's on the sine path; a sine bound of its own replaces it
    both = OURS.with_(keep_best_route_bound=3.0)
    assert both.validation(learner=True, path="sine")["route_bound"] == 3.0
    assert both.with_(keep_best_route_bound_sine=2.0).route_bound_of("sine") == 2.0
    assert both.with_(keep_best_route_bound_sine=2.0).route_bound_of("straight") == 3.0
    plan = build_plan(StudyConfig(seeds=1, setup_changes=(("keep_best_route_bound_sine", 2.0),)))
    default = {spec.run_id: spec.config_hash() for spec in build_plan(StudyConfig(seeds=1))}
    for spec in plan:
        bounded = spec.kind == "transfer" and spec.path == "sine"
        assert spec.validation.get("route_bound") == (2.0 if bounded else None), spec.run_id
        assert (spec.config_hash() != default[spec.run_id]) == bounded, spec.run_id
    changes = parse_setup_changes(["keep_best_route_bound_sine=2"])
    assert changes == {"keep_best_route_bound_sine": 2.0}
    for bad in (0.0, -1.0, float("nan"), "wide"):
        with pytest.raises(ValueError, match=r"keep_best_route_bound_sine=.* is not allowed"):
            OURS.with_(keep_best_route_bound_sine=bad)


def test_last_ranking_keeps_the_latest_check_whatever_its_success(monkeypatch) -> None:
    # own-task (success, return, mean abs(g)): the last check fails episodes and earns least
    own = [(1.0, 90.0, 3.0), (1.0, 60.0, 1.5), (0.8, 10.0, 1.0)]
    results = iter(own)
    monkeypatch.setattr(
        sb3_pnn.evaluation, "evaluate_policy_on_task", lambda *a, **k: _result(*next(results))
    )
    model = _model()
    keeper = KeepBestOnValidation(ENV, every=1, n_episodes=3, rank_by="last", route_bound=2.0)
    keeper.init_callback(model)
    snapshots = _checks_of_changing_weights(keeper, model, len(own))
    assert keeper.restore() and th.equal(_first_weight(model), snapshots[2])
    record = keeper.to_dict()
    assert record["rank_by"] == "last" and record["best_episode"] == 3
    assert validation_rank(record["history"][0], "last") == (1.0,)
    assert max(record["history"], key=validation_rank)["episode"] == 1  # by return: the first


def test_spnn_keep_best_by_sine_ranks_spnns_sine_runs_alone() -> None:
    from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
    from sb3_pnn.reproduce.planning.setups import parse_setup_changes

    assert OURS.spnn_keep_best_by_sine == "last"  # the default (docs/ablation section 103)
    setup = OURS.with_(spnn_keep_best_by_sine="last")
    assert setup.validation(learner=True, path="sine", agent="spnn")["rank_by"] == "last"
    for agent, path in (("spnn", "straight"), ("pnn", "sine"), ("sac_multi", "sine")):
        assert "rank_by" not in setup.validation(learner=True, path=path, agent=agent)
    assert setup.validation(column="oa") == OURS.validation(column="oa")  # columns unchanged
    assert "rank_by" not in setup.validation(learner=True, path="sine")  # no agent named
    with pytest.raises(ValueError, match=r"spnn_keep_best_by_sine='last' depends on the path"):
        setup.validation(learner=True, agent="spnn")
    plan = build_plan(StudyConfig(seeds=1))
    by_return = (("spnn_keep_best_by_sine", "return"),)
    default = {
        spec.run_id: spec.config_hash()
        for spec in build_plan(StudyConfig(seeds=1, setup_changes=by_return))
    }
    changed = [spec.run_id for spec in plan if spec.config_hash() != default[spec.run_id]]
    assert changed == ["spnn-sine-s0"]
    assert parse_setup_changes(["spnn_keep_best_by_sine=last"]) == {
        "spnn_keep_best_by_sine": "last"
    }
    with pytest.raises(
        ValueError, match=r"spnn_keep_best_by_sine='final' is not allowed: expected"
    ):
        OURS.with_(spnn_keep_best_by_sine="final")
    # without checks every run keeps its last policy, so the factor changes nothing there
    assert OURS.with_(keep_best=False).validation(learner=True, path="sine", agent="spnn") == {}
    assert PAPER.spnn_keep_best_by_sine is None


def test_time_ranking_keeps_the_fastest_crossing_among_the_best_successes(monkeypatch) -> None:
    # own-task (success, return, mean abs(g), mean time to the target) of four checks
    own = [(1.0, 50.0, 1.0, 260.0), (1.0, 10.0, 2.0, 240.0), (0.9, 90.0, 0.5, 200.0)]
    own.append((1.0, 60.0, 1.0, 250.0))
    keeper, model, snapshots = _ranked_checks(monkeypatch, own, "time")
    # check 2 is the fastest of the 100 % checks (check 3 is faster but fails more); by return
    # check 4, by route check 1
    assert keeper.restore() and th.equal(_first_weight(model), snapshots[1])
    record = keeper.to_dict()
    assert record["rank_by"] == "time" and record["best_episode"] == 2
    assert [h["mean_time_to_target"] for h in record["history"]] == [260.0, 240.0, 200.0, 250.0]
    assert max(record["history"], key=validation_rank)["episode"] == 4
    assert max(record["history"], key=lambda h: validation_rank(h, "route"))["episode"] == 1


def test_time_ranking_puts_a_check_without_a_success_last() -> None:
    none = {"success_rate": 0.0, "mean_return": 9.0, "mean_time_to_target": None}
    assert validation_rank(none, "time") == (0.0, -float("inf"))
    with pytest.raises(ValueError, match="has no 'mean_time_to_target': ranking by time"):
        validation_rank({"success_rate": 1.0, "mean_return": 3.0}, "time")


def test_discounted_ranking_keeps_the_best_discounted_return_of_the_best_successes(
    monkeypatch,
) -> None:
    # own-task (success, return, mean abs(g), time, discounted return) of four checks: the
    # first creeps along the path (largest return, smallest discounted return)
    own = [(1.0, 390.0, 0.1, 341.0, 60.0), (1.0, 380.0, 0.4, 208.0, 95.0)]
    own += [(0.9, 300.0, 0.5, 200.0, 120.0), (1.0, 385.0, 0.6, 205.0, 90.0)]
    asked = []
    results = iter(own)

    def evaluate(*args, **kwargs):
        asked.append(kwargs.get("discount"))
        return _result(*next(results))

    monkeypatch.setattr(sb3_pnn.evaluation, "evaluate_policy_on_task", evaluate)
    model = _model()
    keeper = KeepBestOnValidation(ENV, every=1, n_episodes=3, rank_by="discounted")
    keeper.init_callback(model)
    snapshots = _checks_of_changing_weights(keeper, model, len(own))
    assert asked == [model.gamma] * 4  # the model's own discount
    assert keeper.restore() and th.equal(_first_weight(model), snapshots[1])
    record = keeper.to_dict()
    assert record["rank_by"] == "discounted" and record["best_episode"] == 2
    assert [h["mean_discounted_return"] for h in record["history"]] == [60.0, 95.0, 120.0, 90.0]
    assert max(record["history"], key=validation_rank)["episode"] == 1  # by return: the creeper
    with pytest.raises(ValueError, match="has no 'mean_discounted_return': ranking by discounted"):
        validation_rank({"success_rate": 1.0, "mean_return": 3.0}, "discounted")


def test_checks_ranked_by_return_do_not_ask_for_a_discount(monkeypatch) -> None:
    asked = []

    def evaluate(*args, **kwargs):
        asked.append(kwargs)
        return _result(1.0, 1.0)

    monkeypatch.setattr(sb3_pnn.evaluation, "evaluate_policy_on_task", evaluate)
    keeper = KeepBestOnValidation(ENV, every=1, n_episodes=3)
    keeper.init_callback(_model())
    keeper.check()
    assert "discount" not in asked[0] and "mean_discounted_return" not in keeper.history[0]


def test_prior_keep_best_by_reaches_the_source_columns_only() -> None:
    from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan

    setup = OURS.with_(prior_keep_best_by="discounted")
    assert setup.validation()["rank_by"] == "discounted"
    assert setup.validation(learner=True) == OURS.validation(learner=True)
    assert "rank_by" not in OURS.validation()  # default: the study's hashes
    plan = build_plan(StudyConfig(seeds=1, setup_changes=(("prior_keep_best_by", "discounted"),)))
    default = {spec.run_id: spec for spec in build_plan(StudyConfig(seeds=1))}
    for spec in plan:
        ranking = spec.validation.get("rank_by")
        expected = "discounted" if spec.kind == "prior" else None
        if spec.run_id.startswith("spnn-sine"):  # spnn_keep_best_by_sine's, the default
            expected = "last"
        assert ranking == expected, spec.run_id
        if spec.kind != "prior":  # the learners' own specs do not change
            assert spec.to_dict() == default[spec.run_id].to_dict(), spec.run_id
    with pytest.raises(ValueError, match="prior_keep_best_by='time' is not allowed with keep_best"):
        PAPER.with_(prior_keep_best_by="time")
    with pytest.raises(ValueError, match=r"prior_keep_best_by='gap' is not allowed: expected one"):
        OURS.with_(prior_keep_best_by="gap")


def test_keep_best_by_reaches_the_learners_only() -> None:
    from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan

    setup = OURS.with_(keep_best_by="route")
    assert setup.validation() == OURS.validation()  # the source columns rank by return
    assert setup.validation(learner=True)["rank_by"] == "route"
    assert "rank_by" not in OURS.validation(learner=True)  # default: the study's hashes
    plan = build_plan(StudyConfig(seeds=1, setup_changes=(("keep_best_by", "route"),)))
    for spec in plan:
        ranking = spec.validation.get("rank_by")
        expected = "route" if spec.kind == "transfer" else None
        if spec.run_id.startswith("spnn-sine"):  # spnn_keep_best_by_sine's, the default
            expected = "last"
        assert ranking == expected, spec.run_id
    with pytest.raises(ValueError, match="keep_best_by='route' is not allowed with keep_best off"):
        PAPER.with_(keep_best_by="route")
    with pytest.raises(ValueError, match=r"keep_best_by='gap' is not allowed: expected one of"):
        OURS.with_(keep_best_by="gap")


def test_also_rank_by_keeps_each_rankings_best_beside_the_own(monkeypatch) -> None:
    # own-task (success, return, mean abs(g)): the return-best check (2) keeps the route wider
    # than the route-best one (3); the last check (4) fails episodes
    own = [(0.9, 50.0, 1.0), (1.0, 90.0, 3.0), (1.0, 70.0, 1.5), (0.8, 10.0, 0.5)]
    results = iter(own)
    monkeypatch.setattr(
        sb3_pnn.evaluation, "evaluate_policy_on_task", lambda *a, **k: _result(*next(results))
    )
    model = _model()
    keeper = KeepBestOnValidation(ENV, every=1, n_episodes=3, also_rank_by=("route", "last"))
    keeper.init_callback(model)
    assert not keeper.restore("route")  # nothing kept yet: nothing changes
    snapshots = _checks_of_changing_weights(keeper, model, len(own))
    assert keeper.restore("route") and th.equal(_first_weight(model), snapshots[2])
    assert keeper.restore("last") and th.equal(_first_weight(model), snapshots[3])
    assert keeper.restore() and th.equal(_first_weight(model), snapshots[1])
    record = keeper.to_dict()
    assert record["best_episode"] == 2 and record["best_episode_by"] == {"route": 3, "last": 4}
    with pytest.raises(ValueError, match=r"ranking='time' is not allowed: .*\['route', 'last'\]"):
        keeper.restore("time")


def test_also_rank_by_leaves_training_and_the_own_choice_unchanged() -> None:
    """The further rankings read the same checks: the same weights train, the same checks are
    recorded, the same policy is kept by ``rank_by``, and a ranking also kept alone (route)
    keeps what a callback ranking by it alone keeps."""
    runs = {}
    for also in ((), ("route", "last")):
        model = _model()
        keeper = KeepBestOnValidation(ENV, every=1, n_episodes=2, also_rank_by=also)
        model.learn(600, callback=keeper)
        kept = {k: v.clone() for k, v in model.policy.state_dict().items()}
        routes = None
        if also:
            keeper.restore("route")
            routes = {k: v.clone() for k, v in model.policy.state_dict().items()}
        runs[also] = (kept, keeper.history, routes)
    (plain, plain_history, _), (both, both_history, route_kept) = runs.values()
    assert plain_history == both_history and len(plain_history) >= 2
    assert all(th.equal(plain[k], both[k]) for k in plain)
    model = _model()
    by_route = KeepBestOnValidation(ENV, every=1, n_episodes=2, rank_by="route")
    model.learn(600, callback=by_route)
    assert all(th.equal(route_kept[k], v) for k, v in model.policy.state_dict().items())


@pytest.mark.parametrize(
    ("bad", "match"),
    [("route", "also_rank_by='route' is not allowed"), (("route", "nope"), "rank_by='nope'")],
)
def test_also_rank_by_refuses_bad_values_by_name(bad, match) -> None:
    with pytest.raises(ValueError, match=match):
        KeepBestOnValidation(ENV, also_rank_by=bad)


def test_also_rank_by_discounted_asks_for_the_discount(monkeypatch) -> None:
    asked = []

    def evaluate(*args, **kwargs):
        asked.append(kwargs.get("discount"))
        return _result(1.0, 1.0, discounted=5.0)

    monkeypatch.setattr(sb3_pnn.evaluation, "evaluate_policy_on_task", evaluate)
    model = _model()
    keeper = KeepBestOnValidation(ENV, every=1, n_episodes=3, also_rank_by=["discounted"])
    keeper.init_callback(model)
    keeper.check()
    assert asked == [model.gamma] and keeper.to_dict()["best_episode_by"] == {"discounted": 0}
