"""Evaluate a policy (an SB3 model or a PID baseline) on an rov_envs task (paper section 4.3).

* :mod:`.evaluate`: :func:`evaluate_policy_on_task`, seeded episodes in lock-step batches;
* :mod:`.backends`: where the episodes run (rov_envs' batched engine, or any Gymnasium env);
* :mod:`.result`: :class:`EvaluationResult` and the statistics behind Figures 12-20;
* :mod:`.no_reversal`: :class:`NoReversal`, a policy played without immediate turn reversals;
* :mod:`.played`: :func:`played_through`, a model played as the study plays it;
* :mod:`.__main__`: the command line, ``python -m sb3_pnn.evaluate`` (or ``python -m
  sb3_pnn.evaluation``, ``sb3-pnn-evaluate``).
"""

from sb3_pnn.evaluation.evaluate import (
    DEFAULT_MAX_ENVS,
    DEFAULT_START_NOISE,
    evaluate_policy_on_task,
    resolve_env_id,
)
from sb3_pnn.evaluation.no_reversal import NoReversal
from sb3_pnn.evaluation.result import EpisodeRecord, EvaluationResult, Trajectory, wilson_interval

__all__ = [
    "DEFAULT_MAX_ENVS",
    "DEFAULT_START_NOISE",
    "EpisodeRecord",
    "EvaluationResult",
    "NoReversal",
    "Trajectory",
    "evaluate_policy_on_task",
    "resolve_env_id",
    "wilson_interval",
]
