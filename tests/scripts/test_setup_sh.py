"""scripts/setup.sh says what step runs, keeps an installed torch and otherwise asks for one;
run here against a stand-in ``python`` that records its calls (nothing is installed)."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
FAKE_PYTHON = """#!/usr/bin/env bash
printf '%s\\n' "$*" >> "$CALLS"
if [ "$1" = "-c" ]; then
  [ -n "${HAS_TORCH:-}" ] || exit 1
  echo "$HAS_TORCH"
fi
"""


def setup(tmp_path: Path, **env: str) -> tuple[list[str], list[str]]:
    """(lines printed, calls of the stand-in python) of a non-interactive run, as in CI."""
    python = tmp_path / "python"
    python.write_text(FAKE_PYTHON)
    python.chmod(0o755)
    calls = tmp_path / "calls"
    variables = {k: v for k, v in os.environ.items() if k not in ("SB3_PNN_TORCH", "HAS_TORCH")}
    variables.update(PYTHON=str(python), CALLS=str(calls), CI="true", **env)
    result = subprocess.run(
        ["bash", str(REPO / "scripts" / "setup.sh")],
        env=variables,
        stdin=subprocess.DEVNULL,
        capture_output=True,
        text=True,
        timeout=60,
        check=True,
    )
    assert result.stderr == ""
    return result.stdout.splitlines(), calls.read_text().splitlines()


def test_keeps_an_installed_torch_and_says_each_step(tmp_path: Path) -> None:
    lines, calls = setup(tmp_path, HAS_TORCH="2.5.1+cpu")
    assert lines[0] == "setup.sh: keeping the installed torch 2.5.1+cpu"
    assert lines[1].startswith("setup.sh: installing sb3-pnn (editable) with its dev extras")
    assert lines[2].startswith("setup.sh: done in ") and len(lines) == 3
    assert calls[1:] == ["-m pip install --quiet -e .[dev]"]


@pytest.mark.parametrize(
    ("env", "spec"), [({}, "torch==2.13.0"), ({"SB3_PNN_TORCH": "torch==2.5.1"}, "torch==2.5.1")]
)
def test_asks_for_torch_when_there_is_none(tmp_path: Path, env: dict, spec: str) -> None:
    lines, calls = setup(tmp_path, **env)
    assert lines[0] == f"setup.sh: no torch found: installing {spec} (a large download) ..."
    assert calls[1:] == [f"-m pip install --quiet {spec}", "-m pip install --quiet -e .[dev]"]
