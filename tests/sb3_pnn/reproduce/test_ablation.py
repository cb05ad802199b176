"""The ablation: one factor per cell, each planning run on its own cell's priors, the table."""

from __future__ import annotations

import json
import re

import pytest
from reproduce_helpers import fake_work

from sb3_pnn.reproduce.ablation.catalog import (
    CELLS,
    NOT_ABLATED,
    TASKS,
    AblationConfig,
    all_cells,
    build_ablation_plan,
    cell_of,
    run_id,
)
from sb3_pnn.reproduce.cli import main
from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import (
    AGENT_FACTORS,
    OURS,
    PAPER,
    TrainingSetup,
    describe_value,
    parse_setup_changes,
    parse_updates,
)


def test_each_cell_changes_one_factor_of_its_base() -> None:
    cells = all_cells()
    assert cells[0].setup == PAPER and CELLS["ours"].setup == OURS
    for cell in cells:
        base = PAPER if cell.name.startswith("paper") else OURS
        changed = cell.setup.differences(base)
        if cell.name in ("paper", "ours") or cell.prior_share != 1.0:
            assert changed == {}
        else:
            factor = cell.name.split("+")[1].split("=")[0]
            assert list(changed) == [factor], cell.name
    # every departure of OURS is tried alone on the paper and put back alone in ours, unless
    # no ablation task reads it (then the reason names where it is measured)
    for factor in OURS.differences(PAPER):
        if factor in NOT_ABLATED:
            assert not any(f"+{factor}=" in c.name for c in cells)
            assert "docs/ablation" in NOT_ABLATED[factor]
            continue
        assert any(c.name.startswith(f"paper+{factor}=") for c in cells)
        assert any(c.name.startswith(f"ours+{factor}=") for c in cells)
    # the factors: the vehicle, and 1 update per k steps
    assert CELLS["paper+vehicle=wu2018"].setup.vehicle == "wu2018"
    assert parse_updates(CELLS["paper+updates=step:4"].setup.updates) == ((4, "step"), 1)
    assert parse_updates(CELLS["ours+updates=step:1"].setup.updates) == ((1, "step"), 1)


def test_plan_priors_per_cell_and_before_use() -> None:
    config = AblationConfig("quick", seeds=3, cells=("paper", "ours+prior_budget=0.5"))
    plan = build_ablation_plan(config)
    ids = [spec.run_id for spec in plan]
    assert len(ids) == len(set(ids))
    by_id = {spec.run_id: spec for spec in plan}
    for spec in plan:
        assert all(ids.index(d) < ids.index(spec.run_id) for d in spec.deps)
    spnn = by_id[run_id("paper", "planning_straight", 2)]
    assert spnn.agent == "spnn"
    assert spnn.deps == (run_id("paper", "pf_straight", 0), run_id("paper", "oa", 0))
    assert spnn.env_kwargs["start_noise"] == [0.0, 0.0]  # the paper trains from the exact pose
    assert spnn.sac_kwargs["policy_kwargs"] == {  # the paper's eq. 15, written out
        "net_arch": [255, 255],
        "d_th": 12.5,
        "sigma": 0.5,
        "own_weight": 0.5,
        "start_as_prior": False,
        "init_from_prior": False,
        "prior_kl": 0.0,
    }
    # half-budget priors are runs of their own; the cell has no single-task rows of its own
    half = by_id[run_id("ours+prior_budget=0.5", "planning_straight", 0)]
    for dep in half.deps:  # half of ours (whose avoidance column trains oa_budget times longer)
        task = dep.split("-")[1][:-6]
        ours = OURS.column_episodes(task, config.budget.episodes[task])
        assert by_id[dep].episodes == round(ours * 0.5)
    assert run_id("ours+prior_budget=0.5", "oa", 1) not in by_id
    assert by_id[run_id("paper", "oa", 1)].episodes == config.budget.episodes["oa"]
    # evaluation on the run's own task, with the cell's environment (no training start noise)
    oa = by_id[run_id("paper", "oa", 1)]
    assert oa.eval_tasks == (("own", TASKS["oa"][0], PAPER.env_kwargs()),)


@pytest.mark.parametrize(
    ("bad", "match"),
    [({"seeds": 0}, "seeds=0"), ({"cells": ("papr",)}, "cell 'papr' is unknown"),
     ({"tasks": ()}, "no task chosen"), ({"budget_name": "huge"}, "budget 'huge'")],
)  # fmt: skip
def test_bad_config_refused(bad, match) -> None:
    with pytest.raises(ValueError, match=match):
        AblationConfig(**bad)


