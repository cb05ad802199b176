"""A shared run folder cannot make ``enjoy`` run code, and the commands' bad input (values,
paths, priors) gives one line and exit status 2 before any work starts."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from zoo_helpers import OA_ENV, PF_ENV, PLAN_ENV, fails, run_cli, train_fails

from sb3_pnn.zoo.cli import ENJOY_PROG, enjoy_main

RUN = PF_ENV.replace("/", "-")
PAYLOAD = '!!python/object/apply:os.system ["touch {marker}"]'


@pytest.fixture
def shared_logs(prior_logs: Path, tmp_path: Path) -> Path:
    """A copy of a log folder with a trained path-following model, as a user might receive it."""
    shutil.copytree(prior_logs / "logs", tmp_path / "logs")
    return tmp_path


@pytest.mark.parametrize(
    ("file", "content"),
    [
        ("args.yml", "- - pwn\n  - " + PAYLOAD + "\n"),
        ("config.yml", "env_kwargs: " + PAYLOAD + "\n"),
        ("config.yml", "normalize: \"__import__('os').system('touch {marker}')\"\n"),
    ],
)
@pytest.mark.parametrize("record", [False, True])
def test_enjoy_never_runs_code_from_a_run_folder(
    file: str, content: str, record: bool, shared_logs: Path
) -> None:
    marker = shared_logs / "PWNED"
    settings = shared_logs / "logs" / "dsac" / f"{RUN}_1" / RUN / file
    settings.write_text(content.format(marker=marker))
    extra = ["--record", str(shared_logs / "v.gif")] if record else ["--no-render"]
    result = run_cli(
        "enjoy", "--algo", "dsac", "--env", PF_ENV, "-f", "logs", "-n", "5", *extra,
        cwd=shared_logs, check=False,
    )  # fmt: skip
    assert not marker.exists()
    assert result.returncode == 2, result.stdout + result.stderr
    assert result.stderr.strip().startswith(f"{ENJOY_PROG}: error:")


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["-params", "learning_rate:abc"], "'abc' is not a Python expression"),
        (["-i", "/nonexistent.zip"], "expected the path of a model .zip"),
        (["-f", "{file}/logs"], "is not a folder"),
        (["-tb", "{file}/runs"], "is not a folder"),
    ],
)
def test_train_refuses_bad_values_and_paths_up_front(
    argv: list[str], needle: str, capsys, tmp_path: Path, monkeypatch
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "file").write_text("not a folder")
    argv = [a.format(file=tmp_path / "file") for a in argv]
    line = train_fails(capsys, ["--algo", "dsac", "--env", PF_ENV, "-n", "10", *argv])
    assert needle in line


def test_enjoy_refuses_an_unwritable_recording_before_playing(
    shared_logs: Path, capsys, monkeypatch
) -> None:
    monkeypatch.chdir(shared_logs)
    (shared_logs / "file").write_text("not a folder")
    line = fails(
        capsys, enjoy_main, ENJOY_PROG,
        ["--algo", "dsac", "--env", PF_ENV, "-f", "logs", "--record", "file/v.gif"],
    )  # fmt: skip
    assert "--record" in line and "is not a folder" in line


@pytest.mark.parametrize(
    ("algo", "env", "prior_env", "needle"),
    [
        ("pnn", PLAN_ENV, f"{OA_ENV} {OA_ENV}", "observes the sonar"),
        ("sac_multi", PLAN_ENV, OA_ENV, "observes the sonar"),
        ("pnn", "rov_envs/PlanningSine-v0", f"{PF_ENV} {OA_ENV}", "whose path is not"),
        ("pnn", "rov_envs/PlanningSine-v0", PF_ENV, "takes 2 (path-following, obstacle-avoidance)"),
    ],
)
def test_train_refuses_a_prior_that_cannot_play_its_role(
    algo: str, env: str, prior_env: str, needle: str, prior_logs: Path, capsys, monkeypatch
) -> None:
    """(PNN on the sine path reads the path-following and the avoidance column.)"""
    monkeypatch.chdir(prior_logs)
    priors = []
    for prior in prior_env.split():
        name = prior.replace("/", "-")
        priors.append(str(prior_logs / "logs" / "dsac" / f"{name}_1" / f"{name}.zip"))
    line = train_fails(capsys, ["--algo", algo, "--env", env, "--priors", *priors, "-n", "10"])
    assert needle in line
