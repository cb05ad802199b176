"""Finding and checking the rl-zoo style hyperparameter files (``zoo_configs/<algo>.yml``).

Lookup order for the default ``--conf-file`` of an algo (``<algo>.yml`` holds our set-up,
``paper/<algo>.yml`` the paper's read literally, picked by ``--setup paper``):

1. ``$SB3_PNN_ZOO_CONFIGS/<algo>.yml`` when that variable names a folder;
2. ``zoo_configs/<algo>.yml`` beside the ``sb3_pnn`` package (a repository checkout or an editable
   install);
3. ``<sys.prefix>/share/sb3-pnn/zoo_configs/<algo>.yml`` (where a wheel installs the files as
   ``data_files``).

Each file maps an env id (``rov_envs/<Task>-v0``) to an entry. An entry holds the zoo's own keys
(``n_timesteps``, ``policy``, ``policy_kwargs``, ``env_kwargs``, ...), the learner's constructor
arguments, and two keys of ours that never reach the constructor: ``priors`` (see
:mod:`sb3_pnn.zoo.priors`) and ``tuning`` (see :mod:`sb3_pnn.zoo.tuning`).
"""

from __future__ import annotations

import inspect
import os
import sys
from pathlib import Path
from typing import Any

import yaml

from sb3_pnn.common.checks import did_you_mean
from sb3_pnn.zoo.errors import ZooUsageError

CONFIG_ENV_VAR = "SB3_PNN_ZOO_CONFIGS"

# Keys the zoo's ExperimentManager consumes itself (never passed to the learner's constructor).
ZOO_KEYS = frozenset(
    {
        "n_timesteps",
        "n_envs",
        "policy",
        "policy_kwargs",
        "env_kwargs",
        "env_wrapper",
        "vec_env_wrapper",
        "callback",
        "normalize",
        "frame_stack",
        "monitor_kwargs",
        "noise_type",
        "noise_std",
    }
)
# Keys of ours, consumed before the zoo sees the entry.
OUR_KEYS = frozenset({"priors", "tuning"})
# Arguments the zoo passes to the constructor itself (an entry must not set them).
RESERVED_KEYS = frozenset({"env", "seed", "verbose", "device", "tensorboard_log"})


def config_search_dirs() -> list[Path]:
    """The folders searched for ``<algo>.yml``, in order."""
    dirs: list[Path] = []
    custom = os.environ.get(CONFIG_ENV_VAR)
    if custom:
        dirs.append(Path(custom).expanduser())
    package_root = Path(__file__).resolve().parents[2]
    dirs.append(package_root / "zoo_configs")
    dirs.append(Path(sys.prefix) / "share" / "sb3-pnn" / "zoo_configs")
    return dirs


#: The shipped set-ups: ``ours`` (the default files) and ``paper`` (the ``paper/`` subfolder),
#: the same two as ``sb3_pnn.reproduce --setup`` (sb3_pnn/reproduce/planning/setups.py).
CONFIG_SETUPS = {"ours": "", "paper": "paper"}


def default_config_path(algo: str, setup: str = "ours") -> Path:
    """The default hyperparameter file of ``algo`` for ``setup`` (``"ours"`` or ``"paper"``;
    first hit of :func:`config_search_dirs`)."""
    if setup not in CONFIG_SETUPS:
        raise ZooUsageError(
            f"--setup {setup!r}: {did_you_mean(setup, list(CONFIG_SETUPS))}"
            f"expected one of {', '.join(CONFIG_SETUPS)}"
        )
    candidates = [folder / CONFIG_SETUPS[setup] / f"{algo}.yml" for folder in config_search_dirs()]
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    searched = ", ".join(str(c) for c in candidates)
    raise ZooUsageError(
        f"no configuration file for algo {algo!r}: looked for {searched}; "
        f"pass one with --conf-file or set {CONFIG_ENV_VAR} to a folder holding {algo}.yml"
    )


