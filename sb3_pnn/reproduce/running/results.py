"""Read a study folder's finished runs back into one structure for figures and the report."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from sb3_pnn.reproduce.planning.plan import RunSpec
from sb3_pnn.reproduce.running.store import RunStore


@dataclass
class RunResult:
    """One finished run: its spec, manifest, training records and evaluation results."""

    spec: RunSpec
    manifest: dict[str, Any]
    episodes: dict[str, Any] | None = None
    evals: dict[str, dict[str, Any]] = field(default_factory=dict)
    folder: Path | None = None
    # the keep-best checks (sb3_pnn.common.callbacks.KeepBestOnValidation.to_dict); None without
    # them
    validation: dict[str, Any] | None = None

    def trajectories(self) -> dict[int, np.ndarray]:
        """Recorded training trajectories, episode index -> (T, 2)."""
        if self.folder is None or not (self.folder / "trajectories.npz").is_file():
            return {}
        with np.load(self.folder / "trajectories.npz") as data:
            return {int(k.split("_")[1]): data[k] for k in data.files}


@dataclass
class StudyResults:
    """All finished runs of a plan, and the ids of the unfinished or failed ones."""

    runs: dict[str, RunResult]
    missing: list[str]
    failures: dict[str, dict[str, Any]]

    def select(
        self, kind: str, agent: str | None = None, path: str | None = None
    ) -> list[RunResult]:
        out = [
            r
            for r in self.runs.values()
            if r.spec.kind == kind
            and (agent is None or r.spec.agent == agent)
            and (path is None or r.spec.path == path)
        ]
        return sorted(out, key=lambda r: r.spec.seed)


def load_results(plan: list[RunSpec], store: RunStore) -> StudyResults:
    """Load every finished run of ``plan`` from ``store``."""
    runs: dict[str, RunResult] = {}
    missing: list[str] = []
    for spec in plan:
        manifest = store.manifest(spec.run_id)
        if manifest is None or manifest.get("config_hash") != spec.config_hash():
            missing.append(spec.run_id)
            continue
        folder = store.run_dir(spec.run_id)
        result = RunResult(spec=spec, manifest=manifest, folder=folder)
        if (folder / "episodes.json").is_file():
            result.episodes = json.loads((folder / "episodes.json").read_text())
        if (folder / "eval.json").is_file():
            result.evals = json.loads((folder / "eval.json").read_text())
        if (folder / "validation.json").is_file():
            result.validation = json.loads((folder / "validation.json").read_text())
        runs[spec.run_id] = result
    failures = {k: v for k, v in store.failures().items() if k in missing}
    return StudyResults(runs=runs, missing=missing, failures=failures)
