"""rl-zoo style commands for sb3_pnn: train, enjoy and Optuna tuning on top of rl_zoo3.

Importing this package needs the ``zoo`` extra (rl_zoo3, optuna, pandas, requests, tensorboard).
Entry points: ``python -m sb3_pnn.train`` and ``python -m sb3_pnn.enjoy``.
"""

from sb3_pnn.zoo.callbacks import RovMetricsCallback
from sb3_pnn.zoo.errors import ZooUsageError
from sb3_pnn.zoo.registry import OUR_ALGOS, register_algos

__all__ = ["OUR_ALGOS", "RovMetricsCallback", "ZooUsageError", "register_algos"]