STUDY_NO_NOISE = "ours+goal_obs=off+train_start_noise=off"


def test_composite_cell_is_its_base_with_each_factor_changed() -> None:
    """The study's own set-up with two factors put back: a cell the catalog lacks."""
    cell = cell_of(STUDY_NO_NOISE)
    assert cell.setup == OURS.with_(goal_obs=False, train_start_noise=False)
    assert cell.describe() == (
        "ours with training start noise off, goal part observed (avoidance reads it instead "
        "of the path) off"
    )
    # the catalog's words and the --set spellings name the same set-up; a catalog name is the
    # catalog's cell
    assert cell_of("ours+net_arch=255x255").setup == cell_of("ours+net_arch=[255,255]").setup
    assert cell_of("paper+vehicle=wu2018") is CELLS["paper+vehicle=wu2018"]
    # its planning runs learn at 1 update per 2 steps from its own seed-0 columns, trained at
    # 2 per step without start noise, none of them observing the goal part
    plan = build_ablation_plan(
        AblationConfig("tiny", seeds=2, cells=(STUDY_NO_NOISE,), tasks=("planning_straight",))
    )
    by_id = {spec.run_id: spec for spec in plan}
    spnn = by_id[run_id(STUDY_NO_NOISE, "planning_straight", 1)]
    assert spnn.deps == (run_id(STUDY_NO_NOISE, "pf_straight", 0), run_id(STUDY_NO_NOISE, "oa", 0))
    assert (spnn.sac_kwargs["train_freq"], spnn.sac_kwargs["gradient_steps"]) == ([2, "step"], 1)
    for dep in spnn.deps:
        assert (by_id[dep].sac_kwargs["train_freq"], by_id[dep].sac_kwargs["gradient_steps"]) == (
            [1, "step"],
            2,
        )
        assert by_id[dep].env_kwargs["start_noise"] == [0.0, 0.0]
        assert by_id[dep].env_kwargs["goal_obs"] is False


def test_planning_sine_only_when_asked_for(tmp_path) -> None:
    # the four tasks by default; PlanningSine on request, from the sine path's column
    assert "planning_sine" not in AblationConfig().tasks and "planning_sine" in TASKS
    plan = build_ablation_plan(
        AblationConfig("full", seeds=2, cells=(STUDY_NO_NOISE,), tasks=("planning_sine",))
    )
    by_id = {spec.run_id: spec for spec in plan}
    spnn = by_id[run_id(STUDY_NO_NOISE, "planning_sine", 1)]
    assert spnn.env_id == "rov_envs/PlanningSine-v0" and spnn.path == "sine"
    assert spnn.episodes == 400  # the paper's budget on the sinusoid (Figure 10)
    assert spnn.deps == (run_id(STUDY_NO_NOISE, "pf_sine", 0), run_id(STUDY_NO_NOISE, "oa", 0))
    assert by_id[spnn.deps[0]].env_id == "rov_envs/PathFollowingSine-v0"
    # the study's own set-up on the sine path trains the 5-seed study's SPNN run, field for field
    # (so the study's runs are that cell's rows without retraining them)
    ablation = build_ablation_plan(AblationConfig("full", 1, ("ours",), ("planning_sine",)))
    study = {spec.run_id: spec for spec in build_plan(StudyConfig(seeds=1))}
    pairs = [(ablation[-1], study["spnn-sine-s0"])]
    pairs += [(a, study[f"prior-{a.run_id.split('-')[1]}-s0"]) for a in ablation[:-1]]
    for mine, theirs in pairs:
        for field in ("env_id", "agent", "path", "seed", "episodes", "eval_episodes"):
            assert getattr(mine, field) == getattr(theirs, field), field
        for field in ("sac_kwargs", "env_kwargs", "validation"):
            assert getattr(mine, field) == getattr(theirs, field), field
    out = tmp_path / "ablation"
    argv = ["--ablation", "--tiny", "--seeds", "1", "--cells", STUDY_NO_NOISE, "--jobs", "1"]
    argv += ["--tasks", "planning_sine", "--no-progress", "--out", str(out)]
    assert main(argv, work=fake_work) == 0
    report = (out / "report.md").read_text()
    assert "PlanningSine is learned by SPNN from the cell's own seed-0 PathFollowingSine and " in (
        report
    )
    assert "| PlanningSine (SPNN) |" in report and "PlanningStraight" not in report


