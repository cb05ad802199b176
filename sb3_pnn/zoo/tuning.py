"""Optuna search space for ``-optimize``: the SPNN switch (eq. 15) and, on request, SAC settings.

The paper fixed the SPNN switch distance d_th = 12.5 m and the mixing weights sigma = tau = 0.5
"after a number of experimental trials" (section 3.3, eq. 15). Here they are searched:

==============  =====================  ==========================================================
name            default bounds         allowed bounds
==============  =====================  ==========================================================
d_th            [2.5, 22.5] m          0 < low <= high <= the env's sonar range (``sonar_range``)
sigma           [0.1, 0.9]             0 <= low <= high <= 1 (weight of the selected prior column)
own_weight      [0.1, 0.9]             0 <= low <= high <= 1 (the paper's tau in eq. 15)
temperature     [0.1, 10.0] m, log     0 < low <= high <= sonar range; only with ``gate: soft``
==============  =====================  ==========================================================

With ``sac: true`` (always for dsac, pnn and sac_multi, which have no switch) the usual SAC
settings are searched as well: ``learning_rate`` [1e-5, 1e-2] (log), ``gamma`` [0.9, 0.9999],
``tau`` (Polyak) [1e-3, 0.05] (log), ``gradient_steps`` [1, 20], ``batch_size`` in
{64, 128, 256, 512}.

Bounds come from the entry's ``tuning:`` mapping in the zoo config, or from the command line
(``--tune d_th=5:20 --tune sigma=0.2:0.8 --tune-sac``). A name given a single number is fixed,
``null`` leaves it untuned. Bounds outside the allowed ranges are refused.

Storage: without ``--storage`` a journal file ``<log-folder>/<algo>/optuna/<env>.log`` that
several processes on one machine can share; a ``postgresql://`` (or other SQLAlchemy) URL for
many machines, with a heartbeat so that the trial of a killed worker is marked FAIL by the
next worker that starts a trial, after the grace period.
"""

from __future__ import annotations

import importlib.util
import math
import re
import time
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import optuna

from sb3_pnn.zoo.errors import ZooUsageError

SPNN_PARAMETERS = ("d_th", "sigma", "own_weight", "temperature")
SAC_PARAMETERS = ("learning_rate", "gamma", "tau", "gradient_steps", "batch_size")
LOG_SCALE = frozenset({"temperature", "learning_rate", "tau"})
INTEGER = frozenset({"gradient_steps"})

DEFAULT_BOUNDS: dict[str, Any] = {
    "d_th": (2.5, 22.5),
    "sigma": (0.1, 0.9),
    "own_weight": (0.1, 0.9),
    "temperature": (0.1, 10.0),
    "learning_rate": (1e-5, 1e-2),
    "gamma": (0.9, 0.9999),
    "tau": (1e-3, 0.05),
    "gradient_steps": (1, 20),
    "batch_size": (64, 128, 256, 512),
}
CREATE_ATTEMPTS = 4
PAPER_VALUES = {"d_th": 12.5, "sigma": 0.5, "own_weight": 0.5}


def _allowed(name: str, sonar_range: float) -> tuple[float, float, bool, bool]:
    """(low, high, low_open, high_open) allowed for ``name``."""
    return {
        "d_th": (0.0, sonar_range, True, False),
        "sigma": (0.0, 1.0, False, False),
        "own_weight": (0.0, 1.0, False, False),
        "temperature": (0.0, sonar_range, True, False),
        "learning_rate": (0.0, 1.0, True, False),
        "gamma": (0.0, 1.0, True, True),
        "tau": (0.0, 1.0, True, False),
        "gradient_steps": (1, 1000, False, False),
    }[name]


def _describe(low: float, high: float, low_open: bool, high_open: bool) -> str:
    return f"{'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"


@dataclass
class TuningSpace:
    """Which parameters are searched and in which bounds (see the module docstring)."""

    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)
    fixed: dict[str, float] = field(default_factory=dict)
    batch_sizes: tuple[int, ...] = ()

    def names(self) -> list[str]:
        return list(self.bounds) + (["batch_size"] if self.batch_sizes else [])


def _check_bound(name: str, value: Any, sonar_range: float, origin: str) -> tuple[float, float]:
    if (
        not isinstance(value, (list, tuple))
        or len(value) != 2
        or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
    ):
        raise ZooUsageError(
            f"{origin}: bounds of {name} must be [low, high] numbers, got {value!r}"
        )
    low, high = float(value[0]), float(value[1])
    if not (math.isfinite(low) and math.isfinite(high)) or low > high:
        raise ZooUsageError(f"{origin}: bounds of {name} need low <= high, got [{low:g}, {high:g}]")
    a_low, a_high, low_open, high_open = _allowed(name, sonar_range)
    inside = (low > a_low if low_open else low >= a_low) and (
        high < a_high if high_open else high <= a_high
    )
    if not inside:
        unit = " m (the env's sonar range caps it)" if name in ("d_th", "temperature") else ""
        allowed = _describe(a_low, a_high, low_open, high_open)
        raise ZooUsageError(
            f"{origin}: tuning bounds [{low:g}, {high:g}] for {name} are out of range; "
            f"allowed {allowed}{unit}"
        )
    if name in INTEGER:
        if low != int(low) or high != int(high):
            raise ZooUsageError(f"{origin}: bounds of {name} must be integers, got {value!r}")
    return low, high


