"""The plan (runs, dependencies, budgets) and the run store (atomic commits, conflicts, lock)."""

from __future__ import annotations

import json
import math

import pytest

import rov_envs
from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import OURS, PAPER, describe_value, parse_setup_changes
from sb3_pnn.reproduce.running.store import RunStore, StudyConflictError


@pytest.mark.parametrize("prior_per_seed", [True, False])
def test_plan_has_every_run_and_deps_come_first(prior_per_seed) -> None:
    plan = build_plan(StudyConfig(budget_name="full", seeds=5, prior_per_seed=prior_per_seed))
    ids = [s.run_id for s in plan]
    assert len(set(ids)) == len(ids)
    kinds = [s.kind for s in plan]
    # pf_straight, pf_sine, oa: per seed, or seed 0's shared by every seed
    assert kinds.count("prior") == (3 * 5 if prior_per_seed else 3)
    assert kinds.count("transfer") == 4 * 2 * 5
    assert kinds.count("baseline") == 2 * 2
    seen: set[str] = set()
    for spec in plan:
        assert set(spec.deps) <= seen, spec.run_id
        seen.add(spec.run_id)
    spnn = next(s for s in plan if s.run_id == "spnn-sine-s3")
    prior_seed = 3 if prior_per_seed else 0
    assert spnn.deps == (f"prior-pf_sine-s{prior_seed}", f"prior-oa-s{prior_seed}")
    assert {label for label, _, _ in spnn.eval_tasks} == {"original", "path_following", "dense"}


def test_priors_per_seed_by_default_and_recorded_episodes_inside_budget() -> None:
    plan = build_plan(StudyConfig(budget_name="full", seeds=2, episodes=200))
    assert sum(s.kind == "prior" for s in plan) == 6
    pnn = next(s for s in plan if s.run_id == "pnn-straight-s1")
    assert pnn.deps == ("prior-pf_straight-s1", "prior-oa-s1")  # pnn_avoidance_column
    assert pnn.episodes == 200
    assert pnn.record_episodes == (0, 80, 150, 199)  # paper's episodes < 200, then the last


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"seeds": 0}, "seeds=0"), ({"seeds": -2}, "seeds=-2"), ({"episodes": 0}, "episodes=0"),
     ({"budget_name": "huge"}, "huge")],
)  # fmt: skip
def test_bad_study_config(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        StudyConfig(**kwargs)


def test_config_hash_changes_with_the_budget() -> None:
    def pnn(config: StudyConfig):
        return next(s for s in build_plan(config) if s.run_id == "pnn-straight-s0")

    a = pnn(StudyConfig(budget_name="quick", seeds=1))
    b = pnn(StudyConfig(budget_name="quick", seeds=1, episodes=7))
    assert a.config_hash() != b.config_hash()
    assert a.config_hash() == pnn(StudyConfig(budget_name="quick", seeds=3)).config_hash()


def test_config_hash_changes_with_the_task_revision(monkeypatch) -> None:
    """Runs stored before a task's definition changed are not taken for current ones."""
    import rov_envs.sim.tasks

    spec = build_plan(StudyConfig(budget_name="quick", seeds=1))[0]
    before = spec.config_hash()
    monkeypatch.setattr(rov_envs.sim.tasks, "TASKS_REVISION", rov_envs.sim.tasks.TASKS_REVISION + 1)
    assert spec.config_hash() != before


def test_commit_is_atomic_and_never_overwrites(tmp_path) -> None:
    spec = build_plan(StudyConfig(budget_name="tiny", seeds=1))[0]
    store = RunStore(tmp_path)
    store.open()
    try:
        tmp = store.begin(spec)
        (tmp / "result.txt").write_text("first")
        assert not store.is_done(spec)
        assert store.commit(spec, tmp, {"note": 1})
        assert store.is_done(spec)
        assert store.manifest(spec.run_id)["config_hash"] == spec.config_hash()
        tmp2 = store.begin(spec)
        (tmp2 / "result.txt").write_text("second")
        assert not store.commit(spec, tmp2, {"note": 2})  # refused, first result kept
        assert (store.run_dir(spec.run_id) / "result.txt").read_text() == "first"
        assert not tmp2.exists()
    finally:
        store.close()


def test_changed_config_is_an_error(tmp_path) -> None:
    spec = build_plan(StudyConfig(budget_name="tiny", seeds=1))[0]
    store = RunStore(tmp_path)
    store.open()
    store.commit(spec, store.begin(spec), {})
    changed = build_plan(StudyConfig(budget_name="quick", seeds=1))[0]
    assert changed.run_id == spec.run_id
    with pytest.raises(StudyConflictError, match="another configuration"):
        store.is_done(changed)
    store.close()


def test_open_removes_leftovers_and_takes_a_lock(tmp_path) -> None:
    (tmp_path / "runs" / ".tmp-x-1-2").mkdir(parents=True)
    store = RunStore(tmp_path)
    store.open()
    assert not (tmp_path / "runs" / ".tmp-x-1-2").exists()
    with pytest.raises(RuntimeError, match="another study is running"):
        RunStore(tmp_path).open()
    store.close()
    RunStore(tmp_path).open()


def test_unwritable_out_is_refused(tmp_path) -> None:
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    with pytest.raises(PermissionError, match="not a writable folder"):
        RunStore(blocker / "sub").open()


def test_failures_are_recorded(tmp_path) -> None:
    spec = build_plan(StudyConfig(budget_name="tiny", seeds=1))[0]
    store = RunStore(tmp_path)
    store.open()
    store.fail(spec, store.begin(spec), "boom")
    assert (
        json.loads((tmp_path / "failures" / f"{spec.run_id}.json").read_text())["error"] == "boom"
    )
    assert list((tmp_path / "runs").iterdir()) == []
    store.close()


def test_pnn_goal_obs_off_drops_the_goal_part_for_pnn_alone() -> None:
    """pnn_goal_obs=false: PNN's planning runs train and are evaluated without the goal part;
    every other learner's runs, and the source columns, are unchanged."""
    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    changed = build_plan(
        StudyConfig(budget_name="tiny", seeds=1, setup_changes=(("pnn_goal_obs", False),))
    )
    for spec in changed:
        if spec.agent == "pnn":
            assert spec.env_kwargs["goal_obs"] is False
            assert all(kw["goal_obs"] is False for _, _, kw in spec.eval_tasks)
            assert "goal_obs" not in plain[spec.run_id].env_kwargs
        else:
            assert spec.env_kwargs == plain[spec.run_id].env_kwargs
            assert spec.eval_tasks == plain[spec.run_id].eval_tasks


@pytest.mark.parametrize(
    ("factor", "value", "keyword", "default"),
    [
        ("oa_corridor", 15.0, "corridor", "the task's (30 m)"),
        ("oa_time_limit", 90.0, "max_episode_seconds", "the task's (120 s)"),
    ],
)
def test_avoidance_task_factors_change_only_the_avoidance_columns_training(
    factor, value, keyword, default
) -> None:
    """oa_corridor=15 (episodes end 15 m from the line) and oa_time_limit=90 (90 s episodes,
    the task's 120 s otherwise): the obstacle-avoidance column trains and validates with that
    env keyword, is evaluated on its own task as before, and every other run's environment is
    unchanged; the SPNN runs that read that column get a new hash through their prior's."""
    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    changed = build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=((factor, value),)))
    for spec in changed:
        if spec.run_id == "prior-oa-s0":
            assert spec.env_kwargs[keyword] == value
            assert keyword not in plain[spec.run_id].env_kwargs
            assert spec.eval_tasks == plain[spec.run_id].eval_tasks
            assert spec.config_hash() != plain[spec.run_id].config_hash()
        else:
            assert spec.env_kwargs == plain[spec.run_id].env_kwargs
            assert spec.eval_tasks == plain[spec.run_id].eval_tasks
    assert describe_value(factor, None) == default  # as the report names the task's own