def test_composite_cell_row_in_the_report(tmp_path) -> None:
    out = tmp_path / "ablation"
    argv = ["--ablation", "--tiny", "--seeds", "1", "--cells", STUDY_NO_NOISE, "--jobs", "1"]
    argv += ["--tasks", "planning_straight", "--no-progress", "--out", str(out)]
    assert main(argv, work=fake_work) == 0
    report = (out / "report.md").read_text()
    assert f"--cells {STUDY_NO_NOISE} " in report  # the command that made it
    row = next(line for line in report.splitlines() if line.startswith(f"| `{STUDY_NO_NOISE}`"))
    assert "| ours with training start noise off, goal part observed " in row
    assert row.endswith(" |") and "100 % [" in row  # stand-in SPNN: 90 % of 2 episodes


@pytest.mark.parametrize(
    ("name", "match"),
    [("study+motion_obs=off", "cell 'study\\+motion_obs=off' is unknown"),
     ("ours+bogus=1", "'bogus=1' is not allowed: expected factor=value"),
     ("ours+updates=step:0", "updates='step:0' is not allowed"),
     ("ours+motion_obs=maybe", "expected a value like motion_obs=false"),
     ("ours+motion_obs", "'motion_obs' is not allowed"),
     ("ours+updates=step:4+updates=step:2", "'updates=step:2' is not allowed"),
     ("ours+prior_budget=0.5+motion_obs=off", "prior_budget is only the catalog's"),
     ("paper+vehicle=boat", "vehicle='boat' is not allowed: expected one of")],
)  # fmt: skip
def test_bad_composite_cell_refused(name: str, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        cell_of(name)


def test_bad_setup_refused() -> None:
    with pytest.raises(ValueError, match="updates='step:0'"):
        TrainingSetup(updates="step:0")
    with pytest.raises(ValueError, match="net_arch"):
        TrainingSetup(net_arch=())
    with pytest.raises(ValueError, match="target_entropy_ratio=0"):
        TrainingSetup(target_entropy_ratio=0)


def test_target_entropy_reaches_the_learner_only_when_changed() -> None:
    """Specs of runs made before the factor existed keep their hash (no key at the default)."""
    assert "target_entropy_ratio" not in PAPER.sac_kwargs()
    assert PAPER.with_(target_entropy_ratio=0.2).sac_kwargs()["target_entropy_ratio"] == 0.2


def test_cli_unknown_cell_one_line(capsys, tmp_path) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["--ablation", "--cells", "paper,ourz", "--out", str(tmp_path)])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert sum("error" in line for line in err.splitlines()) == 1  # usage, then one error line
    assert "cell 'ourz' is unknown; expected a cell of the catalog (--list) or" in err


def test_stand_in_ablation_report(tmp_path, capsys) -> None:
    out = tmp_path / "ablation"
    argv = ["--ablation", "--tiny", "--seeds", "2", "--cells", "paper,ours", "--jobs", "2"]
    argv += ["--tasks", "oa,planning_straight", "--no-progress", "--out", str(out)]
    assert main(argv, work=fake_work) == 0
    report = (out / "report.md").read_text()
    assert "Made by: `python -m sb3_pnn.reproduce --ablation --tiny --seeds 2" in report
    assert "| update schedule | 10 per episode | 1 per 2 steps |" in report
    # stand-ins: DiscreteSAC evaluates 60 %, SPNN 90 %, of 2 episodes per seed; seed s trains
    # for 60 (1 + s) s, so 1.5 min on average; the CPU time is the executor's own measurement
    assert "| `paper` | paper (see the set-up table) | 50 % [15, 85] (seeds: 50, 50 %);" in report
    assert re.search(r"1\.5 min \(\d+\.\d CPU-min\) \|", report)
    assert "| `ours` |" in report and "90 %" not in report  # 2 of 2 at 90 % rounds to 100 %
    assert "100 % [51, 100] (seeds: 100, 100 %)" in report
    capsys.readouterr()
    # a rerun resumes: every run was finished earlier, and the table is the same
    assert main(argv, work=fake_work) == 0
    assert "runs: 0 done now, 10 earlier, 0 failed" in capsys.readouterr().out
    assert (out / "report.md").read_text().split("Runs finished")[0] == report.split(
        "Runs finished"
    )[0]
    # a session with other cells adds its runs; the report then names each session's command
    more = ["--ablation", "--tiny", "--seeds", "2", "--cells", "ours+motion_obs=off", "--jobs", "2"]
    more += ["--tasks", "oa", "--no-progress", "--out", str(out)]
    assert main(more, work=fake_work) == 0
    report = (out / "report.md").read_text()
    assert "Made by these invocations, in order" in report
    assert (
        "1. `python -m sb3_pnn.reproduce --ablation --tiny --seeds 2 --cells paper,ours" in report
    )
    assert (
        "3. `python -m sb3_pnn.reproduce --ablation --tiny --seeds 2 --cells ours+motion_obs"
        in report
    )


