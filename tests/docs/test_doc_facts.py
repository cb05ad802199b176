"""Facts that the docs quote must be the source's: the control period, episode lengths in steps,
and the study's budgets in ``reproduce --help`` (a copy that drifted said 0.1 s and 5 minutes)."""

from __future__ import annotations

import math
import re
import subprocess
from pathlib import Path

import pytest

from rov_envs.sim.config import CONTROL_PERIOD, TIME_LIMIT_FACTOR, U_REF
from sb3_pnn.reproduce.cli import make_parser
from sb3_pnn.reproduce.planning.plan import BUDGETS

REPO = Path(__file__).resolve().parents[2]
NUMBER = r"(\d[\d,]*(?:\.\d+)?)"
#: Ways the docs state the length of one step (the control period), in seconds.
PERIOD_PATTERNS = [
    rf"control period,? (?:is )?{NUMBER} s\b",
    rf"control period `[\w.]+` \({NUMBER} s\)",
    rf"one step (?:=|is|lasts) {NUMBER} s\b",
    rf"one {NUMBER} s control period",
]


def doc_files() -> list[Path]:
    listed = subprocess.run(
        ["git", "ls-files", "*.md", "*.yml", "*.py"], cwd=REPO, capture_output=True, text=True
    ).stdout.split()
    return [REPO / p for p in listed if not p.startswith(("tests/", "docs/study"))]


def number(text: str) -> float:
    return float(text.replace(",", ""))


def found(pattern: str) -> list[tuple[str, tuple[str, ...]]]:
    hits = []
    for path in doc_files():
        for match in re.finditer(pattern, path.read_text(), flags=re.IGNORECASE):
            hits.append((path.relative_to(REPO).as_posix(), match.groups()))
    return hits


def test_every_quoted_control_period_is_the_source_one() -> None:
    hits = [hit for pattern in PERIOD_PATTERNS for hit in found(pattern)]
    assert len(hits) >= 3, hits  # the patterns still find the README statements
    wrong = [(where, value) for where, (value,) in hits if number(value) != CONTROL_PERIOD]
    assert not wrong, f"control period in the docs differs from {CONTROL_PERIOD} s: {wrong}"


def test_quoted_step_counts_follow_from_the_control_period() -> None:
    seconds = found(rf"{NUMBER} s = {NUMBER} steps")
    lines = found(rf"{NUMBER} steps on the {NUMBER} m line")
    assert seconds and lines
    for where, (s, steps) in seconds:
        assert number(steps) == math.ceil(number(s) / CONTROL_PERIOD - 1e-9), where
    for where, (steps, length) in lines:
        limit_s = TIME_LIMIT_FACTOR * number(length) / U_REF
        assert number(steps) == round(limit_s / CONTROL_PERIOD), where


def test_reproduce_help_quotes_the_plan_and_no_times(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        make_parser().parse_args(["--help"])
    text = " ".join(capsys.readouterr().out.split())
    for name in ("full", "quick"):
        budget = BUDGETS[name]
        assert f"agents {budget.transfer_episodes['straight']} straight" in text
        assert f"evaluation {budget.eval_episodes}," in text
    assert not re.search(r"\d\s*(min|minutes|hours?)\b", text), "times belong to the README"


def test_readme_lists_every_console_script() -> None:
    import configparser

    setup = configparser.ConfigParser()
    setup.read(REPO / "setup.cfg")
    scripts = setup["options.entry_points"]["console_scripts"].strip().splitlines()
    readme = (REPO / "README.md").read_text()
    assert scripts
    for line in scripts:
        name, target = (part.strip() for part in line.split("="))
        module = target.split(":")[0].removesuffix(".cli")  # reproduce.cli: python -m ...reproduce
        assert f"| `{name}` | `python -m {module}` |" in readme, name