@pytest.mark.parametrize(
    ("factor", "value"),
    [("oa_corridor", v) for v in (0.5, 500.0, float("nan"))]
    + [("oa_time_limit", v) for v in (5.0, 2000.0, float("nan"))],
)
def test_bad_avoidance_task_factor_is_refused(factor, value) -> None:
    with pytest.raises(ValueError, match=f"{factor}={value!r} is not allowed"):
        StudyConfig(budget_name="tiny", seeds=1, setup_changes=((factor, value),))


def _spnn_gates(changes: tuple = ()) -> tuple[dict, dict]:
    """(run id -> the SPNN policy's (gate, temperature) as its spec names them, run id -> spec)
    of a tiny one-seed plan with ``changes``."""
    specs = {
        s.run_id: s
        for s in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes))
    }
    gates = {
        run_id: (
            spec.sac_kwargs["policy_kwargs"].get("gate"),
            spec.sac_kwargs["policy_kwargs"].get("temperature"),
        )
        for run_id, spec in specs.items()
        if spec.agent == "spnn"
    }
    return gates, specs


def test_the_default_spnn_gate_is_the_switch_on_the_straight_path_and_soft_on_the_sine() -> None:
    gates, _ = _spnn_gates()
    assert gates == {"spnn-straight-s0": (None, None), "spnn-sine-s0": ("soft", 2.0)}


def test_the_switch_on_both_paths_names_no_gate_and_changes_only_the_sine_spnn() -> None:
    """spnn_gate_sine=null puts eq. 15's switch back on the sine path: no run's spec names a
    gate (runs made before the factor existed keep their hash), and only the sine SPNN run
    differs from the default plan's."""
    _, default = _spnn_gates()
    gates, specs = _spnn_gates((("spnn_gate_sine", None),))
    assert set(gates.values()) == {(None, None)}
    for run_id, spec in specs.items():
        same = spec.config_hash() == default[run_id].config_hash()
        assert same == (run_id != "spnn-sine-s0")


def test_spnn_gate_reaches_only_the_spnn_runs() -> None:
    """spnn_gate=soft with spnn_gate_sine=null: both SPNN runs get the soft gate at the given
    temperature; no other run changes."""
    _, default = _spnn_gates()
    changes = (("spnn_gate", "soft"), ("spnn_gate_sine", None), ("spnn_gate_temperature", 3.0))
    gates, specs = _spnn_gates(changes)
    assert gates == {"spnn-straight-s0": ("soft", 3.0), "spnn-sine-s0": ("soft", 3.0)}
    for run_id, spec in specs.items():
        if spec.agent != "spnn":
            assert spec.config_hash() == default[run_id].config_hash()


def test_spnn_d_th_sine_gives_the_sine_spnn_its_own_switch_distance() -> None:
    """spnn_d_th=17.5 with spnn_d_th_sine=7.5: the straight SPNN run switches at 17.5 m, the sine
    one at 7.5 m (its soft gate kept); no other run changes, and unset the sine path follows
    spnn_d_th."""
    _, default = _spnn_gates()
    _, specs = _spnn_gates((("spnn_d_th", 17.5), ("spnn_d_th_sine", 7.5)))
    d_th = {r: s.sac_kwargs["policy_kwargs"]["d_th"] for r, s in specs.items() if s.agent == "spnn"}
    assert d_th == {"spnn-straight-s0": 17.5, "spnn-sine-s0": 7.5}
    assert specs["spnn-sine-s0"].sac_kwargs["policy_kwargs"]["gate"] == "soft"
    for run_id, spec in specs.items():
        if spec.agent != "spnn":
            assert spec.config_hash() == default[run_id].config_hash()
    _, specs = _spnn_gates((("spnn_d_th", 17.5),))
    assert {s.sac_kwargs["policy_kwargs"]["d_th"] for s in specs.values() if s.agent == "spnn"} == {
        17.5
    }


def test_spnn_gate_corridor_reaches_both_spnn_runs_only() -> None:
    """The default hands both SPNN policies back at abs(g) / d_L >= 0.9 (the sine one keeps its
    soft gate), and bounds PNN's straight near KL reference alike (the sine one has its own
    bound, pnn_near_corridor_sine); spnn_gate_corridor=null (the paper's gate) names no bound
    and changes only the SPNN runs and PNN's straight run."""
    _, default = _spnn_gates()
    _, paper_gate = _spnn_gates((("spnn_gate_corridor", None),))
    own = {"pnn-sine-s0": 0.6}
    for run_id, spec in default.items():
        kwargs = spec.sac_kwargs.get("policy_kwargs", {})
        assert kwargs.get("gate_corridor") == (0.9 if spec.agent == "spnn" else None)
        bound = kwargs.get("near_reference_corridor")
        assert bound == own.get(run_id, 0.9 if spec.agent == "pnn" else None), run_id
        other = paper_gate[run_id].sac_kwargs.get("policy_kwargs", {})
        assert "gate_corridor" not in other
        assert other.get("near_reference_corridor") == own.get(run_id), run_id
        changed = spec.agent == "spnn" or run_id == "pnn-straight-s0"
        assert (spec.config_hash() == paper_gate[run_id].config_hash()) == (not changed)
    assert default["spnn-sine-s0"].sac_kwargs["policy_kwargs"]["gate"] == "soft"
    with pytest.raises(ValueError, match="spnn_gate_corridor=0.9 is not allowed with a learned"):
        StudyConfig(budget_name="tiny", seeds=1, setup_changes=(("spnn_gate", "learned"),))
    learned = (("spnn_gate", "learned"), ("spnn_gate_corridor", None))
    assert StudyConfig(budget_name="tiny", seeds=1, setup_changes=learned)