def build_space(
    algo: str,
    spec: Mapping[str, Any] | None,
    *,
    sonar_range: float,
    gate: str | None,
    origin: str,
) -> TuningSpace:
    """Validate a ``tuning:`` mapping (merged with the command line) into a TuningSpace."""
    spec = dict(spec or {})
    tune_sac = spec.pop("sac", algo != "spnn")
    if not isinstance(tune_sac, (bool, dict)):
        raise ZooUsageError(f"{origin}: tuning 'sac' must be true, false or a mapping of bounds")
    sac_spec: dict[str, Any] = {}
    if isinstance(tune_sac, dict):
        sac_spec, tune_sac = dict(tune_sac), True
    unknown = set(spec) - set(SPNN_PARAMETERS) - set(SAC_PARAMETERS)
    if unknown:
        expected = ", ".join((*SPNN_PARAMETERS, *SAC_PARAMETERS, "sac"))
        raise ZooUsageError(
            f"{origin}: unknown tuning parameter(s) {sorted(unknown)}; expected {expected}"
        )
    if algo != "spnn":
        switch = [name for name in SPNN_PARAMETERS if spec.get(name) is not None]
        if switch:
            raise ZooUsageError(
                f"{origin}: {', '.join(switch)} belong to spnn's selective policy; {algo} has none"
            )
    requested: dict[str, Any] = {}
    if algo == "spnn":
        for name in SPNN_PARAMETERS:
            requested[name] = spec.get(name, DEFAULT_BOUNDS[name])
        if gate != "soft":
            requested["temperature"] = None
    if tune_sac:
        for name in SAC_PARAMETERS:
            requested[name] = spec.get(name, sac_spec.get(name, DEFAULT_BOUNDS[name]))
    else:
        for name in SAC_PARAMETERS:
            if name in spec:
                requested[name] = spec[name]
    space = TuningSpace()
    for name, value in requested.items():
        if value is None:
            continue
        if name == "batch_size":
            sizes = tuple(value) if isinstance(value, (list, tuple)) else (value,)
            if not sizes or not all(
                isinstance(s, int) and not isinstance(s, bool) and s > 0 for s in sizes
            ):
                raise ZooUsageError(
                    f"{origin}: batch_size choices must be positive integers, got {value!r}"
                )
            space.batch_sizes = sizes
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            low, _ = _check_bound(name, [value, value], sonar_range, origin)
            space.fixed[name] = int(low) if name in INTEGER else low
        else:
            space.bounds[name] = _check_bound(name, value, sonar_range, origin)
    return space


def parse_cli_bounds(items: list[str] | None) -> dict[str, Any]:
    """``--tune d_th=5:20`` -> {"d_th": [5.0, 20.0]}; ``--tune sigma=0.5`` fixes it."""
    result: dict[str, Any] = {}
    for item in items or []:
        match = re.fullmatch(r"\s*(\w+)\s*=\s*([^:]+?)\s*(?::\s*(.+?)\s*)?", item)
        if match is None:
            raise ZooUsageError(f"--tune expects NAME=LOW:HIGH or NAME=VALUE, got {item!r}")
        name, low, high = match.groups()
        try:
            if name == "batch_size":
                result[name] = [int(v) for v in item.split("=", 1)[1].split(",")]
            elif high is None:
                result[name] = None if low.lower() == "none" else float(low)
            else:
                result[name] = [float(low), float(high)]
        except ValueError:
            raise ZooUsageError(f"--tune {item!r}: bounds must be numbers") from None
    return result


def sample_params(trial: optuna.Trial, space: TuningSpace) -> dict[str, Any]:
    """Draw one point of ``space`` (flat names, as stored in ``trial.params``)."""
    params: dict[str, Any] = {}
    for name, (low, high) in space.bounds.items():
        if name in INTEGER:
            params[name] = trial.suggest_int(name, int(low), int(high))
        else:
            params[name] = trial.suggest_float(name, low, high, log=name in LOG_SCALE)
    if space.batch_sizes:
        params["batch_size"] = trial.suggest_categorical("batch_size", list(space.batch_sizes))
    params.update(space.fixed)
    return params


