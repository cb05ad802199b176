"""Fixtures of the rl-zoo command tests: tiny priors trained once per session with `train`."""

from __future__ import annotations

from pathlib import Path

import pytest
from zoo_helpers import OA_ENV, PF_ENV, TINY, run_cli


@pytest.fixture(scope="session")
def prior_logs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A log folder holding a path-following and an obstacle-avoidance dsac model, made by train."""
    work = tmp_path_factory.mktemp("zoo_priors")
    for env_id in (PF_ENV, OA_ENV):
        run_cli(
            "train", "--algo", "dsac", "--env", env_id, "-n", "120", "-f", "logs", *TINY, cwd=work
        )
    return work


@pytest.fixture
def in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path
