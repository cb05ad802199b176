"""Actor, critics and policies of discrete Soft Actor-Critic (paper section 3.2, Table 2).

The networks are plain fully connected nets, as in the paper's Table 2 (hidden layers
[255, 255], ReLU, no output activation); only the output layer differs from SB3's continuous
SAC: the actor outputs one logit per action (a softmax policy) and every Q-network outputs one
value per action, Q(s, .), instead of taking the action as an input (Christodoulou 2019).

Module names (stable: checkpoints are read by these names, e.g. by the progressive policies)
-------------------------------------------------------------------------------------------
``policy.actor`` (:class:`DiscreteActor`)
    ``actor.features_extractor``  SB3 features extractor (Flatten / CombinedExtractor for Dict)
    ``actor.latent_pi``           ``nn.Sequential`` of the hidden layers: Linear at indices
                                  0, 2, 4, ... each followed by the activation (1, 3, 5, ...)
    ``actor.action_logits``       ``nn.Linear(last hidden, n_actions)``, the logits
``policy.critic`` and ``policy.critic_target`` (:class:`DiscreteCritic`)
    ``critic.features_extractor`` one features extractor shared by the critic's Q-networks
    ``critic.q_networks[i]``      ``nn.Sequential``, i < n_critics: hidden Linear layers at
                                  indices 0, 2, ..., activations between, and the last entry the
                                  ``Linear(last hidden, n_actions)`` output (state-dict keys
                                  ``q_networks.<i>.<layer>.weight``)

Contract for subclasses (what DiscreteSAC relies on): the policy builds
its networks with :meth:`DiscreteSACPolicy.make_actor` and :meth:`DiscreteSACPolicy.make_critic`,
which a subclass may override to build other networks, as long as ``actor(obs)`` returns logits
of shape (B, n_actions) and ``critic(obs)`` returns a tuple of ``n_critics`` tensors of shape
(B, n_actions). Optimizers only receive parameters with ``requires_grad=True``.
"""

import itertools
from typing import Any

import numpy as np
import torch as th
from gymnasium import spaces
from stable_baselines3.common.policies import BaseModel, BasePolicy
from stable_baselines3.common.torch_layers import (
    BaseFeaturesExtractor,
    CombinedExtractor,
    FlattenExtractor,
    create_mlp,
    get_actor_critic_arch,
)
from stable_baselines3.common.type_aliases import PyTorchObs, Schedule
from torch import nn

from sb3_pnn.dsac.lean_adam import LeanFusedAdam
from sb3_pnn.dsac.lean_predict import lean_obs_to_tensor, lean_space_shapes
from sb3_pnn.safe_io.policy_registry import register_policy_class

#: Hidden layers of every actor and critic by default: the recommended set-up's (a third of the
#: update cost of the paper's; the ablation in docs/ablation measures the difference).
DEFAULT_NET_ARCH = [64, 64]
#: The paper's hidden layers (Table 2: FCN = [255, 255, n_out]).
PAPER_NET_ARCH = [255, 255]


def actions_from_logits(logits: th.Tensor, deterministic: bool = False) -> th.Tensor:
    """
    Greedy (argmax) or sampled action for every row of ``logits`` (B, n_actions) -> (B,).

    Sampling uses the Gumbel-max trick, argmax(logits + G) with G = -log(E), E ~ Exp(1), an exact
    sample of softmax(logits) that is about twice as fast per step as ``th.multinomial``.
    """
    if deterministic:
        return logits.argmax(dim=1)
    return (logits - th.empty_like(logits).exponential_().log()).argmax(dim=1)