def test_spnn_switch_memory_reaches_spnns_hard_switch_only() -> None:
    """spnn_switch_memory=H: SPNN's straight runs (the hard switch) observe the latch (d_th,
    d_th + H) in training and evaluation and switch on it; the sine runs (the soft gate) and
    every other run keep their spec and hash."""
    unplayed = ("spnn_play_memory", None)  # the default plays the switch with a memory
    _, default = _spnn_gates((unplayed,))
    _, memory = _spnn_gates((unplayed, ("spnn_switch_memory", 10.0)))
    for run_id, spec in default.items():
        other = memory[run_id]
        latched = run_id == "spnn-straight-s0"
        assert (spec.config_hash() != other.config_hash()) == latched, run_id
        if latched:
            assert other.env_kwargs["obstacle_latch"] == [12.5, 22.5]
            assert all(kw["obstacle_latch"] == [12.5, 22.5] for _, _, kw in other.eval_tasks)
            assert other.sac_kwargs["policy_kwargs"]["gate_latch_key"] == "latch"
    assert parse_setup_changes(["spnn_switch_memory=10"]) == {"spnn_switch_memory": 10.0}
    with pytest.raises(ValueError, match=r"spnn_switch_memory=-1.0 is not allowed: expected a"):
        OURS.with_(spnn_switch_memory=-1.0)
    with pytest.raises(ValueError, match=r"spnn_switch_memory=10.0 depends on the path"):
        OURS.with_(spnn_play_memory=None, spnn_switch_memory=10.0).agent_env_kwargs("spnn")


def test_pnn_avoidance_column_adds_the_avoidance_column_to_pnns_runs_on_its_paths() -> None:
    """pnn_avoidance_column=straight: PNN's straight runs read [pf_straight, oa] with the path
    follower as their reference prior; PNN's sine runs and every other run keep their spec and
    hash; a one-agent study of PNN then trains the avoidance column it needs."""
    _, default = _spnn_gates((("pnn_avoidance_column", "neither"),))
    _, wider = _spnn_gates((("pnn_avoidance_column", "straight"),))
    for run_id, spec in default.items():
        other = wider[run_id]
        changed = run_id == "pnn-straight-s0"
        assert (spec.config_hash() != other.config_hash()) == changed, run_id
        if changed:
            assert other.deps == ("prior-pf_straight-s0", "prior-oa-s0")
            assert other.sac_kwargs["policy_kwargs"]["reference_prior"] == 0
    pnn_only = build_plan(
        StudyConfig(
            budget_name="tiny",
            seeds=1,
            agents=("pnn",),
            setup_changes=(("pnn_avoidance_column", "both"),),
        )
    )
    assert "prior-oa-s0" in {s.run_id for s in pnn_only}
    assert parse_setup_changes(["pnn_avoidance_column=true"]) == {"pnn_avoidance_column": True}
    assert OURS.with_(pnn_avoidance_column=True).pnn_avoidance_column == "both"
    with pytest.raises(ValueError, match=r"pnn_avoidance_column='left' is not allowed"):
        OURS.with_(pnn_avoidance_column="left")


def test_pnn_near_prior_kl_refers_pnns_near_samples_to_the_avoidance_column() -> None:
    """pnn_near_prior_kl=straight beside pnn_avoidance_column=both: PNN's straight runs name the
    avoidance column as the reference of their near samples, bounded by SPNN's corridor; the
    sine runs keep the avoidance column's spec; where PNN does not read the column, or its KL
    term has no clearance, the factor does nothing."""
    column = ("pnn_avoidance_column", "both")
    _, read = _spnn_gates((column, ("pnn_near_prior_kl", "neither")))
    _, near = _spnn_gates((column, ("pnn_near_prior_kl", "straight")))
    for run_id, spec in read.items():
        other = near[run_id]
        changed = run_id == "pnn-straight-s0"
        assert (spec.config_hash() != other.config_hash()) == changed, run_id
        if changed:
            kwargs = other.sac_kwargs["policy_kwargs"]
            assert (kwargs["reference_prior"], kwargs["near_reference_prior"]) == (0, 1)
            assert kwargs["near_reference_corridor"] == OURS.spnn_gate_corridor
    assert OURS.pnn_near_prior_kl == "both" and OURS.pnn_near_prior_kl_on("sine")
    for inert in (dict(pnn_avoidance_column="neither"), dict(pnn_prior_kl_clearance=None)):
        setup = OURS.with_(**inert)
        for path in ("straight", "sine"):
            kwargs = setup.sac_kwargs(agent="pnn", path=path)["policy_kwargs"]
            assert "near_reference_prior" not in kwargs, (inert, path)


def test_pnn_near_corridor_bounds_the_near_reference_of_pnns_runs_on_its_path() -> None:
    """pnn_near_corridor_sine=0.6 (the default) against None (SPNN's bound): PNN's sine runs
    bound their near reference at 0.6 d_L, the straight runs keep SPNN's bound and every other
    run its hash; pnn_near_corridor sets both paths; a bound outside (0, 1] is refused by
    name."""
    assert OURS.pnn_near_corridor_sine == 0.6 and PAPER.pnn_near_corridor_sine is None
    _, default = _spnn_gates((("pnn_near_corridor_sine", None),))
    _, bounded = _spnn_gates()
    for run_id, spec in default.items():
        other = bounded[run_id]
        changed = run_id == "pnn-sine-s0"
        assert (spec.config_hash() != other.config_hash()) == changed, run_id
        corridor = other.sac_kwargs.get("policy_kwargs", {}).get("near_reference_corridor")
        if run_id.startswith("pnn-"):
            assert corridor == (0.6 if changed else OURS.spnn_gate_corridor), run_id
    both = OURS.with_(pnn_near_corridor=0.7, pnn_near_corridor_sine=None)
    assert [both.pnn_near_corridor_of(p) for p in ("straight", "sine")] == [0.7, 0.7]
    refined = OURS.with_(pnn_near_corridor=0.7)
    assert [refined.pnn_near_corridor_of(p) for p in ("straight", "sine")] == [0.7, 0.6]
    assert OURS.with_(spnn_gate_corridor=None).pnn_near_corridor_of("straight") is None
    for name, value in (("pnn_near_corridor", 0.0), ("pnn_near_corridor_sine", 1.5)):
        with pytest.raises(ValueError, match=rf"{name}={value!r} is not allowed: expected a"):
            OURS.with_(**{name: value})


