"""The command line: bad arguments, and a whole (stand-in or tiny real) study to report.md."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace

import pytest
from reproduce_helpers import fake_work

from rov_envs.sim.rewards import END_REASONS
from sb3_pnn.reproduce.cli import config_from_args, main, make_parser
from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import parse_setup_changes
from sb3_pnn.reproduce.reporting.report import write_report
from sb3_pnn.reproduce.running.results import load_results
from sb3_pnn.reproduce.running.store import RunStore
from sb3_pnn.reproduce.running.work import build_model


@pytest.mark.parametrize(
    ("argv", "match"),
    [(["--seeds", "0"], "--seeds must be an integer >= 1, got 0"),
     (["--jobs", "0"], "--jobs must be an integer >= 1, got 0"),
     (["--jobs", "two"], "--jobs must be an integer >= 1, got 'two'"),
     (["--episodes", "-3"], "--episodes must be an integer >= 1, got -3"),
     (["--set", "updats=step:4"], "--set 'updats=step:4' is not allowed"),
     (["--set", "keep_best=yes"], "expected a value like keep_best=false"),
     (["--set", "updates=step:0"], "updates='step:0' is not allowed"),
     (["--set", "batch_size=0"], "batch_size=0 is not allowed: expected an integer >= 1"),
     (["--set", "batch_size=12.5"], "expected a value like batch_size=256"),
     (["--set", "prior_batch_size=-1"], "prior_batch_size=-1 is not allowed"),
     (["--set", "control_period=0"], "control_period=0.0 is not allowed"),
     (["--set", "control_period=5"], "control_period=5.0 is not allowed"),
     (["--agents", "spnn,dqn"], "agent 'dqn' is unknown; expected one of"),
     (["--agents", "spnn,spnn"], "expected distinct agents"),
     (["--prior-per-seed", "--shared-priors"], "not allowed with argument")],
)  # fmt: skip
def test_bad_arguments(argv, match, capsys, tmp_path) -> None:
    with pytest.raises(SystemExit) as exc:
        main([*argv, "--out", str(tmp_path)])
    assert exc.value.code == 2
    assert match in capsys.readouterr().err


def test_source_columns_per_seed_unless_shared_is_asked_for() -> None:
    parser = make_parser()
    assert config_from_args(parser.parse_args([])).prior_per_seed
    assert config_from_args(parser.parse_args(["--prior-per-seed"])).prior_per_seed
    shared = config_from_args(parser.parse_args(["--shared-priors", "--seeds", "2"]))
    assert not shared.prior_per_seed
    deps = {s.run_id: s.deps for s in build_plan(shared)}
    assert deps["spnn-straight-s1"] == ("prior-pf_straight-s0", "prior-oa-s0")


def test_report_only_of_a_folder_without_the_study(capsys, tmp_path) -> None:
    assert main(["--report-only", "--quick", "--out", str(tmp_path)]) == 2
    assert "holds no finished run of this study" in capsys.readouterr().err
    assert not (tmp_path / "report.md").exists()


def test_set_switch_takes_json_or_the_ablation_words() -> None:
    # --set train_start_noise=off names the set-up that the ablation cell ...=off names
    for off, on in (("false", "true"), ("off", "on")):
        assert parse_setup_changes([f"train_start_noise={off}", f"motion_obs={on}"]) == {
            "train_start_noise": False,
            "motion_obs": True,
        }
    with pytest.raises(ValueError, match="expected a value like keep_best=false"):
        parse_setup_changes(["keep_best=Off"])


def test_set_changes_the_runs_of_the_study() -> None:
    changes = (("updates", "step:4"), ("prior_updates", "step:1"))
    config = StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes)
    specs = [spec for spec in build_plan(config) if spec.kind != "baseline"]
    assert {spec.kind for spec in specs} == {"prior", "transfer"}
    for spec in specs:  # the source columns get their own schedule
        assert spec.sac_kwargs["train_freq"] == (
            [1, "step"] if spec.kind == "prior" else [4, "step"]
        )
    assert all(spec.validation for spec in specs)  # the rest of `ours` stays
    # the paper's 256 samples per update is DiscreteSAC's default: not written into the specs,
    # so runs planned before the factor existed keep their hash
    assert all("batch_size" not in spec.sac_kwargs for spec in specs)


def test_batch_size_of_the_transfer_runs_and_of_the_source_columns() -> None:
    changes = (("batch_size", 128), ("prior_batch_size", 256))
    config = StudyConfig(budget_name="tiny", seeds=1, setup_changes=changes)
    specs = [spec for spec in build_plan(config) if spec.kind != "baseline"]
    for spec in specs:
        assert spec.sac_kwargs.get("batch_size") == (None if spec.kind == "prior" else 128)
    # prior_batch_size 0 (the default): the source columns take batch_size too
    config = StudyConfig(budget_name="tiny", seeds=1, setup_changes=(("batch_size", 64),))
    plan = [spec for spec in build_plan(config) if spec.kind != "baseline"]
    assert {spec.sac_kwargs["batch_size"] for spec in plan} == {64}
    prior = next(spec for spec in plan if spec.kind == "prior")
    assert build_model(prior, {}).batch_size == 64  # and the learner samples that many


def test_unwritable_out(capsys, tmp_path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(SystemExit) as exc:
        main(["--tiny", "--out", str(blocker / "sub")])
    assert exc.value.code == 2
    assert "not a writable folder" in capsys.readouterr().err


def test_stand_in_study_writes_report_and_figures(tmp_path, capsys) -> None:
    out = tmp_path / "study"
    argv = ["--tiny", "--seeds", "1", "--eval-episodes", "10", "--jobs", "2", "--no-progress"]
    rc = main([*argv, "--out", str(out)], work=fake_work)
    assert rc == 0
    printed = capsys.readouterr().out
    assert f"report: {(out / 'report.md').resolve()}" in printed
    report = (out / "report.md").read_text()
    assert "## Figure 20" in report and "| SPNN |" in report
    assert "100 % / 98 % / 98 %" in report  # the paper's SPNN row beside ours
    assert "90 % [" in report  # stand-in SPNN success pooled with its Wilson interval
    # a smoke-sized budget is marked as such and gives no verdicts; the end reasons are explained
    # the set-up actually used, factor by factor
    assert "training set-up: `ours` (" in report and "update schedule 1 per 2 steps" in report
    # the source columns' episodes as trained (ours doubles the avoidance and the sine columns')
    assert "priors {'pf_straight': 3, 'pf_sine': 6, 'oa': 6}" in report
    assert "**Smoke test** (budget `tiny`" in report and "No verdicts from a smoke test" in report
    assert "agree" not in report.split("## Do we agree with the paper?")[1]
    assert all(f"`{reason}`: " in report for reason in END_REASONS if reason != "none")
    # the kept policy's validation check beside the last one (stand-ins: 100 % then 50 %)
    assert "Validation checks (every 25 training episodes, 30 episodes each" in report
    assert "| SPNN | 100 % (100) | 50 % (50) | 100 % (100) | 50 % (50) |" in report
    # the same runs reported as a full study: verdicts, no smoke-test mark
    config = StudyConfig(budget_name="tiny", seeds=1, eval_episodes=10)
    results = load_results(build_plan(config), RunStore(out))
    write_report(results, replace(config, budget_name="full"), [], [], out / "full.md", 2)
    full = (out / "full.md").read_text()
    assert "Smoke test" not in full and "SPNN succeeds at least as often as PNN" in full
    names = {p.name for p in (out / "figures").iterdir()}
    expected = {
        "fig10_learning_curves.png",
        "fig11_training_trajectories_straight.png",
        "fig14_training_trajectories_sine.png",
        "fig12_straight_original.png",
        "fig13_straight_path_following.png",
        "fig15_sine_original.png",
        "fig16_sine_path_following.png",
        "fig17_straight_uniform.png",
        "fig18_straight_dense.png",
        "fig19_sine_dense.png",
        "fig20_success_rates.png",
    }
    assert expected <= names
    # a second call with a changed budget in the same folder refuses to overwrite
    rc = main(["--tiny", "--seeds", "1", "--episodes", "9", "--no-progress", "--out", str(out)],
              work=fake_work)  # fmt: skip
    assert rc == 2
    assert "never overwritten" in capsys.readouterr().err


def test_agents_trains_only_the_learners_asked_for(tmp_path, capsys) -> None:
    out = tmp_path / "study"
    argv = ["--tiny", "--seeds", "1", "--eval-episodes", "10", "--jobs", "1", "--no-progress"]
    assert main([*argv, "--agents", "spnn", "--out", str(out)], work=fake_work) == 0
    runs = {p.name for p in (out / "runs").iterdir()}
    # SPNN's two source columns per path and both PID baselines, no other learner
    assert {r for r in runs if "-s0" in r and not r.startswith("prior")} == {
        "spnn-straight-s0",
        "spnn-sine-s0",
    }
    assert {"prior-oa-s0", "prior-pf_sine-s0", "adaptive_pid-straight"} <= runs
    report = (out / "report.md").read_text()
    assert "learners: SPNN (`--agents`: the others not trained)" in report


@pytest.mark.slow
def test_tiny_real_study_end_to_end(tmp_path) -> None:
    """The real runs (DiscreteSAC, SAC-Multi, PNN, SPNN, PID) on a tiny budget, via the module."""
    out = tmp_path / "study"
    proc = subprocess.run(
        [sys.executable, "-m", "sb3_pnn.reproduce", "--tiny", "--seeds", "1", "--jobs", "2",
         "--no-progress", "--out", str(out)],
        capture_output=True, text=True, timeout=240,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "report: " in proc.stdout
    report = (out / "report.md").read_text()
    assert "failed: 0" in report
    assert (out / "figures" / "fig20_success_rates.png").is_file()
    assert (out / "runs" / "spnn-sine-s0" / "model.zip").is_file()


def test_ray_executor_without_ray_installed(monkeypatch, capsys, tmp_path) -> None:
    import sys

    monkeypatch.setitem(sys.modules, "ray", None)  # import ray -> ImportError
    assert main(["--quick", "--executor", "ray", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "pip install 'sb3-pnn[ray]'" in err[0]
    assert not list((tmp_path / "runs").glob("*"))
