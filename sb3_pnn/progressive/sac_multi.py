"""The paper's SAC-Multi baseline (section 4.3): fine-tune a prior's networks on the new task.

:func:`make_sac_multi` builds a plain :class:`sb3_pnn.DiscreteSAC` whose actor and critics have
the prior's architecture and start from the prior's weights (read safely, see
:mod:`.prior_loading`); all of them are then trained. Observation inputs that the prior never saw
(e.g. the sonar, for a path-following prior) get zero weights in the first layer, so the first
policy and Q-values are exactly the prior's on every new observation.

For a DQN prior both the actor and every critic start from its Q-network (the actor's logits are
then the Q-values: same greedy action as the DQN, a softmax policy over them). For a DiscreteSAC
prior, critic i starts from the prior's critic ``i mod n``.
"""

from __future__ import annotations

import os
from typing import Any

import gymnasium as gym
import torch as th
from gymnasium import spaces
from stable_baselines3.common.type_aliases import GymEnv

from sb3_pnn.dsac.dsac import DiscreteSAC
from sb3_pnn.progressive.obs_spec import match_prior_obs, obs_spec_from_space
from sb3_pnn.progressive.prior_loading import ACTIVATIONS, load_prior
from sb3_pnn.progressive.weight_copy import copy_layers, input_columns


def make_sac_multi(
    prior_path: str | os.PathLike[str],
    env: GymEnv | str,
    policy: str | None = None,
    policy_kwargs: dict[str, Any] | None = None,
    **kwargs: Any,
) -> DiscreteSAC:
    """A DiscreteSAC on ``env`` initialised from the checkpoint at ``prior_path`` (SAC-Multi).

    :param prior_path: DiscreteSAC or SB3 DQN checkpoint (.zip)
    :param env: The new task's environment (or its id)
    :param policy: "MlpPolicy" / "MultiInputPolicy"; default chosen from the observation space
    :param policy_kwargs: Extra policy kwargs; ``net_arch``/``activation_fn`` come from the prior
    :param kwargs: Other DiscreteSAC arguments (learning_rate, seed, ...)
    """
    prior = load_prior(prior_path)
    spec = prior.spec
    policy_kwargs = dict(policy_kwargs or {})
    for key in ("net_arch", "activation_fn"):
        if key in policy_kwargs:
            raise ValueError(f"SAC-Multi takes {key} from the prior checkpoint; do not pass {key}")
    if spec.actor.hidden != spec.critics[0].hidden:
        arch: Any = dict(pi=list(spec.actor.hidden), qf=list(spec.critics[0].hidden))
    else:
        arch = list(spec.actor.hidden)
    policy_kwargs.update(net_arch=arch, activation_fn=ACTIVATIONS[spec.actor.activation])
    if isinstance(env, str):
        env = gym.make(env)
    if policy is None:
        policy = (
            "MultiInputPolicy" if isinstance(env.observation_space, spaces.Dict) else "MlpPolicy"
        )
    model = DiscreteSAC(policy, env, policy_kwargs=policy_kwargs, **kwargs)
    n = int(model.action_space.n)  # type: ignore[attr-defined]
    if n != spec.n_actions:
        raise ValueError(
            f"prior checkpoint {os.fspath(prior_path)!r} has {spec.n_actions} actions but the new "
            f"environment has {n}; SAC-Multi needs the same action space"
        )
    new = obs_spec_from_space(model.observation_space)
    feed = match_prior_obs(spec.obs, new, f"prior {os.fspath(prior_path)!r}")
    columns = input_columns(feed.keys, new)
    actor = model.policy.actor
    copy_layers(
        [m for m in actor.latent_pi if isinstance(m, th.nn.Linear)] + [actor.action_logits],
        prior.actor_layers,
        columns,
    )
    for i, q_net in enumerate(model.policy.critic.q_networks):
        layers = prior.critic_layers[i % len(prior.critic_layers)]
        copy_layers([m for m in q_net if isinstance(m, th.nn.Linear)], layers, columns)
    model.policy.critic_target.load_state_dict(model.policy.critic.state_dict())
    return model