def load_config_file(path: str | Path) -> dict[str, Any]:
    """Parse a zoo YAML file; a syntax error or a non-mapping top level is a ZooUsageError."""
    path = Path(path)
    if not path.is_file():
        raise ZooUsageError(f"configuration file {str(path)!r} does not exist")
    try:
        with open(path) as handle:
            content = yaml.safe_load(handle)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f" line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(error, "problem", None) or str(error)
        raise ZooUsageError(f"{path}:{where}: malformed YAML: {problem}") from None
    if not isinstance(content, dict):
        raise ZooUsageError(
            f"{path}: expected a mapping of env ids to hyperparameter entries, "
            f"got {type(content).__name__}"
        )
    return content


def constructor_arguments(algo_class: Any) -> set[str]:
    """Keyword arguments accepted by ``algo_class.__init__`` (of ``.algo_class`` for a factory)."""
    algo_class = getattr(algo_class, "algo_class", algo_class)
    parameters = inspect.signature(algo_class.__init__).parameters
    return {name for name in parameters if name != "self"}


def select_entry(config: dict[str, Any], env_id: str, path: str | Path) -> tuple[str, Any]:
    """The entry the zoo will use for ``env_id`` (the env's own, else ``default``)."""
    if env_id in config:
        return env_id, config[env_id]
    if "default" in config:
        return "default", config["default"]
    available = ", ".join(sorted(str(k) for k in config if "/" in str(k) or "-v" in str(k)))
    raise ZooUsageError(
        f"{path}: no entry for env {env_id!r} (entries: {available or 'none'}); "
        "add one or pass another --conf-file"
    )


def validate_entry(
    entry: Any, *, name: str, path: str | Path, algo: str, algo_class: Any
) -> dict[str, Any]:
    """Check one entry's structure and keys; returns it unchanged.

    Unknown keys are refused (a typo such as ``lerning_rate`` would otherwise reach the learner as
    an unexpected keyword argument, or be silently ignored by the zoo).
    """
    where = f"{path} [{name}]"
    if not isinstance(entry, dict):
        raise ZooUsageError(
            f"{where}: an entry must be a mapping of hyperparameters, got {entry!r}"
        )
    if "n_timesteps" not in entry:
        raise ZooUsageError(f"{where}: missing 'n_timesteps' (total environment steps)")
    n_timesteps = entry["n_timesteps"]
    if isinstance(n_timesteps, bool) or not isinstance(n_timesteps, (int, float)):
        raise ZooUsageError(f"{where}: n_timesteps must be a number, got {n_timesteps!r}")
    if n_timesteps <= 0:
        raise ZooUsageError(f"{where}: n_timesteps must be positive, got {n_timesteps!r}")
    accepted = constructor_arguments(algo_class)
    for key in entry:
        if not isinstance(key, str):
            raise ZooUsageError(f"{where}: hyperparameter names must be strings, got {key!r}")
        if key in RESERVED_KEYS:
            raise ZooUsageError(f"{where}: {key!r} is set by the command line, not the config")
        if key not in ZOO_KEYS | OUR_KEYS and key not in accepted:
            names = sorted(
                name
                for name in (ZOO_KEYS | OUR_KEYS | accepted) - RESERVED_KEYS
                if not name.startswith("_")  # SB3's internal constructor arguments
            )
            hint = did_you_mean(key, names)
            expected = hint.rstrip() if hint else f"expected one of {', '.join(names)}"
            raise ZooUsageError(f"{where}: unknown hyperparameter {key!r} for {algo}; {expected}")
    policy_kwargs = entry.get("policy_kwargs")
    if policy_kwargs is not None and not isinstance(policy_kwargs, (dict, str)):
        raise ZooUsageError(
            f"{where}: policy_kwargs must be a mapping (or a Python dict expression), "
            f"got {policy_kwargs!r}"
        )
    env_kwargs = entry.get("env_kwargs")
    if env_kwargs is not None and not isinstance(env_kwargs, dict):
        raise ZooUsageError(f"{where}: env_kwargs must be a mapping, got {env_kwargs!r}")
    priors = entry.get("priors")
    if priors is not None and not isinstance(priors, list):
        raise ZooUsageError(f"{where}: priors must be a list of prior references, got {priors!r}")
    tuning = entry.get("tuning")
    if tuning is not None and not isinstance(tuning, dict):
        raise ZooUsageError(f"{where}: tuning must be a mapping, got {tuning!r}")
    return entry
