"""Classical baselines of the paper (section 4.3): PID and adaptive PID heading controllers.

Both follow SB3's ``predict(obs, state=None, episode_start=None, deterministic=True)`` interface,
so they run wherever a trained model does (see :mod:`sb3_pnn.evaluation`).
"""

from __future__ import annotations

from typing import Any

from sb3_pnn.baselines.adaptive_pid import AdaptivePIDController
from sb3_pnn.baselines.pid import DEFAULT_DT, PIDController

__all__ = [
    "BASELINE_NAMES",
    "DEFAULT_DT",
    "AdaptivePIDController",
    "PIDController",
    "make_baseline",
]

#: Names accepted by :func:`make_baseline` (and by ``python -m sb3_pnn.evaluate --model``).
BASELINE_NAMES: tuple[str, ...] = ("pid", "adaptive_pid")
_CLASSES = {"pid": PIDController, "adaptive_pid": AdaptivePIDController}


def make_baseline(name: str, env: Any = None, **overrides: Any) -> PIDController:
    """Build baseline ``name`` ("pid" or "adaptive_pid").

    Args:
        name: one of :data:`BASELINE_NAMES`.
        env: optional rov_envs env (single or batched, wrapped or not) or its
            ``rov_envs.sim.config.EnvConfig``: control period, action type and sonar geometry are
            read from it. Without it the env defaults are assumed (1.0 s, Discrete(5), 25 m,
            pi span).
        **overrides: constructor arguments (gains, thresholds, ...).
    """
    if name not in _CLASSES:
        raise ValueError(f"name={name!r} is not allowed: expected one of {list(BASELINE_NAMES)}")
    cls = _CLASSES[name]
    if env is None:
        return cls(**overrides)
    return cls.for_env(env, **overrides)
