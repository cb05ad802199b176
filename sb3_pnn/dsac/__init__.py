"""Discrete-action Soft Actor-Critic (paper section 3.2; Christodoulou 2019) for Stable-Baselines3.

* :mod:`.dsac`: the algorithm, :class:`DiscreteSAC` (an SB3 ``OffPolicyAlgorithm``), and its
  losses as pure functions (:func:`soft_td_target`, :func:`discrete_sac_losses`);
* :mod:`.policies`: the categorical actor, the twin Q-critics and the policy that holds them;
* :mod:`.lean_predict` and :mod:`.lean_adam`: same-bits fast paths for ``predict`` and the fused
  Adam step (the same numbers as SB3's and PyTorch's paths, with less Python around them).
"""

from sb3_pnn.dsac.dsac import (
    DEFAULT_TARGET_ENTROPY_RATIO,
    PAPER_BATCH_SIZE,
    DiscreteSAC,
    DiscreteSACLosses,
    discrete_sac_losses,
    soft_td_target,
)
from sb3_pnn.dsac.policies import (
    DiscreteActor,
    DiscreteCritic,
    DiscreteSACPolicy,
    MultiInputDiscreteSACPolicy,
)

__all__ = [
    "DEFAULT_TARGET_ENTROPY_RATIO",
    "PAPER_BATCH_SIZE",
    "DiscreteActor",
    "DiscreteCritic",
    "DiscreteSAC",
    "DiscreteSACLosses",
    "DiscreteSACPolicy",
    "MultiInputDiscreteSACPolicy",
    "discrete_sac_losses",
    "soft_td_target",
]
