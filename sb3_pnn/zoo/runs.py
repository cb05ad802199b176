"""Run folders of the zoo's log layout, ``<log-folder>/<algo>/<env>_<N>/``.

rl_zoo3 takes the largest N as "the latest run", even when that folder holds no model (``-optimize``
and runs that failed or were interrupted early leave such folders). Priors and ``enjoy`` use
:func:`latest_run_with` instead: the largest N whose folder holds the model asked for.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

HasModel = Callable[[Path], bool]


def run_ids(algo_folder: str | os.PathLike[str], env_name: str) -> list[int]:
    """The run numbers N of the folders ``<algo_folder>/<env_name>_<N>``, largest first."""
    folder = Path(algo_folder)
    prefix = f"{env_name}_"
    if not folder.is_dir():
        return []
    ids = [
        int(child.name[len(prefix) :])
        for child in folder.iterdir()
        if child.name.startswith(prefix) and child.name[len(prefix) :].isdigit() and child.is_dir()
    ]
    return sorted(ids, reverse=True)


def latest_run_with(algo_folder: str | os.PathLike[str], env_name: str, has_model: HasModel) -> int:
    """The largest run number whose folder holds a model (``has_model(folder)``), 0 if none."""
    for n in run_ids(algo_folder, env_name):
        if has_model(Path(algo_folder) / f"{env_name}_{n}"):
            return n
    return 0


def runs_summary(algo_folder: str | os.PathLike[str], env_name: str, has_model: HasModel) -> str:
    """Which runs hold a model, for an error message: ``"runs holding one: 2, 1"``."""
    ids = run_ids(algo_folder, env_name)
    if not ids:
        return f"no run folders {os.path.join(algo_folder, env_name)}_<N>"
    holding = [n for n in ids if has_model(Path(algo_folder) / f"{env_name}_{n}")]
    if not holding:
        return f"run folders {_listed(ids)} hold none"
    return f"runs holding one: {_listed(holding)}"


def _listed(ids: list[int], most: int = 8) -> str:
    text = ", ".join(str(n) for n in ids[:most])
    return text + (f" (+{len(ids) - most} more)" if len(ids) > most else "")