def convert_params(
    params: Mapping[str, Any], base_policy_kwargs: Mapping[str, Any] | None = None
) -> dict[str, Any]:
    """Flat sampled names -> learner keyword arguments.

    The switch parameters go into ``policy_kwargs``, merged over ``base_policy_kwargs`` (which
    keeps the config's ``priors``, ``net_arch``, ``gate`` ...); the others are top-level.
    """
    hyperparams: dict[str, Any] = {}
    policy_kwargs = dict(base_policy_kwargs or {})
    touched = False
    for name, value in params.items():
        if name in SPNN_PARAMETERS:
            policy_kwargs[name] = value
            touched = True
        else:
            hyperparams[name] = value
    if touched or base_policy_kwargs is not None:
        hyperparams["policy_kwargs"] = policy_kwargs
    return hyperparams


def make_sampler(
    space: TuningSpace, base_policy_kwargs: Mapping[str, Any] | None
) -> Callable[[optuna.Trial, int, int, dict], dict[str, Any]]:
    """A sampler with rl_zoo3's signature, for ``HYPERPARAMS_SAMPLER[algo]``."""

    def sampler(
        trial: optuna.Trial, n_actions: int, n_envs: int, additional_args: dict
    ) -> dict[str, Any]:
        return convert_params(sample_params(trial, space), base_policy_kwargs)

    return sampler


def make_converter(
    base_policy_kwargs: Mapping[str, Any] | None,
) -> Callable[[dict[str, Any]], dict[str, Any]]:
    """A converter with rl_zoo3's signature, for ``HYPERPARAMS_CONVERTER[algo]``."""

    def converter(params: dict[str, Any]) -> dict[str, Any]:
        return convert_params(params, base_policy_kwargs)

    return converter


def hide_password(url: str) -> str:
    return re.sub(r"(://[^:/@]+):[^@]*@", r"\1:***@", url)


def default_journal_path(log_folder: str, algo: str, env_name: str) -> str:
    return str(Path(log_folder) / algo / "optuna" / f"{env_name}.log")


def _with_available_postgres_driver(url: str) -> str:
    """``postgresql://`` with the driver that is installed (SQLAlchemy 2.1 defaults to psycopg 3;
    the ``tune`` extra installs psycopg2-binary)."""
    scheme, sep, rest = url.partition("://")
    if scheme not in ("postgresql", "postgres"):
        return url
    for module, driver in (("psycopg", "psycopg"), ("psycopg2", "psycopg2")):
        if importlib.util.find_spec(module) is not None:
            return f"postgresql+{driver}{sep}{rest}"
    return url


def create_storage(
    storage: str, *, heartbeat_interval: int = 60, grace_period: int | None = None
) -> optuna.storages.BaseStorage:
    """A journal file (``*.log``) or an RDB URL with heartbeat; refuses anything else clearly."""
    if storage.endswith(".log"):
        Path(storage).parent.mkdir(parents=True, exist_ok=True)
        backend = optuna.storages.journal.JournalFileBackend(storage)
        return optuna.storages.JournalStorage(backend)
    if "://" not in storage:
        raise ZooUsageError(
            f"--storage {storage!r}: expected a journal file ending in .log (one machine) or a "
            "database URL such as postgresql://user:password@host:5432/db (many machines)"
        )
    if heartbeat_interval <= 0:
        raise ZooUsageError(f"--heartbeat-interval must be positive, got {heartbeat_interval}")
    if grace_period is not None and grace_period <= heartbeat_interval:
        raise ZooUsageError(
            f"--grace-period ({grace_period} s) must exceed --heartbeat-interval "
            f"({heartbeat_interval} s)"
        )
    url = _with_available_postgres_driver(storage)
    try:
        for attempt in range(CREATE_ATTEMPTS):
            try:
                with warnings.catch_warnings():  # heartbeat is "experimental" in Optuna
                    warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
                    return optuna.storages.RDBStorage(
                        url,
                        heartbeat_interval=heartbeat_interval,
                        grace_period=grace_period,
                        engine_kwargs={"pool_pre_ping": True},
                    )
            except ImportError:
                raise
            except Exception as error:
                # Workers starting together on a fresh database race to create Optuna's
                # tables; the loser sees "already exists" and succeeds on a retry.
                if "already exists" not in str(error) or attempt == CREATE_ATTEMPTS - 1:
                    raise
                time.sleep(0.5 + attempt)
        raise AssertionError("unreachable")
    except ImportError as error:
        raise ZooUsageError(
            f"--storage {hide_password(storage)}: missing database driver ({error}); "
            "pip install psycopg2-binary (or sb3-pnn[tune])"
        ) from None
    except Exception as error:  # SQLAlchemy OperationalError / ArgumentError and the like
        reason = " ".join(str(error).split())[:300]
        raise ZooUsageError(
            f"--storage {hide_password(storage)}: cannot open the study database: {reason}"
        ) from None
