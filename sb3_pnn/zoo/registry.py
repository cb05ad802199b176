"""Registering this package's algorithms into rl_zoo3 (the araffin/sbx pattern, no fork).

``dsac``, ``sac_multi``, ``pnn`` and ``spnn`` all train :class:`sb3_pnn.DiscreteSAC`; they differ
by policy and priors, which their ``zoo_configs/<algo>.yml`` entries set, and by their log
folders (``logs/<algo>/...``) and TensorBoard run names (:data:`TB_LOG_NAMES`).
"""

from __future__ import annotations

import importlib
from typing import Any

import rl_zoo3
import rl_zoo3.enjoy
import rl_zoo3.exp_manager
import rl_zoo3.hyperparams_opt as hyperparams_opt
import rl_zoo3.train
from stable_baselines3.common.base_class import BaseAlgorithm

from sb3_pnn.dsac.dsac import DiscreteSAC
from sb3_pnn.progressive import make_sac_multi
from sb3_pnn.zoo.tuning import build_space, make_converter, make_sampler


class SACMulti:
    """rl_zoo3's entry for ``sac_multi``, the paper's SAC-Multi baseline (section 4.3).

    Called like an algo class (``SACMulti()(env=..., policy_kwargs=..., **kwargs)``) it builds a
    :class:`DiscreteSAC` with :func:`sb3_pnn.make_sac_multi` from the single checkpoint in
    ``policy_kwargs["priors"]`` (networks start from the prior's weights, then are all trained);
    ``load`` is :meth:`DiscreteSAC.load` (a saved SAC-Multi model is a plain DiscreteSAC).
    """

    algo_class = DiscreteSAC

    def __call__(
        self,
        env: Any,
        policy: str | None = None,
        policy_kwargs: dict[str, Any] | None = None,
        **kwargs: Any,
    ) -> DiscreteSAC:
        policy_kwargs = dict(policy_kwargs or {})
        priors = list(policy_kwargs.pop("priors", None) or [])
        if len(priors) != 1:
            raise ValueError(
                f"sac_multi starts from exactly one prior checkpoint, got {len(priors)}: {priors}"
            )
        return make_sac_multi(priors[0], env, policy=policy, policy_kwargs=policy_kwargs, **kwargs)

    def load(self, *args: Any, **kwargs: Any) -> DiscreteSAC:
        return DiscreteSAC.load(*args, **kwargs)

    def __repr__(self) -> str:
        return "SACMulti()"


OUR_ALGOS: dict[str, Any] = {
    "dsac": DiscreteSAC,
    "sac_multi": SACMulti(),
    "pnn": DiscreteSAC,
    "spnn": DiscreteSAC,
}
TB_LOG_NAMES = {"dsac": "DSAC", "sac_multi": "SAC_Multi", "pnn": "PNN", "spnn": "SPNN"}
ENV_PACKAGE = "rov_envs"


def _default_sampler(algo: str) -> Any:
    gate = "hard" if algo == "spnn" else None
    space = build_space(algo, None, sonar_range=25.0, gate=gate, origin=f"{algo} defaults")
    return make_sampler(space, None)


def register_algos() -> dict[str, type[BaseAlgorithm]]:
    """Put our algos into ``rl_zoo3.ALGOS`` (and its module-level copies), our Optuna samplers
    and converters into ``rl_zoo3.hyperparams_opt``, and register the rov_envs tasks.

    Idempotent. Returns the zoo's ALGOS mapping.
    """
    importlib.import_module(ENV_PACKAGE)  # registers rov_envs/<Task>-v0 with gymnasium
    algos = rl_zoo3.ALGOS
    algos.update(OUR_ALGOS)
    for module in (rl_zoo3.train, rl_zoo3.exp_manager, rl_zoo3.enjoy):
        module.ALGOS = algos  # the zoo imports ALGOS by name into each module
    for algo in OUR_ALGOS:
        # Defaults; a tuning run replaces them with the entry's bounds and base policy_kwargs.
        hyperparams_opt.HYPERPARAMS_SAMPLER.setdefault(algo, _default_sampler(algo))
        hyperparams_opt.HYPERPARAMS_CONVERTER.setdefault(algo, make_converter(None))
    return algos