def test_pnn_clear_kl_names_the_clear_sonar_term_in_pnns_runs_alone() -> None:
    """pnn_clear_kl=1 with the sine refinement at 0 (the default): PNN's straight run names
    clear_kl and every other run keeps the hash it has without the term; a negative weight is
    refused by name."""
    spnn_off = ("spnn_clear_kl_sine", 0.0)  # SPNN's own term (on its sine runs by default) off
    _, default = _spnn_gates((("pnn_clear_kl", 0.0), spnn_off))
    _, clear = _spnn_gates((("pnn_clear_kl", 1.0), ("pnn_clear_kl_sine", 0.0), spnn_off))
    for run_id, spec in default.items():
        other = clear[run_id]
        changed = run_id == "pnn-straight-s0"
        assert (spec.config_hash() != other.config_hash()) == changed, run_id
        policy_kwargs = other.sac_kwargs.get("policy_kwargs", {})
        assert policy_kwargs.get("clear_kl") == (1.0 if changed else None), run_id
    with pytest.raises(ValueError, match=r"pnn_clear_kl=-1.0 is not allowed: expected a finite"):
        OURS.with_(pnn_clear_kl=-1.0)


def test_obstacle_kl_names_the_drawn_obstacle_term_and_the_span_in_the_chosen_runs() -> None:
    """Against the term off everywhere: the default (0.5 on PNN's and SPNN's sine runs) names
    obstacle_kl and the sonar's span in radians in those two runs alone, every other run keeps
    its hash; pnn_obstacle_kl_sine=1 does so in PNN's sine run, spnn_obstacle_kl=0.5 in SPNN's
    runs on both paths, and the span follows sonar_span; bad weights are refused by name."""
    _, off = _spnn_gates((("pnn_obstacle_kl_sine", 0.0), ("spnn_obstacle_kl_sine", 0.0)))
    for changes, changed_runs, weight in (
        ((), {"pnn-sine-s0", "spnn-sine-s0"}, 0.5),
        ((("pnn_obstacle_kl_sine", 1.0), ("spnn_obstacle_kl_sine", 0.0)), {"pnn-sine-s0"}, 1.0),
        (
            (
                ("pnn_obstacle_kl_sine", 0.0),
                ("spnn_obstacle_kl", 0.5),
                ("spnn_obstacle_kl_sine", None),
            ),
            {"spnn-sine-s0", "spnn-straight-s0"},
            0.5,
        ),
        ((("spnn_obstacle_kl_sine", 0.0), ("sonar_span", 120.0)), {"pnn-sine-s0"}, 0.5),
    ):
        _, drawn = _spnn_gates(changes)
        for run_id, spec in off.items():
            other = drawn[run_id]
            changed = run_id in changed_runs
            if dict(changes).get("sonar_span") is None:  # a span changes every sonar run
                assert (spec.config_hash() != other.config_hash()) == changed, run_id
            policy_kwargs = other.sac_kwargs.get("policy_kwargs", {})
            assert policy_kwargs.get("obstacle_kl") == (weight if changed else None), run_id
            span = math.radians(dict(changes).get("sonar_span", 180.0))
            assert policy_kwargs.get("obstacle_kl_span") == (span if changed else None), run_id
    assert (OURS.pnn_obstacle_kl, OURS.pnn_obstacle_kl_sine) == (0, 0.5)
    assert (OURS.spnn_obstacle_kl, OURS.spnn_obstacle_kl_sine) == (0, 0.5)
    assert (PAPER.pnn_obstacle_kl, PAPER.pnn_obstacle_kl_sine) == (0, None)
    with pytest.raises(ValueError, match=r"pnn_obstacle_kl_sine=-1.0 is not allowed: expected a"):
        OURS.with_(pnn_obstacle_kl_sine=-1.0)


def test_spnn_clear_kl_names_the_clear_sonar_term_in_spnns_sine_runs_alone() -> None:
    """The default spnn_clear_kl_sine=1 (spnn_clear_kl 0) against 0: SPNN's sine run names
    clear_kl, every other run keeps its hash; bad weights are refused by name."""
    _, off = _spnn_gates((("spnn_clear_kl_sine", 0.0),))
    _, clear = _spnn_gates()  # the default: 1 on the sine path
    for run_id, spec in off.items():
        other = clear[run_id]
        changed = run_id == "spnn-sine-s0"
        assert (spec.config_hash() != other.config_hash()) == changed, run_id
        if run_id.startswith("spnn-"):
            assert other.sac_kwargs["policy_kwargs"].get("clear_kl") == (1.0 if changed else None)
    assert (OURS.spnn_clear_kl, OURS.spnn_clear_kl_sine, PAPER.spnn_clear_kl) == (0.0, 1.0, 0.0)
    with pytest.raises(ValueError, match=r"spnn_clear_kl_sine=-2.0 is not allowed: expected a"):
        OURS.with_(spnn_clear_kl_sine=-2.0)


@pytest.mark.parametrize(
    ("factor", "value"),
    [
        ("spnn_gate_corridor", 0.0),
        ("spnn_gate_corridor", 1.2),
        ("spnn_d_th", 0.0),
        ("spnn_d_th_sine", -2.0),
        ("spnn_gate", "fuzzy"),
        ("spnn_gate_sine", "fuzzy"),
        ("spnn_gate_temperature", 0.0),
        ("spnn_gate_temperature", -1.0),
    ],
)
def test_bad_spnn_gate_or_switch_distance_is_refused(factor, value) -> None:
    with pytest.raises(ValueError, match=factor):
        StudyConfig(budget_name="tiny", seeds=1, setup_changes=((factor, value),))


def test_n_step_targets_reach_only_their_agents_runs() -> None:
    """spnn_n_steps / pnn_n_steps: DiscreteSAC's n_steps of that agent's runs, named in the
    spec only when it is not 1 (runs made before the factors existed keep their hash)."""

    def plan(spnn: int, pnn: int) -> dict:
        changes = (("spnn_n_steps", spnn), ("pnn_n_steps", pnn), ("pnn_n_steps_sine", None))
        config = StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes)
        return {s.run_id: s for s in build_plan(config)}

    one_step, spnn_only = plan(1, 1), plan(5, 1)
    assert all("n_steps" not in spec.sac_kwargs for spec in one_step.values())
    for run_id, spec in spnn_only.items():
        assert spec.sac_kwargs.get("n_steps") == (5 if spec.agent == "spnn" else None)
        same = spec.config_hash() == one_step[run_id].config_hash()
        assert same == (spec.agent != "spnn")
    assert {s.sac_kwargs.get("n_steps") for s in plan(1, 3).values() if s.agent == "pnn"} == {3}


def test_pf_n_steps_reaches_only_the_path_following_columns() -> None:
    """pf_n_steps: DiscreteSAC's n_steps of the two path-following columns' runs, named only
    when it is not 1; the avoidance column and every learner keep their spec and hash."""
    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    config = StudyConfig(budget_name="tiny", seeds=1, setup_changes=(("pf_n_steps", 8),))
    changed = set()
    for spec in build_plan(config):
        column = spec.run_id.startswith("prior-pf_")
        assert spec.sac_kwargs.get("n_steps") == (
            8 if column else plain[spec.run_id].sac_kwargs.get("n_steps")
        )
        if spec.config_hash() != plain[spec.run_id].config_hash():
            changed.add(spec.run_id)
    assert changed == {"prior-pf_straight-s0", "prior-pf_sine-s0"}
    with pytest.raises(ValueError, match=r"pf_n_steps=0 is not allowed: expected an integer >= 1"):
        OURS.with_(pf_n_steps=0)


