"""bench/env_speed.py: the control period reaches every row, each row's simulated seconds per
second is its steps per second times that period, and a period outside the envs' range stops the
script with a message naming it."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import pytest

SCRIPT = str(Path(__file__).parents[2] / "bench" / "env_speed.py")


def _run(monkeypatch, *args: str) -> None:
    monkeypatch.setattr(sys, "argv", ["env_speed.py", *args])
    runpy.run_path(SCRIPT, run_name="__main__")


def test_rows_run_at_the_period_asked(monkeypatch, capsys) -> None:
    _run(monkeypatch, "--seconds", "0.01", "--rounds", "1", "--envs", "2", "--no-sb3",
         "--control-period", "0.5")  # fmt: skip
    out = capsys.readouterr().out
    assert "control period 0.5 s" in out
    rows = [line for line in out.splitlines() if line.startswith("rov_envs/")]
    assert len(rows) == 3  # single, single continuous, make_vec N=2
    for row in rows:
        steps, sim = (float(cell.replace(",", "")) for cell in row.split()[-4::3])
        assert sim == pytest.approx(steps * 0.5, abs=1.0)


def test_a_period_out_of_range_is_refused_by_name(monkeypatch) -> None:
    with pytest.raises(SystemExit, match=r"--control-period 3 is not in \[0.05, 1\] s"):
        _run(monkeypatch, "--control-period", "3")
