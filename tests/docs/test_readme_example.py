"""The README's Python example runs as written (with small budgets): it trains the two source
columns and the SPNN, saves them, loads the SPNN without its priors and evaluates it."""

from __future__ import annotations

import os
import runpy
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
_BENCH = runpy.run_path(str(REPO / "bench" / "readme_example.py"))  # its extraction, not main
readme_example, with_budgets = _BENCH["readme_example"], _BENCH["with_budgets"]


def test_readme_example_runs_as_written(tmp_path: Path, monkeypatch, capsys) -> None:
    source = with_budgets(readme_example(REPO / "README.md"), 400, 400)
    script = tmp_path / "example.py"
    script.write_text(source)
    monkeypatch.chdir(tmp_path)
    runpy.run_path(str(script), run_name="__main__")
    for name in ("pf_straight.zip", "obstacle_avoidance.zip", "spnn.zip"):
        assert (tmp_path / name).is_file(), name
    out = capsys.readouterr().out
    assert out.count("success rate") == 2
    assert "rov_envs/PlanningStraightDense-v0" in out


def test_the_budget_line_is_found_and_replaced() -> None:
    source = readme_example(REPO / "README.md")
    assert "PRIOR_STEPS, SPNN_STEPS = 7, 8" in with_budgets(source, 7, 8)
    with pytest.raises(ValueError, match="no '## Use it' section"):
        readme_example(os.devnull)
