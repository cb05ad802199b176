"""The configuration hash of every finished run of a study folder, as JSON.

A study's documentation keeps this list beside its report (``docs/study_*/runs.json``), so that
a test can check that the command the documentation gives still plans exactly those runs: a
change of a default that the study was not rerun for, or an archived study's command that no
longer puts back a later change, then fails (tests/docs/test_study_commands.py).

Usage: python -m sb3_pnn.reproduce.tools.run_hashes STUDY > docs/study_NAME/runs.json
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def run_hashes(study: Path) -> dict[str, str]:
    """``{run_id: config_hash}`` of the runs in ``study/runs`` whose manifest says done."""
    hashes = {}
    for manifest in sorted((study / "runs").glob("*/manifest.json")):
        entry = json.loads(manifest.read_text())
        if entry.get("status") == "done":
            hashes[str(entry["run_id"])] = str(entry["config_hash"])
    return hashes


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("study", type=Path)
    args = parser.parse_args(argv)
    hashes = run_hashes(args.study)
    if not hashes:
        parser.error(f"{args.study / 'runs'} holds no finished run: expected a study folder")
    print(json.dumps(hashes, indent=1, sort_keys=True))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