def test_reduced_prior_budget_row_shows_its_source_columns(tmp_path) -> None:
    out = tmp_path / "ablation"
    argv = ["--ablation", "--tiny", "--seeds", "1", "--cells", "ours+prior_budget=0.5"]
    argv += ["--tasks", "pf_sine,oa,planning_straight", "--no-progress", "--out", str(out)]
    assert main(argv, work=fake_work) == 0
    row = next(
        line
        for line in (out / "report.md").read_text().splitlines()
        if line.startswith("| `ours+prior_budget=0.5`")
    )
    cells = [c.strip() for c in row.strip("|").split(" | ")]
    # pf_sine is no source column of PlanningStraight: the cell trains nothing there
    assert cells[2] == "as ours"
    # the seed-0 ObstacleAvoidance column, trained at half budget (stand-in: 1 of 2 episodes)
    assert cells[3].startswith("seed-0 column at 0.5 of the budget: 50 % [")
    assert cells[4].startswith("100 % [")  # stand-in SPNN: 90 % of 2 episodes rounds to 2


def test_made_by_quotes_a_sessions_note() -> None:
    from sb3_pnn.reproduce.ablation.report import made_by

    sessions = [
        {"command": "python -m sb3_pnn.reproduce --ablation --cells a", "wall_s": 600.0},
        {
            "command": "python -m sb3_pnn.reproduce --ablation --cells b",
            "wall_s": 120.0,
            "note": "stopped by hand after its first run",
        },
    ]
    lines = made_by("python -m sb3_pnn.reproduce --ablation --cells a,b", sessions)
    assert lines[2] == "1. `python -m sb3_pnn.reproduce --ablation --cells a` (10 min)"
    assert lines[3] == (
        "2. `python -m sb3_pnn.reproduce --ablation --cells b` (2 min; stopped by hand after its "
        "first run)"
    )


def kwargs_by_agent(changes: tuple) -> dict[str, dict]:
    """The policy keyword arguments of each transfer agent in a one-seed study of ``paper``
    with ``changes``."""
    from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan

    config = StudyConfig(budget_name="quick", seeds=1, setup_name="paper", setup_changes=changes)
    plan = build_plan(config)
    return {s.agent: s.sac_kwargs["policy_kwargs"] for s in plan if s.kind == "transfer"}


AGENT_FACTOR_CASES = [
    (("pnn_lateral_init", 0.0), "pnn", "lateral_scale_init"),
    (("pnn_critic_priors", False), "pnn", "critic_priors"),
    (("pnn_start_as_prior", True), "pnn", "start_as_prior"),
    (("spnn_start_as_prior", True), "spnn", "start_as_prior"),
    (("spnn_d_th", 8.0), "spnn", "d_th"),
    (("pnn_init_from_prior", True), "pnn", "init_from_prior"),
    (("spnn_init_from_prior", True), "spnn", "init_from_prior"),
    (("spnn_sigma", 1.0), "spnn", "sigma"),
    (("spnn_own_weight", 1.0), "spnn", "own_weight"),
    (("spnn_prior_kl", 2.0), "spnn", "prior_kl"),
    (("pnn_prior_kl", 2.0), "pnn", "prior_kl"),
]


@pytest.mark.parametrize(("change", "agent", "key"), AGENT_FACTOR_CASES)
def test_agent_factor_reaches_only_its_agent(change: tuple, agent: str, key: str) -> None:
    """A factor that one agent reads (``--set pnn_lateral_init=0``, ``pnn_critic_priors=false``,
    ``spnn_d_th=8``) reaches that agent's policy and nothing else changes; it is written even at
    the paper's value (the policies' own defaults are the recommended set-up's)."""
    default = kwargs_by_agent(())
    changed = kwargs_by_agent((change,))
    assert key in default[agent] and changed[agent][key] == change[1]
    assert {a: kw for a, kw in changed.items() if a != agent} == {
        a: kw for a, kw in default.items() if a != agent
    }
    name, value = change
    assert parse_setup_changes([f"{name}={str(value).lower()}"]) == {name: value}


