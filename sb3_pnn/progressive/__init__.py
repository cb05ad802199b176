"""Progressive (PNN, eq. 13) and selective progressive (SPNN, eq. 15) policies for DiscreteSAC,
safe loading of prior columns from SB3 checkpoints, and the SAC-Multi baseline."""

from sb3_pnn.progressive.gates import DistanceGate, LearnedGate
from sb3_pnn.progressive.obs_spec import ObsSpec, match_prior_obs, obs_spec_from_space
from sb3_pnn.progressive.prior_loading import PriorCheckpoint, PriorSpec, load_prior
from sb3_pnn.progressive.progressive_policy import ProgressivePolicy
from sb3_pnn.progressive.sac_multi import make_sac_multi
from sb3_pnn.progressive.selective_policy import SelectivePolicy
from sb3_pnn.progressive.switch_memory import SwitchMemory

__all__ = [
    "DistanceGate",
    "LearnedGate",
    "ObsSpec",
    "PriorCheckpoint",
    "PriorSpec",
    "ProgressivePolicy",
    "SelectivePolicy",
    "SwitchMemory",
    "load_prior",
    "make_sac_multi",
    "match_prior_obs",
    "obs_spec_from_space",
]