class DiscreteActor(BasePolicy):
    """
    Softmax policy pi(a|s) for discrete actions: features -> MLP -> one logit per action.

    :param observation_space: Observation space
    :param action_space: Discrete action space
    :param net_arch: Hidden layer sizes
    :param features_extractor: Network to extract features
    :param features_dim: Number of features
    :param activation_fn: Activation function of the hidden layers
    :param normalize_images: Whether to divide image observations by 255
    """

    action_space: spaces.Discrete

    def __init__(
        self,
        observation_space: spaces.Space,
        action_space: spaces.Discrete,
        net_arch: list[int],
        features_extractor: BaseFeaturesExtractor,
        features_dim: int,
        activation_fn: type[nn.Module] = nn.ReLU,
        normalize_images: bool = True,
    ):
        super().__init__(
            observation_space,
            action_space,
            features_extractor=features_extractor,
            normalize_images=normalize_images,
        )
        self.net_arch = net_arch
        self.features_dim = features_dim
        self.activation_fn = activation_fn
        self.latent_pi = nn.Sequential(*create_mlp(features_dim, -1, net_arch, activation_fn))
        last_layer_dim = net_arch[-1] if len(net_arch) > 0 else features_dim
        self.action_logits = nn.Linear(last_layer_dim, int(action_space.n))

    def _get_constructor_parameters(self) -> dict[str, Any]:
        data = super()._get_constructor_parameters()
        data.update(
            dict(
                net_arch=self.net_arch,
                features_dim=self.features_dim,
                activation_fn=self.activation_fn,
                features_extractor=self.features_extractor,
            )
        )
        return data

    def forward(self, obs: PyTorchObs) -> th.Tensor:
        """Logits of pi(.|s), shape (B, n_actions)."""
        features = self.extract_features(obs, self.features_extractor)
        return self.action_logits(self.latent_pi(features))

    def _predict(self, observation: PyTorchObs, deterministic: bool = False) -> th.Tensor:
        return actions_from_logits(self(observation), deterministic)


class DiscreteCritic(BaseModel):
    """
    ``n_critics`` Q-networks, each mapping features to Q(s, a) for every action a.

    :param observation_space: Observation space
    :param action_space: Discrete action space
    :param net_arch: Hidden layer sizes of each Q-network
    :param features_extractor: Network to extract features (shared by the Q-networks)
    :param features_dim: Number of features
    :param activation_fn: Activation function of the hidden layers
    :param normalize_images: Whether to divide image observations by 255
    :param n_critics: Number of Q-networks (2: clipped double Q-learning)
    :param share_features_extractor: Whether the features extractor is the actor's; if so it is
        trained by the actor loss only (features computed without gradient here, as in SB3)
    """

    action_space: spaces.Discrete
    features_extractor: BaseFeaturesExtractor

    def __init__(
        self,
        observation_space: spaces.Space,
        action_space: spaces.Discrete,
        net_arch: list[int],
        features_extractor: BaseFeaturesExtractor,
        features_dim: int,
        activation_fn: type[nn.Module] = nn.ReLU,
        normalize_images: bool = True,
        n_critics: int = 2,
        share_features_extractor: bool = False,
    ):
        super().__init__(
            observation_space,
            action_space,
            features_extractor=features_extractor,
            normalize_images=normalize_images,
        )
        self.net_arch = net_arch
        self.features_dim = features_dim
        self.activation_fn = activation_fn
        self.n_critics = n_critics
        self.share_features_extractor = share_features_extractor
        n_actions = int(action_space.n)
        self.q_networks = nn.ModuleList(
            nn.Sequential(*create_mlp(features_dim, n_actions, net_arch, activation_fn))
            for _ in range(n_critics)
        )

    def forward(self, obs: PyTorchObs) -> tuple[th.Tensor, ...]:
        """Q-values of every action from each Q-network: ``n_critics`` tensors (B, n_actions)."""
        with th.set_grad_enabled(th.is_grad_enabled() and not self.share_features_extractor):
            features = self.extract_features(obs, self.features_extractor)
        return tuple(q_net(features) for q_net in self.q_networks)