def test_agent_factor_values_checked() -> None:
    # (pnn_lateral_init_sine reaches the PNN through pnn_lateral_init: test_critic_priors_per_path)
    assert {c[0]: (agent, key) for c, agent, key in AGENT_FACTOR_CASES} == AGENT_FACTORS
    assert OURS.sac_kwargs(agent="pnn", path="straight")["policy_kwargs"]["lateral_scale_init"] == 0
    # on the sine path ours is eq. 13's full scale
    assert OURS.sac_kwargs(agent="pnn", path="sine")["policy_kwargs"]["lateral_scale_init"] == 1
    # both set-ups switch at eq. 15's 12.5 m
    assert PAPER.sac_kwargs(agent="spnn")["policy_kwargs"]["d_th"] == 12.5
    assert OURS.sac_kwargs(agent="spnn", path="sine")["policy_kwargs"]["d_th"] == 12.5
    eight = OURS.with_(spnn_d_th=8.0).sac_kwargs(agent="spnn", path="straight")
    assert eight["policy_kwargs"]["d_th"] == 8.0
    # ours' gate differs by path, so an SPNN's keywords need the path
    with pytest.raises(ValueError, match="spnn_gate_sine='soft' depends on the path"):
        OURS.sac_kwargs(agent="spnn")
    with pytest.raises(ValueError, match=r"spnn_d_th=0\.0 is not allowed: expected a distance > 0"):
        OURS.with_(spnn_d_th=0.0)


@pytest.mark.parametrize("name", ["spnn_sigma", "spnn_own_weight", "spnn_prior_kl", "pnn_prior_kl"])
@pytest.mark.parametrize("bad", [-0.5, float("inf"), float("nan"), True, "half"])
def test_spnn_mixing_weights_checked(name: str, bad: object) -> None:
    """Eq. 15's weights are finite numbers >= 0; anything else is refused by name."""
    with pytest.raises(ValueError, match=rf"{name}=.* is not allowed: expected a finite weight"):
        OURS.with_(**{name: bad})


def test_stopped_ablation_session_is_recorded_and_the_report_quotes_it(
    tmp_path, capsys, monkeypatch
) -> None:
    import sb3_pnn.reproduce.running.executor as executor
    from sb3_pnn.reproduce.running.executor import ExecutionSummary

    def stopped(plan, store, work, jobs, quiet=False, pool=None):  # execute after Ctrl-C
        return ExecutionSummary(done=[plan[0].run_id], stopped=True)

    out = tmp_path / "ablation"
    argv = ["--ablation", "--tiny", "--seeds", "1", "--cells", "paper", "--tasks", "oa"]
    argv += ["--no-progress", "--out", str(out)]
    monkeypatch.setattr(executor, "execute", stopped)  # the CLI imports it when it runs
    assert main(argv, work=fake_work) == 130
    assert "stopped after 1 new run(s)" in capsys.readouterr().err
    (session,) = json.loads((out / "sessions.json").read_text())
    assert session["stopped"] is True and session["runs_done"] == 1
    assert session["command"].startswith("python -m sb3_pnn.reproduce --ablation --tiny")
    monkeypatch.undo()
    assert main(argv, work=fake_work) == 0  # the same command resumes and writes the report
    report = (out / "report.md").read_text()
    assert "stopped by the user after 1 new run(s)" in report


def test_several_updates_per_step() -> None:
    """``step:KxG``: G gradient steps every K environment steps, as DiscreteSAC reads them;
    at a 1.0 s control period ``step:1x2`` keeps a 0.5 s ``step:1`` schedule's updates per
    simulated second."""
    assert parse_updates("step:1x2") == ((1, "step"), 2)
    assert parse_updates("step:3x4") == ((3, "step"), 4)
    setup = TrainingSetup(updates="step:2", prior_updates="step:1x2")
    prior = setup.sac_kwargs(prior=True)
    assert (prior["train_freq"], prior["gradient_steps"]) == ([1, "step"], 2)
    learner = setup.sac_kwargs(agent="spnn", path="straight")
    assert (learner["train_freq"], learner["gradient_steps"]) == ([2, "step"], 1)
    assert describe_value("prior_updates", "step:1x2") == "2 per step"
    assert describe_value("updates", "step:4") == "1 per 4 steps"
    for bad in ("step:1x", "step:1x0", "step:0x2", "step:x2", "episode:2x3", "step:1x2x3"):
        with pytest.raises(ValueError, match=f"updates='{bad}' is not allowed: expected"):
            parse_updates(bad)
    with pytest.raises(ValueError, match="prior_updates='step:1x0' is not allowed"):
        TrainingSetup(prior_updates="step:1x0")


