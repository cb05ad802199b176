"""The command each study's page gives plans exactly the runs behind its report.

``docs/study_*/runs.json`` holds each run's configuration hash, read off the study folder
(``python -m sb3_pnn.reproduce.tools.run_hashes``). A default changed without the study being
rerun, or an archived study's command that no longer puts back a later change of a default,
plans other runs and fails here. docs/study_5_seeds must have one: the default command is the
study the README reports.
"""

from __future__ import annotations

import json
import shlex
from pathlib import Path

import pytest

from sb3_pnn.reproduce.cli import parse_study_args
from sb3_pnn.reproduce.planning.plan import build_plan
from sb3_pnn.reproduce.tools.run_hashes import main as run_hashes_main
from sb3_pnn.reproduce.tools.run_hashes import run_hashes

DOCS = Path(__file__).resolve().parents[2] / "docs"
COMMAND = "python -m sb3_pnn.reproduce --seeds"
STUDIES = sorted(p.parent for p in DOCS.glob("study_*/runs.json"))


def study_command(readme: Path) -> list[str]:
    """The arguments of the page's first ``python -m sb3_pnn.reproduce --seeds ...`` command
    (continued lines joined, a trailing comment dropped)."""
    text = readme.read_text().replace("\\\n", " ")
    for line in text.splitlines():
        if COMMAND in line:
            words = shlex.split(line[line.index(COMMAND) :], comments=True)
            return words[3:]
    raise AssertionError(f"{readme} gives no {COMMAND!r} command")


def test_the_default_study_keeps_its_run_list() -> None:
    assert DOCS / "study_5_seeds" in STUDIES
    assert study_command(DOCS / "study_5_seeds" / "README.md") == [
        "--seeds", "5", "--jobs", "2", "--out", "results/study",
    ]  # fmt: skip


@pytest.mark.parametrize("study", STUDIES, ids=lambda p: p.name)
def test_the_page_command_plans_the_runs_of_its_report(study: Path) -> None:
    _, _, config = parse_study_args(study_command(study / "README.md"))
    planned = {run.run_id: run.config_hash() for run in build_plan(config)}
    recorded = json.loads((study / "runs.json").read_text())
    changed = sorted(
        r for r in planned.keys() | recorded.keys() if planned.get(r) != recorded.get(r)
    )
    assert not changed, f"{study.name}: the command plans other runs than its report's: {changed}"


def test_run_hashes_reads_finished_runs_only(tmp_path, capsys) -> None:
    for run_id, status in (("a-s0", "done"), ("b-s0", "running")):
        folder = tmp_path / "runs" / run_id
        folder.mkdir(parents=True)
        manifest = {"run_id": run_id, "config_hash": f"h{run_id}", "status": status}
        (folder / "manifest.json").write_text(json.dumps(manifest))
    assert run_hashes(tmp_path) == {"a-s0": "ha-s0"}
    assert run_hashes_main([str(tmp_path)]) == 0
    assert json.loads(capsys.readouterr().out) == {"a-s0": "ha-s0"}
    with pytest.raises(SystemExit):
        run_hashes_main([str(tmp_path / "empty")])