class DiscreteSACPolicy(BasePolicy):
    """
    Policy of discrete SAC: a softmax actor, ``n_critics`` Q-networks and their Polyak targets.

    :param observation_space: Observation space
    :param action_space: Discrete action space
    :param lr_schedule: Learning rate schedule (``lr_schedule(1)`` is the initial rate)
    :param net_arch: Hidden layers, a list (actor and critic alike) or
        ``dict(pi=[...], qf=[...])``; default [64, 64] (the paper's Table 2: [255, 255])
    :param activation_fn: Activation function (ReLU, paper Table 2)
    :param features_extractor_class: Features extractor to use
    :param features_extractor_kwargs: Keyword arguments for the features extractor
    :param normalize_images: Whether to divide image observations by 255
    :param optimizer_class: Optimizer class (Adam)
    :param optimizer_kwargs: Extra optimizer keyword arguments, excluding the learning rate
    :param n_critics: Number of Q-networks (at least 1; 2 = twin critics)
    :param share_features_extractor: Share the actor's features extractor with the critic
    """

    actor: DiscreteActor
    critic: DiscreteCritic
    critic_target: DiscreteCritic
    action_space: spaces.Discrete

    def __init__(
        self,
        observation_space: spaces.Space,
        action_space: spaces.Discrete,
        lr_schedule: Schedule,
        net_arch: list[int] | dict[str, list[int]] | None = None,
        activation_fn: type[nn.Module] = nn.ReLU,
        features_extractor_class: type[BaseFeaturesExtractor] = FlattenExtractor,
        features_extractor_kwargs: dict[str, Any] | None = None,
        normalize_images: bool = True,
        optimizer_class: type[th.optim.Optimizer] = th.optim.Adam,
        optimizer_kwargs: dict[str, Any] | None = None,
        n_critics: int = 2,
        share_features_extractor: bool = False,
    ):
        if not isinstance(action_space, spaces.Discrete):
            raise ValueError(
                "DiscreteSACPolicy needs a gymnasium.spaces.Discrete action space, "
                f"got {action_space}"
            )
        if not isinstance(n_critics, int) or n_critics < 1:
            raise ValueError(f"n_critics must be an integer >= 1, got {n_critics!r}")
        super().__init__(
            observation_space,
            action_space,
            features_extractor_class,
            features_extractor_kwargs,
            optimizer_class=optimizer_class,
            optimizer_kwargs=optimizer_kwargs,
            normalize_images=normalize_images,
        )
        if net_arch is None:
            net_arch = list(DEFAULT_NET_ARCH)
        actor_arch, critic_arch = get_actor_critic_arch(net_arch)

        self.net_arch = net_arch
        self.activation_fn = activation_fn
        self.n_critics = n_critics
        self.share_features_extractor = share_features_extractor
        self.net_args = {
            "observation_space": self.observation_space,
            "action_space": self.action_space,
            "activation_fn": activation_fn,
            "normalize_images": normalize_images,
        }
        self.actor_kwargs = {**self.net_args, "net_arch": actor_arch}
        self.critic_kwargs = {
            **self.net_args,
            "net_arch": critic_arch,
            "n_critics": n_critics,
            "share_features_extractor": share_features_extractor,
        }
        self._build(lr_schedule)

    def _optimizer_kwargs(self) -> dict[str, Any]:
        """The optimizer's keyword arguments: the user's, plus ``fused=True`` for Adam.

        PyTorch's fused Adam does the whole parameter update in one kernel (``python
        bench/dsac_update.py`` times it against the unfused one). The arithmetic is Adam's;
        rounding may differ in the last bits. A ``fused`` given in ``optimizer_kwargs`` wins, and
        only the user's arguments are saved with the model.
        """
        kwargs = dict(self.optimizer_kwargs)
        if self.optimizer_class is th.optim.Adam and "fused" not in kwargs:
            kwargs["fused"] = self.device.type in ("cpu", "cuda")
        return kwargs

    def _make_optimizer(self, params: list[nn.Parameter], lr: float) -> th.optim.Optimizer:
        """``optimizer_class(params, lr=lr, **kwargs)``; a fused Adam is built as
        :class:`~sb3_pnn.dsac.lean_adam.LeanFusedAdam`, the same arithmetic bit for bit with less
        Python around the kernel (the class saved with the model stays ``optimizer_class``)."""
        kwargs = self._optimizer_kwargs()
        if self.optimizer_class is th.optim.Adam and kwargs.get("fused"):
            return LeanFusedAdam(params, lr=lr, **kwargs)
        return self.optimizer_class(params, lr=lr, **kwargs)  # type: ignore[call-arg]

    def _build(self, lr_schedule: Schedule) -> None:
        self.actor = self.make_actor()
        self.actor.optimizer = self._make_optimizer(
            [p for p in self.actor.parameters() if p.requires_grad], lr_schedule(1)
        )

        if self.share_features_extractor:
            self.critic = self.make_critic(features_extractor=self.actor.features_extractor)
            # The shared features extractor is trained by the actor loss only (as in SB3's SAC)
            critic_parameters = [
                p
                for name, p in self.critic.named_parameters()
                if p.requires_grad and not name.startswith("features_extractor.")
            ]
        else:
            self.critic = self.make_critic(features_extractor=None)
            critic_parameters = [p for p in self.critic.parameters() if p.requires_grad]
        self.critic.optimizer = self._make_optimizer(critic_parameters, lr_schedule(1))

        # The target never shares a features extractor and only moves by Polyak averaging
        self.critic_target = self.make_critic(features_extractor=None)
        self.critic_target.load_state_dict(self.critic.state_dict())
        self.critic_target.set_training_mode(False)
        self.critic_target.requires_grad_(False)

    def make_actor(self, features_extractor: BaseFeaturesExtractor | None = None) -> DiscreteActor:
        """Build the actor; a new features extractor unless one is given (to share)."""
        actor_kwargs = self._update_features_extractor(self.actor_kwargs, features_extractor)
        return DiscreteActor(**actor_kwargs).to(self.device)

    def make_critic(
        self, features_extractor: BaseFeaturesExtractor | None = None
    ) -> DiscreteCritic:
        """Build the critic (all Q-networks); a new features extractor unless one is given."""
        critic_kwargs = self._update_features_extractor(self.critic_kwargs, features_extractor)
        return DiscreteCritic(**critic_kwargs).to(self.device)

    def _get_constructor_parameters(self) -> dict[str, Any]:
        data = super()._get_constructor_parameters()
        data.update(
            dict(
                net_arch=self.net_arch,
                activation_fn=self.activation_fn,
                n_critics=self.n_critics,
                share_features_extractor=self.share_features_extractor,
                lr_schedule=self._dummy_schedule,  # not needed to load the policy alone
                optimizer_class=self.optimizer_class,
                optimizer_kwargs=self.optimizer_kwargs,
                features_extractor_class=self.features_extractor_class,
                features_extractor_kwargs=self.features_extractor_kwargs,
            )
        )
        return data

    def forward(self, obs: PyTorchObs, deterministic: bool = False) -> th.Tensor:
        return self._predict(obs, deterministic=deterministic)

    def predict(
        self,
        observation: np.ndarray | dict[str, np.ndarray],
        state: tuple[np.ndarray, ...] | None = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = False,
    ) -> tuple[np.ndarray, tuple[np.ndarray, ...] | None]:
        """
        SB3's ``BasePolicy.predict``, the same actions from the same observations and random
        state, with the observation converted by
        :func:`~sb3_pnn.dsac.lean_predict.lean_obs_to_tensor`
        (no deep copy, the device looked up once): SB3 calls this before every environment
        step. Observations that function does not handle go through SB3's own ``predict``.
        """
        # (space, actor, shapes, a parameter of the actor: its device), found once per actor
        lean = self.__dict__.get("_lean_predict")
        if lean is None or lean[0] is not self.observation_space or lean[1] is not self.actor:
            param = next(self.actor.parameters(), None)
            shapes = lean_space_shapes(self.observation_space) if param is not None else None
            lean = (self.observation_space, self.actor, shapes, param)
            self.__dict__["_lean_predict"] = lean
        _, _, shapes, param = lean
        converted = None
        if shapes is not None and state is None:
            converted = lean_obs_to_tensor(shapes, observation, param.device)
        if converted is None:
            return super().predict(observation, state, episode_start, deterministic)
        obs_tensor, vectorized = converted
        self.set_training_mode(False)
        with th.no_grad():
            actions = self._predict(obs_tensor, deterministic=deterministic)
        actions_np = actions.cpu().numpy().reshape((-1, *self.action_space.shape))
        if not vectorized:
            actions_np = actions_np.squeeze(axis=0)
        return actions_np, state

    def _predict(self, observation: PyTorchObs, deterministic: bool = False) -> th.Tensor:
        """Argmax of the logits when deterministic, else a sample of the softmax policy."""
        return actions_from_logits(self.actor(observation), deterministic)

    def set_training_mode(self, mode: bool) -> None:
        """
        Train/eval mode of actor and critic (the target always stays in eval mode).

        SB3 calls this before every ``predict``, i.e. every environment step, and DiscreteSAC
        before every ``train``, so with one update every few steps the mode flips twice per
        update; walking all submodules with ``nn.Module.train`` each time was a tenth of an SPNN
        run. The first switch to a mode walks them as SB3 does and keeps the flag it left on
        every module of the actor and critic (a frozen prior column stays in eval mode whatever
        the mode); later switches to that mode set those flags again from the flat list, which
        is what the walk would do, also to a module whose flag was changed by hand since.
        """
        mode = bool(mode)
        # (actor, critic, {mode: [(module, flag)]}); kept in __dict__ directly so that it is a
        # plain attribute, not a registered submodule or saved state (a deep copy of the policy
        # maps the modules to their copies). A module added to the actor or critic after the
        # first switch is not in the list: build a new policy rather than add modules to one.
        cache = self.__dict__.get("_mode_flags")
        if cache is None or cache[0] is not self.actor or cache[1] is not self.critic:
            cache = (self.actor, self.critic, {})
            self.__dict__["_mode_flags"] = cache
        flags = cache[2].get(mode)
        if flags is None:
            self.actor.set_training_mode(mode)
            self.critic.set_training_mode(mode)
            modules = itertools.chain(self.actor.modules(), self.critic.modules())
            cache[2][mode] = [(m, m.training) for m in modules]
        else:
            # nn.Module keeps ``training`` in the instance __dict__ (Module.__setattr__ puts a
            # plain bool there too), so this is the walk's assignment without its recursion
            for module, flag in flags:
                module.__dict__["training"] = flag
        self.training = mode