def test_pf_validation_every_reaches_only_the_path_following_columns_checks() -> None:
    """pf_validation_every: the path-following columns validate every N episodes; the
    avoidance column and the learners keep the default grid, spec and hash."""
    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    config = StudyConfig(budget_name="tiny", seeds=1, setup_changes=(("pf_validation_every", 5),))
    for spec in build_plan(config):
        column = spec.run_id.startswith("prior-pf_")
        expected = 5 if column else plain[spec.run_id].validation.get("every")
        assert spec.validation.get("every") == expected, spec.run_id
        assert (spec.config_hash() != plain[spec.run_id].config_hash()) == column
    with pytest.raises(ValueError, match=r"pf_validation_every=0 is not allowed: expected an"):
        OURS.with_(pf_validation_every=0)


def test_pnn_net_arch_widens_only_pnns_new_column() -> None:
    """pnn_net_arch: the hidden widths of PNN's runs alone (its prior column, the source columns
    and the other learners keep net_arch's), named only when set, so every other run keeps its
    hash; [] means net_arch's, and a zero width is refused naming the value."""
    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    changes = parse_setup_changes(["pnn_net_arch=[255,255]"])
    assert changes == {"pnn_net_arch": (255, 255)}
    config = StudyConfig(budget_name="tiny", seeds=1, setup_changes=tuple(changes.items()))
    for spec in build_plan(config):
        pnn = spec.agent == "pnn"
        if spec.sac_kwargs:  # the PID baselines train nothing
            widths = spec.sac_kwargs["policy_kwargs"]["net_arch"]
            assert widths == ([255, 255] if pnn else list(OURS.net_arch)), spec.run_id
        assert (spec.config_hash() != plain[spec.run_id].config_hash()) == pnn, spec.run_id
    same = StudyConfig(budget_name="tiny", seeds=1, setup_changes=(("pnn_net_arch", ()),))
    assert {s.config_hash() for s in build_plan(same)} == {s.config_hash() for s in plain.values()}
    with pytest.raises(ValueError, match=r"pnn_net_arch=\(64, 0\) is not allowed: expected widths"):
        OURS.with_(pnn_net_arch=(64, 0))
    with pytest.raises(ValueError, match=r"--set 'pnn_net_arch=255' is not allowed.*\[255, 255\]"):
        parse_setup_changes(["pnn_net_arch=255"])


def test_pnn_n_steps_sine_replaces_pnn_n_steps_on_the_sine_path_only() -> None:
    """pnn_n_steps_sine: PNN's n on the sine path; its straight-path runs keep pnn_n_steps,
    and a sine-path n of 1 leaves those runs' specs as one-step targets make them."""
    changes = parse_setup_changes(["pnn_n_steps=8", "pnn_n_steps_sine=1"])
    config = StudyConfig(budget_name="tiny", seeds=1, setup_changes=tuple(changes.items()))
    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    for spec in build_plan(config):
        if spec.agent == "pnn":
            path = spec.run_id.split("-")[1]
            assert spec.sac_kwargs.get("n_steps") == (8 if path == "straight" else None)
        if spec.agent != "pnn" or "sine" in spec.run_id:
            assert spec.config_hash() == plain[spec.run_id].config_hash(), spec.run_id
    with pytest.raises(ValueError, match=r"pnn_n_steps_sine=2.*depends on the path"):
        PAPER.with_(pnn_n_steps_sine=2).sac_kwargs(agent="pnn")
    with pytest.raises(ValueError, match=r"pnn_n_steps_sine=true' is not allowed.*an integer"):
        parse_setup_changes(["pnn_n_steps_sine=true"])
    assert describe_value("pnn_n_steps_sine", None) == "as on the straight path"


def test_pnn_prior_kl_clearance_reaches_only_pnn_runs_when_set() -> None:
    """pnn_prior_kl_clearance: PNN's policy keyword prior_kl_clearance, named only when set
    (runs made before the factor existed keep their hash); no other run changes."""
    unset = (("pnn_prior_kl", 1.0), ("pnn_prior_kl_clearance", None))
    config = StudyConfig(budget_name="tiny", seeds=1, setup_changes=unset)
    plain = {s.run_id: s for s in build_plan(config)}
    changes = (("pnn_prior_kl", 1.0), ("pnn_prior_kl_clearance", 8.0))
    for spec in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes)):
        policy_kwargs = spec.sac_kwargs.get("policy_kwargs", {})
        if spec.agent == "pnn":
            assert policy_kwargs["prior_kl_clearance"] == 8.0
            assert policy_kwargs["prior_kl"] == 1.0
        else:
            assert spec.config_hash() == plain[spec.run_id].config_hash(), spec.run_id
    assert all(
        "prior_kl_clearance" not in s.sac_kwargs.get("policy_kwargs", {}) for s in plain.values()
    )
    no_term = (("pnn_prior_kl", 0.0), ("pnn_prior_kl_clearance", 8.0))
    for spec in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=no_term)):
        assert "prior_kl_clearance" not in spec.sac_kwargs.get("policy_kwargs", {})
    for bad in (0, -1.0):
        with pytest.raises(ValueError, match="pnn_prior_kl_clearance"):
            StudyConfig(
                budget_name="tiny", seeds=1, setup_changes=(("pnn_prior_kl_clearance", bad),)
            )


@pytest.mark.parametrize("factor", ["spnn_n_steps", "pnn_n_steps", "pnn_n_steps_sine"])
@pytest.mark.parametrize("value", [0, -2, 2.5])
def test_bad_n_steps_is_refused(factor, value) -> None:
    with pytest.raises(ValueError, match=factor):
        StudyConfig(budget_name="tiny", seeds=1, setup_changes=((factor, value),))


def _offset_runs(changes: tuple) -> set[str]:
    """The runs that oa_offset_obs (with ``changes``) gives the goal offset, checking that they
    get it in training and evaluation alike and that every other run is unchanged."""
    plain = {
        s.run_id: s
        for s in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes))
    }
    changed = build_plan(
        StudyConfig(budget_name="tiny", seeds=1, setup_changes=(*changes, ("oa_offset_obs", True)))
    )
    touched = set()
    for spec in changed:
        if spec.env_kwargs.get("goal_offset"):
            touched.add(spec.run_id)
            assert all(kw["goal_offset"] is True for _, _, kw in spec.eval_tasks)
        else:
            assert spec.env_kwargs == plain[spec.run_id].env_kwargs
            assert spec.eval_tasks == plain[spec.run_id].eval_tasks
    return touched


