"""sb3-pnn: discrete Soft Actor-Critic and progressive policies for Stable-Baselines3.

Packages: :mod:`sb3_pnn.dsac` (the algorithm), :mod:`sb3_pnn.progressive` (PNN and SPNN
policies over frozen prior columns), :mod:`sb3_pnn.safe_io` (checkpoints that load without
running code), :mod:`sb3_pnn.baselines` (PID controllers), :mod:`sb3_pnn.evaluation`,
:mod:`sb3_pnn.zoo` (rl-zoo commands), :mod:`sb3_pnn.reproduce` (the paper's study) and
:mod:`sb3_pnn.common` (what they share).
"""

from rov_envs.moved import install as _install_moved
from sb3_pnn.baselines import AdaptivePIDController, PIDController, make_baseline
from sb3_pnn.dsac import (
    DiscreteActor,
    DiscreteCritic,
    DiscreteSAC,
    DiscreteSACPolicy,
    MultiInputDiscreteSACPolicy,
)
from sb3_pnn.evaluation import EvaluationResult, evaluate_policy_on_task, wilson_interval
from sb3_pnn.progressive import ProgressivePolicy, SelectivePolicy, load_prior, make_sac_multi

#: sb3_pnn's old module paths -> the new ones (importing an old one names the new one).
MOVED_MODULES = {
    "sb3_pnn.checks": "sb3_pnn.common.checks",
    "sb3_pnn.suggest": "sb3_pnn.common.checks",
    "sb3_pnn.validation": "sb3_pnn.common.callbacks",
    "sb3_pnn.policies": "sb3_pnn.dsac.policies",
    "sb3_pnn.lean_adam": "sb3_pnn.dsac.lean_adam",
    "sb3_pnn.lean_predict": "sb3_pnn.dsac.lean_predict",
    **{f"sb3_pnn.reproduce.{m}": f"sb3_pnn.reproduce.planning.{m}" for m in ("plan", "setups")},
    **{
        f"sb3_pnn.reproduce.{m}": f"sb3_pnn.reproduce.running.{m}"
        for m in ("executor", "store", "work", "recorder", "results", "adopt")
    },
    **{
        f"sb3_pnn.reproduce.{m}": f"sb3_pnn.reproduce.reporting.{m}"
        for m in ("report", "figures", "stats")
    },
    "sb3_pnn.reproduce.ablation_cli": "sb3_pnn.reproduce.ablation.cli",
    "sb3_pnn.reproduce.ablation_report": "sb3_pnn.reproduce.ablation.report",
}
_install_moved(MOVED_MODULES)

__all__ = [
    "AdaptivePIDController",
    "EvaluationResult",
    "PIDController",
    "evaluate_policy_on_task",
    "make_baseline",
    "wilson_interval",
    "DiscreteActor",
    "DiscreteCritic",
    "DiscreteSAC",
    "DiscreteSACPolicy",
    "MultiInputDiscreteSACPolicy",
    "ProgressivePolicy",
    "SelectivePolicy",
    "load_prior",
    "make_sac_multi",
]
