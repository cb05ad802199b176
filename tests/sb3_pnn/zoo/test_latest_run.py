"""The "latest run" of priors and enjoy is the latest run folder that holds a model.

Empty run folders (left by -optimize, or by a run that failed early) come after the trained one.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest
from zoo_helpers import PF_ENV, PLAN_ENV

from sb3_pnn.zoo.cli import enjoy_main
from sb3_pnn.zoo.errors import ZooUsageError
from sb3_pnn.zoo.play import find_model
from sb3_pnn.zoo.priors import resolve_priors

PF = PF_ENV.replace("/", "-")
PLAN = PLAN_ENV.replace("/", "-")


def _tiny_model() -> bytes:
    """A real path-following model file (priors are read before they are used)."""
    import io

    import gymnasium as gym

    from sb3_pnn import DiscreteSAC

    buffer = io.BytesIO()
    env = gym.make(PF_ENV, control_period=0.5, motion_obs=True)
    DiscreteSAC("MultiInputPolicy", env, policy_kwargs={"net_arch": [4]}, seed=0).save(buffer)
    return buffer.getvalue()


def make_runs(algo_folder: Path, name: str, with_model: list[int], empty: list[int]) -> None:
    model = _tiny_model() if with_model and name == PF else b"model"
    for n in with_model:
        (algo_folder / f"{name}_{n}").mkdir(parents=True)
        (algo_folder / f"{name}_{n}" / f"{name}.zip").write_bytes(model)
    for n in empty:
        (algo_folder / f"{name}_{n}").mkdir(parents=True)


def pf_prior(logs: Path, **ref: object) -> list[str]:
    return resolve_priors(
        [{"algo": "dsac", "env": PF_ENV, **ref}],
        algo="pnn",
        env_id=PLAN_ENV,
        log_folder=str(logs),
        where="test",
    )


def test_prior_skips_empty_later_runs(tmp_path: Path) -> None:
    make_runs(tmp_path / "dsac", PF, with_model=[1, 2], empty=[3, 10])
    assert pf_prior(tmp_path) == [str(tmp_path / "dsac" / f"{PF}_2" / f"{PF}.zip")]


def test_missing_prior_says_which_runs_hold_one_and_names_priors(tmp_path: Path) -> None:
    make_runs(tmp_path / "dsac", PF, with_model=[], empty=[1, 2])
    with pytest.raises(ZooUsageError) as info:
        pf_prior(tmp_path)
    message = str(info.value)
    assert "no run of dsac on rov_envs/PathFollowingStraight-v0 holds a model" in message
    assert "run folders 2, 1 hold none" in message and "--priors" in message
    with pytest.raises(ZooUsageError, match=r"_2/.*does not exist \(run folders 2, 1 hold none"):
        pf_prior(tmp_path, exp_id=2)


def enjoy_args(folder: Path, **overrides: object) -> argparse.Namespace:
    values = dict(
        env=PLAN_ENV,
        algo="spnn",
        folder=str(folder),
        exp_id=0,
        load_best=False,
        load_checkpoint=None,
        load_last_checkpoint=False,
    )
    values.update(overrides)
    return argparse.Namespace(**values)


def test_enjoy_loads_the_latest_run_that_holds_a_model(tmp_path: Path) -> None:
    make_runs(tmp_path / "spnn", PLAN, with_model=[1], empty=[2, 3])
    args = enjoy_args(tmp_path)
    model_path, log_path = find_model(args)
    assert Path(model_path) == tmp_path / "spnn" / f"{PLAN}_1" / f"{PLAN}.zip"
    assert args.exp_id == 1


def test_enjoy_names_exp_id_when_the_chosen_run_has_no_model(tmp_path: Path) -> None:
    make_runs(tmp_path / "spnn", PLAN, with_model=[1], empty=[2])
    with pytest.raises(ZooUsageError) as info:
        find_model(enjoy_args(tmp_path, exp_id=2))
    message = str(info.value)
    assert "no trained spnn model" in message and "runs holding one: 1" in message
    assert "--exp-id N" in message


def test_enjoy_plays_the_chosen_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import sb3_pnn.zoo.play

    make_runs(tmp_path / "spnn", PLAN, with_model=[1], empty=[2])
    seen: list[argparse.Namespace] = []
    monkeypatch.setattr(sb3_pnn.zoo.play, "play", seen.append)
    enjoy_main(["--algo", "spnn", "--env", PLAN_ENV, "-f", str(tmp_path), "--no-render"])
    (args,) = seen
    model_path, _ = find_model(args)
    assert args.exp_id == 1 and Path(model_path).parent.name == f"{PLAN}_1"