def test_oa_offset_obs_reaches_the_avoidance_column_and_the_learners_that_read_it() -> None:
    """oa_offset_obs: the avoidance column trains and is evaluated with its offset in the goal
    part, and the planning runs of every learner that reads the column (SPNN; PNN where it
    reads the avoidance column) observe it too, so that the column reads what it was trained
    on; no other run changes."""
    assert _offset_runs(()) == {
        "prior-oa-s0",
        "spnn-straight-s0",
        "spnn-sine-s0",
        "pnn-straight-s0",
        "pnn-sine-s0",
    }
    alone = (("pnn_avoidance_column", "neither"),)  # PNN reads its path column alone
    assert _offset_runs(alone) == {"prior-oa-s0", "spnn-straight-s0", "spnn-sine-s0"}


def test_spnn_action_smoothness_reaches_only_spnn_runs_when_on() -> None:
    """spnn_action_smoothness: SPNN's policy keyword action_smoothness, named only when > 0
    (runs made before the factor existed keep their hash); no other run changes."""
    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    changes = tuple(parse_setup_changes(["spnn_action_smoothness=1"]).items())
    for spec in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes)):
        policy_kwargs = spec.sac_kwargs.get("policy_kwargs", {})
        if spec.agent == "spnn":
            assert policy_kwargs["action_smoothness"] == 1.0
        else:
            assert spec.config_hash() == plain[spec.run_id].config_hash(), spec.run_id
    assert all("action_smoothness" not in s.sac_kwargs.get("policy_kwargs", {})
               for s in plain.values())  # fmt: skip
    with pytest.raises(ValueError, match=r"spnn_action_smoothness=-1.0 is not allowed"):
        StudyConfig(budget_name="tiny", seeds=1, setup_changes=(("spnn_action_smoothness", -1.0),))


def test_sonar_span_and_sectors_reach_every_task_only_off_the_default() -> None:
    """sonar_span (degrees) / sonar_sectors: the env keywords of every run, named only off the
    180 deg / 9 sectors default (runs made before the factors existed keep their hash); the
    avoidance column's task then observes q sectors over the span; bad values are refused."""
    import gymnasium as gym

    import rov_envs  # noqa: F401 - registers the tasks
    from sb3_pnn.reproduce.planning.setups import OURS

    assert "sonar_span" not in OURS.env_kwargs() and "sonar_sectors" not in OURS.env_kwargs()
    wide = OURS.with_(sonar_span=360.0, sonar_sectors=18)
    kwargs = wide.train_env_kwargs("rov_envs/ObstacleAvoidance-v0")
    assert kwargs["sonar_span"] == pytest.approx(2 * math.pi) and kwargs["sonar_sectors"] == 18
    env = gym.make("rov_envs/ObstacleAvoidance-v0", **kwargs)
    assert env.observation_space["sonar"].shape == (18,)
    assert env.unwrapped.config.sonar_span == pytest.approx(2 * math.pi)
    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    changes = tuple(parse_setup_changes(["sonar_span=360", "sonar_sectors=18"]).items())
    changed = build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes))
    assert all(s.config_hash() != plain[s.run_id].config_hash() for s in changed)
    for bad in (("sonar_span", 0.0), ("sonar_span", 400.0), ("sonar_sectors", 0)):
        with pytest.raises(ValueError, match=f"{bad[0]}={bad[1]!r} is not allowed"):
            OURS.with_(**dict([bad]))


def test_los_lookahead_reaches_the_path_tasks_only_off_the_default() -> None:
    """los_lookahead: the env keyword of every run, named only off rov_envs' 5 m (earlier runs
    keep their hash); the path-following task then reads a_c from the course toward the path
    point Delta ahead (atan(d / Delta) off the path, heading along it); bad values refused."""
    import gymnasium as gym

    import rov_envs  # noqa: F401 - registers the tasks
    from sb3_pnn.reproduce.planning.setups import OURS

    assert "los_lookahead" not in OURS.env_kwargs()
    long = OURS.with_(los_lookahead=10.0)
    headings = []
    for setup in (OURS, long):
        kwargs = {**setup.train_env_kwargs("rov_envs/PathFollowingStraight-v0")}
        kwargs["start_noise"] = [0.0, 0.0]
        env = gym.make("rov_envs/PathFollowingStraight-v0", **kwargs)
        env.reset(seed=0)
        obs = env.unwrapped.set_pose(20.0, 4.0, 0.0)
        headings.append(float(obs["path"][0]) * math.pi)
    # heading along the line 4 m to its left: the course points atan(4 / Delta) back to it
    assert abs(headings[0]) == pytest.approx(math.atan(4.0 / 5.0), abs=1e-4)
    assert abs(headings[1]) == pytest.approx(math.atan(4.0 / 10.0), abs=1e-4)
    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    changes = tuple(parse_setup_changes(["los_lookahead=10"]).items())
    changed = build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes))
    assert all(s.config_hash() != plain[s.run_id].config_hash() for s in changed)
    for bad in (0.1, 200.0, float("nan")):
        with pytest.raises(ValueError, match="los_lookahead=.* is not allowed"):
            OURS.with_(los_lookahead=bad)


def test_learner_sonar_noise_perturbs_the_learners_training_episodes_only() -> None:
    """learner_sonar_noise: the learners' training env reads a noisy sonar; their validation
    checks, their evaluation and the source columns' runs read it noise-free (the columns keep
    their hash); the noise is real (the same pose near an obstacle reads otherwise); bad values
    refused."""
    import gymnasium as gym
    import numpy as np

    from sb3_pnn.reproduce.planning.setups import validation_env_kwargs

    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    changes = tuple(parse_setup_changes(["learner_sonar_noise=1.0"]).items())
    noisy = build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes))
    for spec in noisy:
        learner = spec.kind == "transfer"
        assert ("sonar_noise" in spec.env_kwargs) is learner, spec.run_id
        assert (spec.config_hash() != plain[spec.run_id].config_hash()) is learner, spec.run_id
        assert all("sonar_noise" not in kwargs for _, _, kwargs in spec.eval_tasks)
        assert "sonar_noise" not in validation_env_kwargs(spec.env_kwargs)
    spec = next(s for s in noisy if s.run_id == "spnn-straight-s0")
    readings = []
    for kwargs in (spec.env_kwargs, validation_env_kwargs(spec.env_kwargs)):
        env = gym.make(spec.env_id, **kwargs)
        env.reset(seed=0)
        x, y, _ = env.unwrapped.obstacles[0]
        readings.append(np.asarray(env.unwrapped.set_pose(x - 8.0, y, 0.0)["sonar"]))
    assert np.abs(readings[0] - readings[1]).max() > 0.005  # 1 m of 25: well above rounding
    for bad in (-1.0, 30.0, float("nan")):
        with pytest.raises(ValueError, match="learner_sonar_noise=.* is not allowed"):
            OURS.with_(learner_sonar_noise=bad)


