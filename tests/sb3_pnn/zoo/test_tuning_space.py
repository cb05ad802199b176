"""The Optuna search space, its converter and the storages (no training)."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import optuna
import pytest

from sb3_pnn.zoo.errors import ZooUsageError
from sb3_pnn.zoo.tuning import (
    DEFAULT_BOUNDS,
    build_space,
    convert_params,
    create_storage,
    hide_password,
    make_converter,
    make_sampler,
    parse_cli_bounds,
)

optuna.logging.set_verbosity(optuna.logging.WARNING)


def space(algo: str = "spnn", spec=None, gate: str = "hard", sonar_range: float = 25.0):
    return build_space(algo, spec, sonar_range=sonar_range, gate=gate, origin="test")


def test_spnn_defaults_tune_the_switch_only() -> None:
    hard = space()
    assert set(hard.bounds) == {"d_th", "sigma", "own_weight"}  # no temperature for a hard gate
    soft = space(gate="soft")
    assert set(soft.bounds) == {"d_th", "sigma", "own_weight", "temperature"}
    assert not soft.batch_sizes


def test_sac_settings_on_request_and_always_for_dsac() -> None:
    with_sac = space(spec={"sac": True})
    assert {"learning_rate", "gamma", "tau", "gradient_steps"} <= set(with_sac.bounds)
    assert with_sac.batch_sizes == DEFAULT_BOUNDS["batch_size"]
    dsac = space("dsac", gate=None)
    assert set(dsac.bounds) == {"learning_rate", "gamma", "tau", "gradient_steps"}


def test_fixed_and_untuned_names() -> None:
    s = space(spec={"sigma": 0.5, "own_weight": None, "d_th": [5, 15]})
    assert s.fixed == {"sigma": 0.5}
    assert set(s.bounds) == {"d_th"} and s.bounds["d_th"] == (5.0, 15.0)


def test_d_th_is_capped_by_the_sonar_range() -> None:
    assert space(spec={"d_th": [1, 40]}, sonar_range=50.0).bounds["d_th"] == (1.0, 40.0)
    with pytest.raises(ZooUsageError, match=r"allowed \(0, 25\] m"):
        space(spec={"d_th": [1, 40]})


@pytest.mark.parametrize(
    "spec",
    [
        {"sigma": [-0.1, 0.5]},
        {"own_weight": [0.5, 1.01]},
        {"temperature": [0.0, 1.0]},
        {"gamma": [0.9, 1.0]},
        {"tau": [0.0, 0.1]},
        {"gradient_steps": [0, 5]},
        {"gradient_steps": [1.5, 5]},
        {"batch_size": [0, 64]},
        {"d_th": [10, 5]},
        {"d_th": "wide"},
        {"sac": "yes"},
    ],
)
def test_bad_bounds_are_refused(spec) -> None:
    with pytest.raises(ZooUsageError):
        space(spec=spec, gate="soft")


def test_samples_stay_in_bounds_and_merge_over_the_base_policy_kwargs() -> None:
    s = space(spec={"d_th": [4, 20], "sigma": [0.2, 0.8], "sac": True}, gate="soft")
    base = {"priors": ["pf.zip", "oa.zip"], "net_arch": [255, 255], "gate": "soft", "d_th": 12.5}
    sampler = make_sampler(s, base)
    study = optuna.create_study(direction="maximize")
    for _ in range(20):
        trial = study.ask()
        sampled = sampler(trial, 0, 1, {})
        study.tell(trial, 0.0)
        pk = sampled["policy_kwargs"]
        assert pk["priors"] == ["pf.zip", "oa.zip"] and pk["net_arch"] == [255, 255]
        assert 4 <= pk["d_th"] <= 20 and 0.2 <= pk["sigma"] <= 0.8
        assert 0.1 <= pk["temperature"] <= 10.0
        assert 1e-5 <= sampled["learning_rate"] <= 1e-2
        assert sampled["batch_size"] in (64, 128, 256, 512)
        assert "d_th" not in sampled  # switch parameters only inside policy_kwargs
    assert base["d_th"] == 12.5  # the base is not modified
    converted = make_converter(base)(study.trials[0].params)
    assert converted["policy_kwargs"]["d_th"] == study.trials[0].params["d_th"]


def test_convert_without_switch_keeps_no_policy_kwargs() -> None:
    assert convert_params({"learning_rate": 1e-3}) == {"learning_rate": 1e-3}


def test_parse_cli_bounds() -> None:
    assert parse_cli_bounds(["d_th=5:20", "sigma=0.5", "own_weight=none", "batch_size=64,128"]) == {
        "d_th": [5.0, 20.0],
        "sigma": 0.5,
        "own_weight": None,
        "batch_size": [64, 128],
    }
    with pytest.raises(ZooUsageError, match="NAME=LOW:HIGH"):
        parse_cli_bounds(["d_th"])


def test_hide_password() -> None:
    url = "postgresql://user:secret@host:5432/db"
    assert hide_password(url) == "postgresql://user:***@host:5432/db"


def test_storage_kinds(tmp_path: Path) -> None:
    journal = create_storage(str(tmp_path / "a" / "study.log"))
    assert isinstance(journal, optuna.storages.JournalStorage)
    sqlite = create_storage(f"sqlite:///{tmp_path / 'db.sqlite'}", heartbeat_interval=2)
    assert isinstance(sqlite, optuna.storages.RDBStorage)
    assert sqlite.get_heartbeat_interval() == 2
    with pytest.raises(ZooUsageError, match="must exceed --heartbeat-interval"):
        create_storage("sqlite:///x.db", heartbeat_interval=5, grace_period=5)
    with pytest.raises(ZooUsageError, match="cannot open the study database"):
        create_storage("postgresql://u:pw@127.0.0.1:1/none")


WORKER = textwrap.dedent(
    """
    import sys, optuna
    from sb3_pnn.zoo.tuning import create_storage
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.create_study(storage=create_storage(sys.argv[1]), study_name="shared",
                                load_if_exists=True)
    study.optimize(lambda t: t.suggest_float("x", 0, 1) ** 2, n_trials=6)
    """
)


def test_journal_file_is_shared_by_processes_on_one_machine(tmp_path: Path) -> None:
    path = str(tmp_path / "study.log")
    workers = [
        subprocess.Popen([sys.executable, "-c", WORKER, path], stderr=subprocess.PIPE, text=True)
        for _ in range(2)
    ]
    for worker in workers:
        _, err = worker.communicate(timeout=120)
        assert worker.returncode == 0, err
    study = optuna.load_study(storage=create_storage(path), study_name="shared")
    numbers = sorted(t.number for t in study.trials)
    assert numbers == list(range(12))
    assert all(t.state == optuna.trial.TrialState.COMPLETE for t in study.trials)
