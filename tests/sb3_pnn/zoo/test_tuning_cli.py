"""`-optimize` from the command line: >= 10 SPNN trials on tiny budgets, the report, --trial-id."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import optuna
import pytest
import yaml
from zoo_helpers import PLAN_ENV, TINY, run_cli

pytestmark = pytest.mark.slow

RUN = "rov_envs-PlanningStraight-v0"
BOUNDS = {
    "d_th": (4.0, 20.0),
    "sigma": (0.2, 0.8),
    "own_weight": (0.2, 0.8),
    "temperature": (0.5, 5.0),
}


def test_tuning_reports_best_switch_and_trial_zero_loads(prior_logs: Path, tmp_path: Path) -> None:
    shutil.copytree(prior_logs / "logs", tmp_path / "logs")
    tune = [f"--tune={name}={low}:{high}" for name, (low, high) in BOUNDS.items()]
    result = run_cli(
        "train", "--algo", "spnn", "--env", PLAN_ENV, "-f", "logs", "-n", "40",
        "-optimize", "--n-trials", "10", "--n-startup-trials", "4", "--n-evaluations", "1",
        "--eval-episodes", "1", "--no-optim-plots", *tune,
        *TINY, "policy_kwargs:dict(gate='soft')", cwd=tmp_path, timeout=600,
    )  # fmt: skip
    assert "Best switch: d_th = " in result.stdout
    assert "(paper: d_th = 12.5, sigma = 0.5, own_weight = 0.5" in result.stdout

    journal = tmp_path / "logs" / "spnn" / "optuna" / f"{RUN}.log"
    assert journal.is_file()  # the embedded default storage
    reports = list((tmp_path / "logs" / "spnn").glob(f"report_{RUN}_*.json"))
    assert len(reports) == 1
    report = json.loads(reports[0].read_text())
    assert report["n_trials"] >= 10
    assert report["states"]["COMPLETE"] + report["states"]["PRUNED"] >= 10
    best = report["best_params"]
    assert set(best) == set(BOUNDS)  # the switch only: SAC settings were not asked for
    for name, (low, high) in BOUNDS.items():
        assert low <= best[name] <= high

    storage = optuna.storages.JournalStorage(
        optuna.storages.journal.JournalFileBackend(str(journal))
    )
    study = optuna.load_study(storage=storage, study_name=f"spnn_{RUN}")
    assert study.best_trial.params == best
    trial0 = study.trials[0].params

    # --trial-id 0 (falsy in the zoo) trains with trial 0's switch, merged over the config.
    run_cli(
        "train", "--algo", "spnn", "--env", PLAN_ENV, "-f", "logs", "-n", "30",
        "--trial-id", "0", *TINY, cwd=tmp_path,
    )  # fmt: skip
    runs = sorted(
        (tmp_path / "logs" / "spnn").glob(f"{RUN}_*"), key=lambda p: int(p.name.split("_")[-1])
    )
    config_path = runs[-1] / RUN / "config.yml"  # -optimize made an (empty) run folder before it
    policy_kwargs = yaml.load(config_path.read_text(), Loader=yaml.UnsafeLoader)["policy_kwargs"]
    for name in BOUNDS:
        assert policy_kwargs[name] == pytest.approx(trial0[name])
    assert len(policy_kwargs["priors"]) == 2
