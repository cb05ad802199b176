"""sb3-pnn: discrete Soft Actor-Critic and progressive policies for Stable-Baselines3."""

from sb3_pnn.baselines import AdaptivePIDController, PIDController, make_baseline
from sb3_pnn.dsac import DiscreteSAC
from sb3_pnn.evaluation import EvaluationResult, evaluate_policy_on_task, wilson_interval
from sb3_pnn.policies import (
    DiscreteActor,
    DiscreteCritic,
    DiscreteSACPolicy,
    MultiInputDiscreteSACPolicy,
)
from sb3_pnn.progressive import ProgressivePolicy, SelectivePolicy, load_prior, make_sac_multi

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