def test_avoidance_column_updates_change_only_its_runs() -> None:
    """``oa_updates`` gives the avoidance column its own schedule: its run's spec changes,
    every other run of the study keeps its spec (and hash)."""
    base = {s.run_id: s for s in build_plan(StudyConfig(seeds=1))}
    changed = StudyConfig(seeds=1, setup_changes=(("oa_updates", "step:1x3"),))
    plan = {s.run_id: s for s in build_plan(changed)}
    assert set(plan) == set(base)
    differ = {rid for rid in plan if plan[rid].config_hash() != base[rid].config_hash()}
    assert differ == {"prior-oa-s0"}  # SPNN's runs name it by run id (adoption also compares
    oa = plan["prior-oa-s0"].sac_kwargs  # a run's priors' specs)
    assert (oa["train_freq"], oa["gradient_steps"]) == ([1, "step"], 3)
    assert base["prior-oa-s0"].sac_kwargs["gradient_steps"] == 2
    assert describe_value("oa_updates", "") == "as the source columns'"
    assert describe_value("oa_updates", "step:1x2") == "2 per step"
    with pytest.raises(ValueError, match="oa_updates='step:0' is not allowed"):
        TrainingSetup(oa_updates="step:0")


def test_pnn_discount_per_path() -> None:
    """``pnn_gamma_sine`` gives PNN's sine runs their own discount; Table 2's 0.99 is never
    named, so a sine run at 0.99 keeps the hash it had before the factor existed."""
    base = {s.run_id: s for s in build_plan(StudyConfig(seeds=1))}
    changes = (("pnn_gamma", 0.995), ("pnn_gamma_sine", 0.99))
    plan = {s.run_id: s for s in build_plan(StudyConfig(seeds=1, setup_changes=changes))}
    differ = {rid for rid in plan if plan[rid].config_hash() != base[rid].config_hash()}
    assert differ == {"pnn-straight-s0"}
    assert plan["pnn-straight-s0"].sac_kwargs["gamma"] == 0.995
    assert TrainingSetup(pnn_gamma=0.995).pnn_gamma_of("sine") == 0.995
    with pytest.raises(ValueError, match="pnn_gamma_sine=1.5 is not allowed: expected a discount"):
        TrainingSetup(pnn_gamma_sine=1.5)


@pytest.mark.parametrize(
    ("factor", "runs"),
    [
        ("oa_gamma", {"prior-oa-s0"}),
        ("pf_sine_gamma", {"prior-pf_sine-s0"}),
        ("spnn_gamma", {"spnn-straight-s0", "spnn-sine-s0"}),
        ("pnn_gamma", {"pnn-straight-s0", "pnn-sine-s0"}),
    ],
)
def test_discount_factors_change_only_their_runs(factor: str, runs: set[str]) -> None:
    """``oa_gamma`` sets the avoidance column's discount alone, ``pf_sine_gamma`` the sine
    path-following column's, ``spnn_gamma`` SPNN's,
    ``pnn_gamma`` PNN's; every other run keeps DiscreteSAC's 0.99 and its hash; a bad value is
    refused."""
    base = {s.run_id: s for s in build_plan(StudyConfig(seeds=1))}
    changed = StudyConfig(seeds=1, setup_changes=((factor, 0.995),))
    plan = {s.run_id: s for s in build_plan(changed)}
    differ = {rid for rid in plan if plan[rid].config_hash() != base[rid].config_hash()}
    assert differ == runs
    for rid in runs:
        assert plan[rid].sac_kwargs["gamma"] == 0.995
        assert "gamma" not in base[rid].sac_kwargs  # DiscreteSAC's 0.99
    assert describe_value(factor, None) == "Tables 2-3's 0.99"
    for bad in (1.0, 0.0, -0.5, float("nan"), "0.9"):
        with pytest.raises(ValueError, match=f"{factor}={bad!r} is not allowed: expected"):
            TrainingSetup(**{factor: bad})