MlpPolicy = DiscreteSACPolicy


class MultiInputDiscreteSACPolicy(DiscreteSACPolicy):
    """:class:`DiscreteSACPolicy` for Dict observations (SB3's ``CombinedExtractor``)."""

    def __init__(
        self,
        observation_space: spaces.Dict,
        action_space: spaces.Discrete,
        lr_schedule: Schedule,
        net_arch: list[int] | dict[str, list[int]] | None = None,
        activation_fn: type[nn.Module] = nn.ReLU,
        features_extractor_class: type[BaseFeaturesExtractor] = CombinedExtractor,
        features_extractor_kwargs: dict[str, Any] | None = None,
        normalize_images: bool = True,
        optimizer_class: type[th.optim.Optimizer] = th.optim.Adam,
        optimizer_kwargs: dict[str, Any] | None = None,
        n_critics: int = 2,
        share_features_extractor: bool = False,
    ):
        super().__init__(
            observation_space,
            action_space,
            lr_schedule,
            net_arch,
            activation_fn,
            features_extractor_class,
            features_extractor_kwargs,
            normalize_images,
            optimizer_class,
            optimizer_kwargs,
            n_critics,
            share_features_extractor,
        )


MultiInputPolicy = MultiInputDiscreteSACPolicy

register_policy_class("DiscreteSACPolicy", DiscreteSACPolicy)
register_policy_class("MultiInputDiscreteSACPolicy", MultiInputDiscreteSACPolicy)