@pytest.mark.parametrize(("factor", "column"), [("oa_budget", "oa"), ("pf_sine_budget", "pf_sine")])
def test_column_budget_scales_its_column_alone(factor: str, column: str) -> None:
    """oa_budget / pf_sine_budget: that column's runs train that multiple of the budget's
    episodes (and change spec); the other columns and every other run keep theirs and their
    hash; bad values refused."""
    one = ((factor, 1.0),)
    plain = {s.run_id: s for s in build_plan(StudyConfig("tiny", seeds=1, setup_changes=one))}
    changes = tuple(parse_setup_changes([f"{factor}=2"]).items())
    longer = build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes))
    for spec in longer:
        base = plain[spec.run_id]
        scaled = spec.run_id.startswith(f"prior-{column}-")
        assert spec.episodes == (2 * base.episodes if scaled else base.episodes), spec.run_id
        assert (spec.config_hash() != base.config_hash()) is scaled, spec.run_id
    assert OURS.with_(**{factor: 0.01}).column_episodes(column, 3) == 1
    for bad in (0.0, -1.0, 21.0, float("nan")):
        with pytest.raises(ValueError, match=f"{factor}=.* is not allowed"):
            OURS.with_(**{factor: bad})


LEARNERS = ("pnn", "spnn", "sac_single", "sac_multi")


def _assert_learners_only(key: str, value: float, setting: str, base: tuple = ()) -> None:
    """``--set setting`` (on top of ``base``) names DiscreteSAC keyword ``key`` = ``value`` in
    the four learners' runs only: the source columns and baselines keep their hashes, and
    without it no run names the keyword."""
    plain = {
        s.run_id: s
        for s in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=base))
    }
    changes = base + tuple(parse_setup_changes([setting]).items())
    for spec in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes)):
        learner = spec.agent in LEARNERS
        assert spec.sac_kwargs.get(key) == (value if learner else None)
        if not learner:
            assert spec.config_hash() == plain[spec.run_id].config_hash(), spec.run_id
    assert all(key not in s.sac_kwargs for s in plain.values())


def test_exploration_epsilon_reaches_the_learners_only_when_on() -> None:
    """exploration_epsilon: a DiscreteSAC keyword of the four learners' runs (not the source
    columns'), named only when > 0; a bad value is refused."""
    as_all = (("pnn_exploration_epsilon", None), ("pnn_exploration_epsilon_sine", None))
    _assert_learners_only("exploration_epsilon", 0.05, "exploration_epsilon=0.05", as_all)
    with pytest.raises(ValueError, match=r"exploration_epsilon=1.0 is not allowed"):
        StudyConfig(budget_name="tiny", seeds=1, setup_changes=(("exploration_epsilon", 1.0),))


def test_mirror_augmentation_reaches_the_learners_only_when_on() -> None:
    """mirror_augmentation: the four learners' runs (not the source columns') name rov_envs'
    mirror map as DiscreteSAC's ``mirror``; off, no run names it."""
    _assert_learners_only("mirror", rov_envs.LEFT_RIGHT_MIRROR, "mirror_augmentation=true")


def test_spnn_off_path_kl_reaches_spnn_runs_on_the_path_it_names() -> None:
    """spnn_off_path_kl_sine (the default: 1): SPNN's sine runs alone name ``off_path_kl``; with
    it at 0 no run names it and every other run keeps its hash; spnn_off_path_kl with the sine
    refinement null names it on both paths; pnn_off_path_kl names it in PNN's runs alone; a
    negative weight is refused by name."""
    off = (("spnn_off_path_kl_sine", 0.0),)
    plain = {
        s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=off))
    }
    assert all("off_path_kl" not in s.sac_kwargs.get("policy_kwargs", {}) for s in plain.values())
    cases = (
        ((), ("sine",), 1.0),
        (("spnn_off_path_kl=0.5", "spnn_off_path_kl_sine=null"), ("straight", "sine"), 0.5),
    )
    for settings, paths, value in cases:
        changes = tuple(parse_setup_changes(list(settings)).items())
        for spec in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes)):
            on = spec.agent == "spnn" and spec.path in paths
            weight = spec.sac_kwargs.get("policy_kwargs", {}).get("off_path_kl")
            assert weight == (value if on else None), spec.run_id
            assert (spec.config_hash() != plain[spec.run_id].config_hash()) is on, spec.run_id
    changes = (*off, ("pnn_off_path_kl", 2.0))
    for spec in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes)):
        weight = spec.sac_kwargs.get("policy_kwargs", {}).get("off_path_kl")
        assert weight == (2.0 if spec.agent == "pnn" else None), spec.run_id
    with pytest.raises(
        ValueError,
        match=r"spnn_off_path_kl_sine=-1.0 is not allowed: expected a finite weight >= 0",
    ):
        StudyConfig(
            budget_name="tiny", seeds=1, setup_changes=(("spnn_off_path_kl_sine", -1.0),)
        ).setup()


def test_oa_mirror_reaches_the_avoidance_column_only_and_trains_on_its_task() -> None:
    """oa_mirror: the avoidance column's runs alone name rov_envs' mirror map (every other run
    keeps its hash); the map fits ObstacleAvoidance's observation, which has no path part, and a
    DiscreteSAC with it takes gradient steps there."""
    import gymnasium as gym

    from sb3_pnn import DiscreteSAC

    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    changes = tuple(parse_setup_changes(["oa_mirror=true"]).items())
    plan = build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes))
    for spec in plan:
        column = spec.run_id.startswith("prior-oa-")
        assert spec.sac_kwargs.get("mirror") == (rov_envs.LEFT_RIGHT_MIRROR if column else None)
        assert (spec.config_hash() != plain[spec.run_id].config_hash()) is column, spec.run_id
    spec = next(s for s in plan if s.run_id.startswith("prior-oa-"))
    env = gym.make(spec.env_id, **{k: v for k, v in spec.env_kwargs.items() if k != "start_noise"})
    model = DiscreteSAC("MultiInputPolicy", env, seed=0, device="cpu", **spec.sac_kwargs)
    model.learn(300)
    assert "path" not in model.mirror["observations"]
    assert model._n_updates > 0


