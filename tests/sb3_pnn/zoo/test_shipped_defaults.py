"""`train`, `-optimize` and `enjoy` on the shipped YAML defaults: no --env-kwargs, evaluation on.

A user's first command is ``python -m sb3_pnn.train --algo dsac --env ...`` with nothing else.
The entry's ``env_kwargs`` (1.0 s control period, v and r observed, ...) must then reach the
evaluation env too, or the first evaluation fails on an observation the model was not trained
on. These runs keep the full-length episodes of the YAML and only shorten the step budget.
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
from zoo_helpers import PF_ENV, PLAN_ENV, run_cli

pytestmark = pytest.mark.slow

PF_RUN = "rov_envs-PathFollowingStraight-v0"
PLAN_RUN = "rov_envs-PlanningStraight-v0"


@pytest.fixture(scope="module")
def trained(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A dsac model trained with the YAML defaults; two evaluations fire during training."""
    work = tmp_path_factory.mktemp("zoo_defaults")
    result = run_cli(
        "train", "--algo", "dsac", "--env", PF_ENV, "-n", "700", "--eval-freq", "300",
        "--eval-episodes", "1", "-f", "logs", cwd=work, timeout=600,
    )  # fmt: skip
    (work / "train.out").write_text(result.stdout)
    return work


def _zoo_argv(given: list[str], monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The argv rl_zoo3's train receives from ``train --algo dsac --env PF_ENV *given``."""
    import rl_zoo3.train

    from sb3_pnn.zoo.cli import train_main

    seen: list[list[str]] = []
    monkeypatch.setattr(rl_zoo3.train, "train", lambda: seen.append(list(sys.argv)))
    train_main(["--algo", "dsac", "--env", PF_ENV, *given])
    (argv,) = seen
    return argv


@pytest.mark.parametrize(
    ("given", "expected"), [([], "1"), (["--num-threads", "3"], "3"), (["--num-threads=-1"], None)]
)
def test_train_runs_torch_on_one_thread_unless_told(
    given: list[str], expected: str | None, monkeypatch: pytest.MonkeyPatch
) -> None:
    argv = _zoo_argv(given, monkeypatch)
    threads = [a for a in argv if a.startswith("--num-threads")]
    if expected is None:
        assert threads == ["--num-threads=-1"]
    else:
        assert len(threads) == 1 and argv[argv.index("--num-threads") + 1] == expected


@pytest.mark.parametrize(
    ("given", "expected"),
    [
        ([], ["--device", "cpu"]),
        (["--device", "cuda"], ["--device", "cuda"]),
        (["--device=auto"], ["--device=auto"]),
    ],
)
def test_train_runs_on_the_cpu_unless_told(
    given: list[str], expected: list[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """rl_zoo3's own default, auto, would take a GPU, where these networks train slower."""
    argv = _zoo_argv(given, monkeypatch)
    devices = [a for a in argv if a.startswith("--device")]
    assert len(devices) == 1
    at = argv.index(devices[0])
    assert argv[at : at + len(expected)] == expected


def test_train_evaluates_on_the_entrys_env_kwargs(trained: Path) -> None:
    run = trained / "logs" / "dsac" / f"{PF_RUN}_1"
    assert (run / f"{PF_RUN}.zip").is_file()
    assert (run / "best_model.zip").is_file()  # EvalCallback ran and kept a model
    evaluations = np.load(run / "evaluations.npz")
    assert list(evaluations["timesteps"]) == [300, 600]


def test_enjoy_runs_the_model_train_made(trained: Path) -> None:
    result = run_cli(
        "enjoy", "--algo", "dsac", "--env", PF_ENV, "-f", "logs", "-n", "50", "--no-render",
        cwd=trained,
    )  # fmt: skip
    assert "Loading" in result.stdout
    # what the 600-step policy does is not the point: enjoy played it and said how it went
    assert "Success rate:" in result.stdout or "No episode ended within 50" in result.stdout
    assert "Setting torch.num_threads to 1" in result.stdout


def test_optimize_trials_evaluate_on_the_entrys_env_kwargs(
    prior_logs: Path, tmp_path: Path
) -> None:
    shutil.copytree(prior_logs / "logs", tmp_path / "logs")
    result = run_cli(
        "train", "--algo", "spnn", "--env", PLAN_ENV, "-f", "logs", "-n", "400",
        "-optimize", "--n-trials", "2", "--n-startup-trials", "2", "--n-evaluations", "1",
        "--eval-episodes", "1", "--no-optim-plots", "--num-threads", "1",
        cwd=tmp_path, timeout=600,
    )  # fmt: skip
    assert "Number of finished trials: 2 ({'RUNNING': 0, 'COMPLETE': 2" in result.stdout