def test_planning_obstacle_penalty_reaches_the_learners_planning_envs_only() -> None:
    """planning_obstacle_penalty: rov_envs' ``obstacle_penalty`` in the learners' training and
    evaluation envs (the source columns and baselines keep the paper's eq. 20 and their
    hashes); at 1, the paper's weight, no run names it; a bad value is refused naming it."""
    plain = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    changes = (("planning_obstacle_penalty", 0.0),)
    for spec in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes)):
        learner = spec.agent in LEARNERS
        expected = 0.0 if learner else None
        assert spec.env_kwargs.get("obstacle_penalty") == expected, spec.run_id
        assert {t[2].get("obstacle_penalty") for t in spec.eval_tasks} <= {expected}
        if not learner:
            assert spec.config_hash() == plain[spec.run_id].config_hash(), spec.run_id
    assert all("obstacle_penalty" not in s.env_kwargs for s in plain.values())
    with pytest.raises(ValueError, match=r"planning_obstacle_penalty=-1 is not allowed"):
        StudyConfig(budget_name="tiny", seeds=1, setup_changes=(("planning_obstacle_penalty", -1),))


def test_pnn_exploration_epsilon_is_pnn_s_own_and_the_sine_path_can_differ() -> None:
    """The default study: PNN explores with epsilon 0.05 on the straight path and 0 on the
    sinusoid (pnn_exploration_epsilon, pnn_exploration_epsilon_sine); every other run is
    what exploration_epsilon alone makes it, and None falls back to the factor refined."""
    default = {s.run_id: s for s in build_plan(StudyConfig(budget_name="tiny", seeds=1))}
    as_all = (("pnn_exploration_epsilon", None), ("pnn_exploration_epsilon_sine", None))
    plain = {
        s.run_id: s
        for s in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=as_all))
    }
    for run_id, spec in default.items():
        expected = 0.05 if run_id.startswith("pnn-straight") else None
        assert spec.sac_kwargs.get("exploration_epsilon") == expected, run_id
        if expected is None:
            assert spec.config_hash() == plain[run_id].config_hash(), run_id
    assert OURS.exploration_epsilon_of("pnn", "sine") == 0.0
    assert OURS.exploration_epsilon_of("spnn", "straight") == 0.0
    only_pnn = PAPER.with_(exploration_epsilon=0.1, pnn_exploration_epsilon=0.2)
    assert only_pnn.exploration_epsilon_of("pnn", "sine") == 0.2
    assert only_pnn.exploration_epsilon_of("sac_multi", "sine") == 0.1
    with pytest.raises(ValueError, match=r"pnn_exploration_epsilon_sine=0.3.*depends on the path"):
        PAPER.with_(pnn_exploration_epsilon_sine=0.3).sac_kwargs(agent="pnn")
    for name, bad in (("pnn_exploration_epsilon", 1.0), ("pnn_exploration_epsilon_sine", -0.1)):
        with pytest.raises(ValueError, match=rf"{name}={bad!r} is not allowed.*\[0, 1\)"):
            PAPER.with_(**{name: bad})
    assert parse_setup_changes(["pnn_exploration_epsilon_sine=null"]) == {
        "pnn_exploration_epsilon_sine": None
    }
    assert describe_value("pnn_exploration_epsilon_sine", None) == "as on the straight path"


def test_the_set_up_and_the_policies_name_the_tasks_own_sonar() -> None:
    """The set-ups' sonar defaults (180 deg, 9 sectors) and the progressive policies' sonar key
    and range are rov_envs' own, so that the default study names no sonar keyword and SPNN's
    gate reads metres."""
    import gymnasium as gym

    import rov_envs  # noqa: F401 - registers the tasks
    from rov_envs.sim.config import SONAR_RANGE, SONAR_SECTORS, SONAR_SPAN
    from sb3_pnn.progressive.progressive_policy import SONAR_KEY
    from sb3_pnn.progressive.progressive_policy import SONAR_RANGE as POLICY_RANGE
    from sb3_pnn.reproduce.planning.setups import OURS, PAPER

    for setup in (OURS, PAPER):
        assert math.radians(setup.sonar_span) == pytest.approx(SONAR_SPAN)
        assert setup.sonar_sectors == SONAR_SECTORS
    assert POLICY_RANGE == SONAR_RANGE
    assert SONAR_KEY in gym.make("rov_envs/PlanningStraight-v0").observation_space.spaces


def test_learner_target_entropy_reaches_the_learners_only() -> None:
    """learner_target_entropy_ratio: the four learners' target entropy (named only off the
    default 0.5), the source columns keep target_entropy_ratio and their hashes; None falls
    back; a bad value is refused naming it."""
    _assert_learners_only("target_entropy_ratio", 0.2, "learner_target_entropy_ratio=0.2")
    both = PAPER.with_(target_entropy_ratio=0.3)
    assert both.target_entropy_ratio_of("spnn") == both.target_entropy_ratio_of("") == 0.3
    own = both.with_(learner_target_entropy_ratio=0.2)
    assert (own.target_entropy_ratio_of("pnn"), own.target_entropy_ratio_of("")) == (0.2, 0.3)
    for bad in (0.0, 1.5, float("nan"), "x"):
        with pytest.raises(ValueError, match=rf"learner_target_entropy_ratio={bad!r} is not"):
            PAPER.with_(learner_target_entropy_ratio=bad)
    assert describe_value("learner_target_entropy_ratio", None) == "as the source columns'"


def test_start_spreads_reach_their_own_tasks_only() -> None:
    """planning_start_spread multiplies the training start noise of the learners' planning
    runs only (pf_start_spread that of the path-following columns); the avoidance column,
    validation and evaluation keep 1x and the source columns and baselines their hashes; bad
    values are refused naming them."""
    base = StudyConfig(budget_name="tiny", seeds=1)
    plain = {s.run_id: s for s in build_plan(base)}
    changes = tuple(parse_setup_changes(["planning_start_spread=3"]).items())
    one_x = [1.0, math.radians(5.0)]
    for spec in build_plan(StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes)):
        if spec.kind == "baseline":  # the PID baselines are not trained
            assert spec.config_hash() == plain[spec.run_id].config_hash(), spec.run_id
            continue
        noise = spec.env_kwargs["start_noise"]
        if spec.kind == "prior":
            expected = [5 * n for n in one_x] if "PathFollowing" in spec.env_id else one_x
            assert spec.config_hash() == plain[spec.run_id].config_hash(), spec.run_id
        else:
            assert "Planning" in spec.env_id
            expected = [3 * n for n in one_x]
            assert plain[spec.run_id].env_kwargs["start_noise"] == pytest.approx(one_x)
        assert noise == pytest.approx(expected), spec.run_id
        assert all("start_noise" not in kwargs for _, _, kwargs in spec.eval_tasks)
    assert describe_value("planning_start_spread", None) == "as the training start noise"
    for name in ("pf_start_spread", "planning_start_spread"):
        for bad in (-1.0, 31.0, float("nan"), "x"):
            with pytest.raises(ValueError, match=rf"{name}={bad!r} is not allowed"):
                OURS.with_(**{name: bad})
