"""Discrete Soft Actor-Critic (paper section 3.2, eq. (14), Tables 2-3), an SB3 OffPolicyAlgorithm.

The paper trains every agent with SAC, which maximises the entropy-regularised return of
eq. (14), pi* = argmax_pi sum_t E[r(s_t, a_t) + alpha H(pi(.|s_t))], over the five discrete
thruster actions of its Table 1. For discrete actions the expectations over the policy are
computed exactly instead of with reparameterised samples (Christodoulou 2019, arXiv
1910.07207, section 4); with pi = softmax(logits) and log pi = log_softmax(logits):

- soft state value  V(s') = sum_a' pi(a'|s') [min_i Qbar_i(s', a') - alpha log pi(a'|s')]
- critic target     y = r + gamma (1 - done) V(s')
- critic loss       J_Q = 0.5 sum_i E[(Q_i(s, a) - y)^2]
- actor loss        J_pi = E_s sum_a pi(a|s) [alpha log pi(a|s) - min_i Q_i(s, a)]
- entropy loss      J_alpha = -log(alpha) E_s[sum_a pi(a|s) log pi(a|s) + H_target]
                            = log(alpha) (E_s[H(pi(.|s))] - H_target)
  with H_target = target_entropy_ratio * log|A|.

These are :func:`soft_td_target` and :func:`discrete_sac_losses`; ``DiscreteSAC.train()`` only
samples, runs the networks once each, steps the optimizers and averages the targets.
"""

import inspect
import io
import math
import pathlib
import warnings
from typing import Any, ClassVar, NamedTuple, TypeVar

import gymnasium as gym
import numpy as np
import torch as th
from gymnasium import spaces
from stable_baselines3.common.buffers import DictReplayBuffer, NStepReplayBuffer, ReplayBuffer
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.noise import ActionNoise
from stable_baselines3.common.off_policy_algorithm import OffPolicyAlgorithm
from stable_baselines3.common.policies import BasePolicy
from stable_baselines3.common.type_aliases import (
    GymEnv,
    MaybeCallback,
    RolloutReturn,
    Schedule,
    TrainFreq,
    TrainFrequencyUnit,
)
from stable_baselines3.common.utils import get_parameters_by_name
from stable_baselines3.common.vec_env import VecEnv
from torch.nn import functional as F

from sb3_pnn.common.buffers import DictNStepReplayBuffer
from sb3_pnn.common.checks import check_step_budget, is_finite_number
from sb3_pnn.common.mirror import MirroredBatches, check_mirror_map
from sb3_pnn.dsac.policies import (
    PAPER_NET_ARCH,
    DiscreteActor,
    DiscreteCritic,
    DiscreteSACPolicy,
    MlpPolicy,
    MultiInputPolicy,
)
from sb3_pnn.safe_io.checkpoint import load_model, model_metadata, save_with_metadata
from sb3_pnn.safe_io.json_codec import decode, encode
from sb3_pnn.safe_io.limits import check_number
from sb3_pnn.safe_io.replay_buffer_io import load_buffer, save_buffer

SelfDiscreteSAC = TypeVar("SelfDiscreteSAC", bound="DiscreteSAC")


#: Default target entropy H_target as a fraction of log|A| (the paper does not give one).
DEFAULT_TARGET_ENTROPY_RATIO = 0.5
#: Samples per gradient step: the paper's (section 3.2, "256 samples ... are used to update").
PAPER_BATCH_SIZE = 256
#: Table 2's discount factor gamma.
PAPER_GAMMA = 0.99
#: Largest replay buffer a checkpoint may ask for (transitions): 100 times the paper's 1e6.
MAX_BUFFER_SIZE = 10**8


class DiscreteSACLosses(NamedTuple):
    """The three losses of one gradient step and the mean policy entropy (detached)."""

    critic_loss: th.Tensor
    actor_loss: th.Tensor
    ent_coef_loss: th.Tensor | None
    entropy: th.Tensor


def reduce_critics(q_values: tuple[th.Tensor, ...]) -> th.Tensor:
    """min_i Q_i: the clipped double-Q estimate both the target and the actor loss read
    (Christodoulou 2019). One function, so that a diagnostic can swap the reduction (e.g. the
    critics' mean of Zhou et al. 2022, ``bench/learning_trace.py --critic-mean``)."""
    return th.stack(q_values, dim=0).min(dim=0).values


def soft_td_target(
    next_logits: th.Tensor,
    next_q_targets: tuple[th.Tensor, ...],
    rewards: th.Tensor,
    dones: th.Tensor,
    discounts: th.Tensor | float,
    ent_coef: th.Tensor | float,
) -> th.Tensor:
    """
    Critic target y = r + gamma (1 - done) V(s'),
    V(s') = sum_a' pi(a'|s') [min_i Qbar_i(s', a') - alpha log pi(a'|s')].

    :param next_logits: actor logits at s', (B, n_actions)
    :param next_q_targets: target critics' Q(s', .), ``n_critics`` tensors (B, n_actions)
    :param rewards: (B, 1)
    :param dones: (B, 1), 1 where s' is terminal (SB3 already zeroes it on time-outs)
    :param discounts: gamma, or (B, 1) discounts of n-step returns
    :param ent_coef: alpha
    :return: (B, 1) targets, without gradient
    """
    next_log_probs = F.log_softmax(next_logits, dim=1)
    min_next_q = reduce_critics(next_q_targets)
    next_v = (next_log_probs.exp() * (min_next_q - ent_coef * next_log_probs)).sum(
        dim=1, keepdim=True
    )
    return rewards + (1 - dones) * discounts * next_v


def discrete_sac_losses(
    logits: th.Tensor,
    q_values: tuple[th.Tensor, ...],
    target_q_values: th.Tensor,
    actions: th.Tensor,
    ent_coef: th.Tensor | float,
    log_ent_coef: th.Tensor | None = None,
    target_entropy: float = 0.0,
    prior_log_probs: th.Tensor | None = None,
    prior_kl: float = 0.0,
    prior_kl_weights: th.Tensor | None = None,
    next_logits: th.Tensor | None = None,
    action_smoothness: float = 0.0,
) -> DiscreteSACLosses:
    """
    Critic, actor and entropy-coefficient losses of discrete SAC (see the module docstring).

    The three losses have disjoint computation graphs: the actor loss uses the critics' Q-values
    detached (the same forward pass as the critic loss, so no second critic pass), and the
    entropy loss only depends on ``log_ent_coef``.

    :param logits: actor logits at s, (B, n_actions), with gradient
    :param q_values: critics' Q(s, .), ``n_critics`` tensors (B, n_actions), with gradient
    :param target_q_values: (B, 1) targets from :func:`soft_td_target`
    :param actions: (B, 1) integer actions from the replay buffer
    :param ent_coef: alpha (detached)
    :param log_ent_coef: log(alpha) with gradient when alpha is learned, else None
    :param target_entropy: H_target in nats (only used when ``log_ent_coef`` is given)
    :param prior_log_probs: log pi_0(.|s) of a reference policy, (B, n_actions), without
        gradient; with ``prior_kl`` = beta > 0 the actor loss adds beta * KL(pi || pi_0)
    :param prior_kl_weights: (B,) weights of each sample's KL term (None: all 1); the term is
        then beta * mean_s(w(s) KL(pi(.|s) || pi_0(.|s)))
    :param next_logits: actor logits at the successor s' of each s, (B, n_actions), with
        gradient; with ``action_smoothness`` = lambda > 0 the actor loss adds
        lambda * mean_s KL(pi(.|s) || pi(.|s')), CAPS's temporal term (Mysore et al. 2021)
    """
    log_probs = F.log_softmax(logits, dim=1)
    probs = log_probs.exp()

    actions = actions.long().reshape(-1, 1)
    critic_loss = 0.5 * sum(F.mse_loss(q.gather(1, actions), target_q_values) for q in q_values)

    min_q = reduce_critics(q_values).detach()
    actor_loss = (probs * (ent_coef * log_probs - min_q)).sum(dim=1).mean()
    if prior_log_probs is not None and prior_kl > 0:
        kl = (probs * (log_probs - prior_log_probs)).sum(dim=1)
        if prior_kl_weights is not None:
            kl = kl * prior_kl_weights
        actor_loss = actor_loss + prior_kl * kl.mean()
    if next_logits is not None and action_smoothness > 0:
        temporal_kl = (probs * (log_probs - F.log_softmax(next_logits, dim=1))).sum(dim=1)
        actor_loss = actor_loss + action_smoothness * temporal_kl.mean()

    # E_s[sum_a pi log pi] = -E_s[H(pi(.|s))], no gradient to the actor
    neg_entropy = (probs * log_probs).sum(dim=1).mean().detach()
    ent_coef_loss = None
    if log_ent_coef is not None:
        ent_coef_loss = -(log_ent_coef * (neg_entropy + target_entropy)).sum()
    return DiscreteSACLosses(critic_loss, actor_loss, ent_coef_loss, -neg_entropy)  # type: ignore[arg-type]


class DiscreteSAC(OffPolicyAlgorithm):
    """
    Soft Actor-Critic for discrete action spaces (Christodoulou 2019; the paper's SAC, eq. (14)).

    Defaults are the recommended set-up's: the paper's Tables 2-3 (learning rate 3e-4 for actor
    and critics, Polyak coefficient 0.005, the paper's "target Q-network learning rate", gamma
    0.99, initial entropy coefficient 0.2 (learned), buffer 1e6, batches of 256) with one
    gradient step per environment step (section 3.2's text) instead of Table 3's 10 after every
    episode, and networks [64, 64] instead of [255, 255] (ReLU). The paper read literally is
    ``train_freq=(1, "episode"), gradient_steps=10, policy_kwargs=dict(net_arch=[255, 255])``
    (``sb3_pnn.reproduce.planning.setups.PAPER.sac_kwargs()`` gives them); docs/ablation
    measures every difference.

    Checkpoints are safe to load: :meth:`save` adds a JSON member (``sb3_pnn.json``) to SB3's
    zip and :meth:`load` rebuilds the model from it and the ``.pth`` weights only, never
    unpickling SB3's ``data`` part; replay buffers are saved as ``.npz`` archives (see
    :mod:`sb3_pnn.safe_io`). Pickles are only read with ``trust_pickle=True``.

    :param policy: The policy model to use ("MlpPolicy", "MultiInputPolicy" or a class)
    :param env: The environment to learn from (if registered in Gym, can be str)
    :param learning_rate: Adam learning rate for actor, critics and entropy coefficient;
        a float or a schedule of the remaining progress (1 to 0)
    :param buffer_size: Size of the replay buffer
    :param learning_starts: Number of steps of uniformly random actions collected before
        learning starts (default 1000: a few full batches of distinct transitions before the
        first update).
    :param batch_size: Minibatch size of each gradient step
    :param tau: The soft update coefficient of the target critics ("Polyak update"); the
        paper's 0.005 (its "target Q-network learning rate")
    :param gamma: The discount factor
    :param train_freq: Update the model every ``train_freq`` steps, or a tuple (or list) like
        ``(5, "step")`` or ``(1, "episode")``. With several environments an episodic
        frequency counts episodes finished in any of them.
    :param gradient_steps: Gradient steps after each rollout (-1: as many as env steps)
    :param replay_buffer_class: Replay buffer class (None: chosen from the observation space)
    :param replay_buffer_kwargs: Keyword arguments for the replay buffer
    :param optimize_memory_usage: Memory-efficient replay buffer variant
    :param n_steps: n-step returns when > 1 (SB3's ``NStepReplayBuffer``; for ``Dict``
        observations :class:`sb3_pnn.common.buffers.DictNStepReplayBuffer`)
    :param ent_coef: Entropy coefficient alpha: a float >= 0 (fixed), "auto" (learned,
        initial value 1) or "auto_<init>" (learned, initial value <init>); default "auto_0.2"
    :param target_entropy_ratio: H_target = target_entropy_ratio * log|A| when alpha is
        learned, in (0, 1]. Default 0.5: the paper gives only alpha's initial value;
        Christodoulou's 0.98 puts the target out of reach of a useful policy, so alpha keeps
        growing (CleanRL uses 0.89). How the value was chosen is in docs/benchmarks.md.
    :param exploration_epsilon: During training, each step's action is replaced by a uniformly
        drawn one with this probability (after ``learning_starts``; 0: off, the paper and
        Christodoulou). A softmax policy gives an action whose Q-value lies far below the best
        almost no probability, so its Q-value is never corrected by data; epsilon keeps every
        action tried (as DQN's exploration does). ``predict`` is unchanged.
    :param mirror: A left-right mirror map of a symmetric task (e.g.
        ``rov_envs.LEFT_RIGHT_MIRROR``; None: off, the paper): half of each minibatch is
        replaced by its mirror image (:mod:`sb3_pnn.common.mirror`), so that the agent also
        learns what it saw with left and right swapped. ``predict`` is unchanged.
    :param target_update_interval: Polyak-update the targets every ``target_update_interval``
        gradient steps (counted over the whole run)
    :param stats_window_size: Window size for the rollout logging
    :param tensorboard_log: The log location for tensorboard (if None, no logging)
    :param policy_kwargs: Additional arguments for the policy (see :mod:`sb3_pnn.dsac.policies`)
    :param verbose: Verbosity level: 0 none, 1 info, 2 debug
    :param seed: Seed for the pseudo random generators
    :param device: Device (cpu, cuda, ...) on which the code should be run
    :param _init_setup_model: Whether or not to build the network at the creation of the instance
    """

    policy_aliases: ClassVar[dict[str, type[BasePolicy]]] = {
        "MlpPolicy": MlpPolicy,
        "MultiInputPolicy": MultiInputPolicy,
    }
    policy: DiscreteSACPolicy
    actor: DiscreteActor
    critic: DiscreteCritic
    critic_target: DiscreteCritic

    def __init__(
        self,
        policy: str | type[DiscreteSACPolicy] = "MlpPolicy",
        env: GymEnv | str | None = None,
        learning_rate: float | Schedule = 3e-4,
        buffer_size: int = 1_000_000,
        learning_starts: int = 256,
        batch_size: int = PAPER_BATCH_SIZE,
        tau: float = 0.005,
        gamma: float = PAPER_GAMMA,
        train_freq: int | tuple[int, str] | list = 1,
        gradient_steps: int = 1,
        replay_buffer_class: type[ReplayBuffer] | None = None,
        replay_buffer_kwargs: dict[str, Any] | None = None,
        optimize_memory_usage: bool = False,
        n_steps: int = 1,
        ent_coef: str | float = "auto_0.2",
        target_entropy_ratio: float = DEFAULT_TARGET_ENTROPY_RATIO,
        exploration_epsilon: float = 0.0,
        mirror: dict[str, Any] | None = None,
        target_update_interval: int = 1,
        stats_window_size: int = 100,
        tensorboard_log: str | None = None,
        policy_kwargs: dict[str, Any] | None = None,
        verbose: int = 0,
        seed: int | None = None,
        device: th.device | str = "auto",
        _init_setup_model: bool = True,
    ):
        _parse_ent_coef(ent_coef)  # refuse a bad value before building anything
        if not (
            isinstance(target_entropy_ratio, (int, float)) and 0.0 < target_entropy_ratio <= 1.0
        ):
            raise ValueError(
                f"target_entropy_ratio must be in (0, 1], got {target_entropy_ratio!r}"
            )
        if not (is_finite_number(exploration_epsilon) and 0.0 <= exploration_epsilon < 1.0):
            raise ValueError(f"exploration_epsilon must be in [0, 1), got {exploration_epsilon!r}")
        if not (isinstance(tau, (int, float)) and 0.0 <= tau <= 1.0):
            raise ValueError(f"tau (Polyak coefficient) must be in [0, 1], got {tau!r}")
        if not (isinstance(target_update_interval, int) and target_update_interval >= 1):
            raise ValueError(
                f"target_update_interval must be an integer >= 1, got {target_update_interval!r}"
            )
        if isinstance(train_freq, list):  # e.g. [1, "episode"] from a YAML file
            train_freq = tuple(train_freq)  # type: ignore[assignment]
        n_critics = (policy_kwargs or {}).get("n_critics", 2)
        if not (isinstance(n_critics, int) and n_critics >= 1):
            raise ValueError(
                f"policy_kwargs['n_critics'] must be an integer >= 1, got {n_critics!r}"
            )

        super().__init__(
            policy,
            env,  # type: ignore[arg-type]
            learning_rate,
            buffer_size,
            learning_starts,
            batch_size,
            tau,
            gamma,
            train_freq,
            gradient_steps,
            action_noise=None,
            replay_buffer_class=replay_buffer_class,
            replay_buffer_kwargs=replay_buffer_kwargs,
            optimize_memory_usage=optimize_memory_usage,
            n_steps=n_steps,
            policy_kwargs=policy_kwargs,
            stats_window_size=stats_window_size,
            tensorboard_log=tensorboard_log,
            verbose=verbose,
            device=device,
            seed=seed,
            sde_support=False,
            supported_action_spaces=None,  # checked below, with a ValueError instead of an assert
            support_multi_env=True,
        )
        if getattr(self, "action_space", None) is not None:
            _check_action_space(self.action_space)

        self.ent_coef = ent_coef
        self.target_entropy_ratio = float(target_entropy_ratio)
        self.exploration_epsilon = float(exploration_epsilon)
        self.mirror = mirror
        self._mirrored_batches: MirroredBatches | None = None
        self.target_entropy = 0.0  # set in _setup_model from the action space
        self.target_update_interval = target_update_interval
        self.log_ent_coef: th.Tensor | None = None
        self.ent_coef_optimizer: th.optim.Optimizer | None = None

        if _init_setup_model:
            self._setup_model()

    def _setup_model(self) -> None:
        _check_action_space(self.action_space)
        with warnings.catch_warnings():
            if (
                self.n_steps > 1
                and self.replay_buffer_class is None
                and isinstance(self.observation_space, spaces.Dict)
            ):  # SB3 refuses n-step returns for Dict observations; ours samples them
                self.replay_buffer_class = DictNStepReplayBuffer
                self.replay_buffer_kwargs.update({"n_steps": self.n_steps, "gamma": self.gamma})
                # SB3 warns that a class given by name ignores n_steps; this one reads it
                warnings.filterwarnings("ignore", message=".*n_steps=.* is ignored")
            super()._setup_model()
        if not isinstance(self.policy, DiscreteSACPolicy):
            raise NotADiscreteSACPolicyError(self.policy)
        if self.mirror is not None:
            self.mirror = check_mirror_map(self.mirror, self.observation_space, self.action_space)
            self._mirrored_batches = MirroredBatches(self.mirror)
        smoothness = getattr(self.policy, "action_smoothness", 0.0)
        if smoothness > 0 and self.n_steps > 1:
            if not isinstance(self.replay_buffer, DictNStepReplayBuffer):
                raise ValueError(
                    f"action_smoothness={smoothness!r} compares pi(.|s) with pi(.|s_t+1), which "
                    f"{type(self.replay_buffer).__name__} with n_steps={self.n_steps} does not "
                    "sample: expected n_steps=1, a Dict observation (DictNStepReplayBuffer) or "
                    "action_smoothness=0"
                )
        portable_kwargs = getattr(self.policy, "portable_policy_kwargs", None)
        if callable(portable_kwargs):
            self.policy_kwargs = portable_kwargs()
        self._create_aliases()
        # Running statistics of batch norm layers are copied to the target (SB3 GH issue #996)
        self.batch_norm_stats = get_parameters_by_name(self.critic, ["running_"])
        self.batch_norm_stats_target = get_parameters_by_name(self.critic_target, ["running_"])

        self.target_entropy = self.target_entropy_ratio * math.log(int(self.action_space.n))
        learn_ent_coef, init_value = _parse_ent_coef(self.ent_coef)
        if learn_ent_coef:
            # Optimise log(alpha) (as SB3's SAC), which keeps alpha positive
            self.log_ent_coef = th.log(th.ones(1, device=self.device) * init_value).requires_grad_(
                True
            )
            self.ent_coef_optimizer = th.optim.Adam([self.log_ent_coef], lr=self.lr_schedule(1))
        else:
            self.ent_coef_tensor = th.tensor(init_value, device=self.device)

    def _create_aliases(self) -> None:
        self.actor = self.policy.actor
        self.critic = self.policy.critic
        self.critic_target = self.policy.critic_target

    def train(self, gradient_steps: int, batch_size: int = 64) -> None:
        # Switch to train mode (this affects batch norm / dropout)
        self.policy.set_training_mode(True)
        optimizers = [self.actor.optimizer, self.critic.optimizer]
        if self.ent_coef_optimizer is not None:
            optimizers += [self.ent_coef_optimizer]
        self._update_learning_rate(optimizers)

        critic_params, target_params = self._polyak_params()
        prior_kl = float(getattr(self.policy, "prior_kl", 0.0))
        off_path_kl = float(getattr(self.policy, "off_path_kl", 0.0))
        policy: Any = self.policy
        copy_terms = [  # (weight, the term): the prior KL over made-up copies of each batch
            (weight, term)
            for weight, term in (  # see sb3_pnn.progressive's off_path and obstacle_copies
                (off_path_kl, lambda obs: policy.off_path_kl_term(obs, True)),
                (
                    float(getattr(policy, "clear_kl", 0.0)),
                    lambda obs: policy.off_path_kl_term(obs, False),
                ),
                (
                    float(getattr(policy, "obstacle_kl", 0.0)),
                    lambda obs: policy.obstacle_kl_term(obs),
                ),
            )
            if weight > 0
        ]
        smoothness = float(getattr(self.policy, "action_smoothness", 0.0))
        if smoothness > 0 and isinstance(self.replay_buffer, DictNStepReplayBuffer):
            self.replay_buffer.step_successors = True  # its s' is s_t+n; s_t+1 comes beside it
        # Detached tensors, turned into floats once after the loop (no sync per step)
        ent_coef_losses, ent_coefs, entropies = [], [], []
        actor_losses, critic_losses = [], []

        for _ in range(gradient_steps):
            replay_data = self.replay_buffer.sample(batch_size, env=self._vec_normalize_env)  # type: ignore[union-attr]
            if self._mirrored_batches is not None:
                replay_data = self._mirrored_batches(replay_data)
            # For n-step replay, discount factor is gamma**n_steps (when no early termination)
            discounts = replay_data.discounts if replay_data.discounts is not None else self.gamma

            if self.log_ent_coef is not None:
                ent_coef = th.exp(self.log_ent_coef.detach())
            else:
                ent_coef = self.ent_coef_tensor

            # the successor's logits with gradient only when the smoothness term reads them
            # (the TD target then uses the same values, detached)
            successors = getattr(replay_data, "step_next_observations", None)
            step_logits = None  # the actor at s_t+1, for the smoothness term
            if smoothness > 0:
                step_logits = self.actor(
                    replay_data.next_observations if successors is None else successors
                )
            with th.no_grad():
                target_q_values = soft_td_target(
                    step_logits.detach()
                    if step_logits is not None and successors is None
                    else self.actor(replay_data.next_observations),
                    self.critic_target(replay_data.next_observations),
                    replay_data.rewards,
                    replay_data.dones,
                    discounts,
                    ent_coef,
                )

            logits, prior_log_probs, kl_weights = self._actor_pass(
                replay_data.observations, prior_kl
            )
            losses = discrete_sac_losses(
                logits=logits,
                q_values=self.critic(replay_data.observations),
                target_q_values=target_q_values,
                actions=replay_data.actions,
                ent_coef=ent_coef,
                log_ent_coef=self.log_ent_coef,
                target_entropy=self.target_entropy,
                prior_log_probs=prior_log_probs,
                prior_kl=prior_kl,
                prior_kl_weights=kl_weights,
                next_logits=step_logits,
                action_smoothness=smoothness,
            )
            for weight, term in copy_terms:  # the prior KL term over copies of the batch too
                kl = term(replay_data.observations)
                losses = losses._replace(actor_loss=losses.actor_loss + weight * kl)

            # Optimize the entropy coefficient (alpha, the "temperature")
            if losses.ent_coef_loss is not None and self.ent_coef_optimizer is not None:
                self.ent_coef_optimizer.zero_grad()
                losses.ent_coef_loss.backward()
                self.ent_coef_optimizer.step()
                ent_coef_losses.append(losses.ent_coef_loss.detach())

            # Optimize the critics
            self.critic.optimizer.zero_grad()
            losses.critic_loss.backward()
            self.critic.optimizer.step()

            # Optimize the actor
            self.actor.optimizer.zero_grad()
            losses.actor_loss.backward()
            self.actor.optimizer.step()

            # Polyak averaging of the targets: theta_bar <- (1 - tau) theta_bar + tau theta
            self._n_updates += 1
            if self._n_updates % self.target_update_interval == 0:
                self._polyak_update(critic_params, target_params)

            ent_coefs.append(ent_coef.reshape(()))
            entropies.append(losses.entropy)
            critic_losses.append(losses.critic_loss.detach())
            actor_losses.append(losses.actor_loss.detach())

        self.logger.record("train/n_updates", self._n_updates, exclude="tensorboard")
        if gradient_steps > 0:
            self.logger.record("train/ent_coef", _mean(ent_coefs))
            self.logger.record("train/actor_loss", _mean(actor_losses))
            self.logger.record("train/critic_loss", _mean(critic_losses))
            self.logger.record("train/entropy", _mean(entropies))
            if len(ent_coef_losses) > 0:
                self.logger.record("train/ent_coef_loss", _mean(ent_coef_losses))
        self._record_policy_logs()

    def _actor_pass(
        self, observations: Any, prior_kl: float
    ) -> tuple[th.Tensor, th.Tensor | None, th.Tensor | None]:
        """The actor's logits and, when the prior KL term is on (``prior_kl`` > 0, progressive
        policies), the log-probabilities of the frozen priors' own policy from the same pass
        and the term's per-sample weights (None: every sample weighs 1)."""
        if prior_kl > 0:
            actor = self.actor
            logits, prior_log_probs = actor.logits_and_prior_log_probs(observations)  # type: ignore[attr-defined]
            return logits, prior_log_probs, actor.prior_kl_weights(observations)  # type: ignore[attr-defined]
        return self.actor(observations), None, None

    def _record_policy_logs(self) -> None:
        """The policy's own training figures (e.g. SPNN's gate), when it reports any."""
        extra_logs = getattr(self.policy, "extra_logs", None)
        if callable(extra_logs):
            for name, value in extra_logs().items():
                self.logger.record(f"train/{name}", value)

    def _polyak_params(self) -> tuple[list[th.Tensor], list[th.Tensor]]:
        """The critic's and the target's parameters, in the same order, for the Polyak update:
        listed once per critic / target pair (train() is called every few steps, and walking
        the modules for them cost as much as a small update's arithmetic)."""
        cached = self.__dict__.get("_polyak_cache")
        if cached is None or cached[0] is not self.critic or cached[1] is not self.critic_target:
            params = list(self.critic.parameters())
            target_params = list(self.critic_target.parameters())
            cached = (self.critic, self.critic_target, params, target_params)
            self.__dict__["_polyak_cache"] = cached
        return cached[2], cached[3]

    def _polyak_update(self, params: list[th.Tensor], target_params: list[th.Tensor]) -> None:
        """
        theta_bar <- (1 - tau) theta_bar + tau theta for every critic parameter: the arithmetic
        of SB3's ``polyak_update`` in two multi-tensor operations instead of a Python loop.
        """
        with th.no_grad():
            th._foreach_mul_(target_params, 1.0 - self.tau)
            th._foreach_add_(target_params, params, alpha=self.tau)
            for stat, target_stat in zip(self.batch_norm_stats, self.batch_norm_stats_target):
                target_stat.copy_(stat)

    def _sample_action(
        self, learning_starts: int, action_noise: ActionNoise | None = None, n_envs: int = 1
    ) -> tuple[np.ndarray, np.ndarray]:
        """SB3's exploration action; with ``exploration_epsilon`` > 0, after the warm-up, each
        environment's action is replaced by a uniform draw with that probability (numpy's
        global generator, which SB3 seeds; none is drawn when epsilon is 0)."""
        action, buffer_action = super()._sample_action(learning_starts, action_noise, n_envs)
        if self.exploration_epsilon > 0 and self.num_timesteps >= learning_starts:
            explore = np.random.random(n_envs) < self.exploration_epsilon  # noqa: NPY002
            uniform = np.random.randint(int(self.action_space.n), size=n_envs)  # noqa: NPY002
            action = np.where(explore, uniform, np.asarray(action).reshape(n_envs))
            buffer_action = action
        return action, buffer_action

    def collect_rollouts(
        self,
        env: VecEnv,
        callback: BaseCallback,
        train_freq: TrainFreq,
        replay_buffer: ReplayBuffer,
        action_noise: ActionNoise | None = None,
        learning_starts: int = 0,
        log_interval: int | None = None,
    ) -> RolloutReturn:
        """
        SB3's ``collect_rollouts``; also with several environments and an episodic ``train_freq``
        (which SB3 refuses): it then collects step by step until ``train_freq.frequency``
        episodes have ended, in any of the environments.
        """
        if env.num_envs == 1 or train_freq.unit == TrainFrequencyUnit.STEP:
            return super().collect_rollouts(
                env,
                callback,
                train_freq,
                replay_buffer,
                action_noise,
                learning_starts,
                log_interval,
            )
        one_step = TrainFreq(1, TrainFrequencyUnit.STEP)
        n_steps, n_episodes = 0, 0
        while n_episodes < train_freq.frequency:
            rollout = super().collect_rollouts(
                env, callback, one_step, replay_buffer, action_noise, learning_starts, log_interval
            )
            n_steps += rollout.episode_timesteps
            n_episodes += rollout.n_episodes
            if not rollout.continue_training:
                return RolloutReturn(n_steps, n_episodes, continue_training=False)
        return RolloutReturn(n_steps, n_episodes, continue_training=True)

    def learn(
        self: SelfDiscreteSAC,
        total_timesteps: int,
        callback: MaybeCallback = None,
        log_interval: int = 4,
        tb_log_name: str = "DiscreteSAC",
        reset_num_timesteps: bool = True,
        progress_bar: bool = False,
    ) -> SelfDiscreteSAC:
        check_step_budget(total_timesteps, "total_timesteps")
        return super().learn(
            total_timesteps=total_timesteps,
            callback=callback,
            log_interval=log_interval,
            tb_log_name=tb_log_name,
            reset_num_timesteps=reset_num_timesteps,
            progress_bar=progress_bar,
        )

    # --- checkpoints without pickle (project rule: loading never runs code from a file) -----
    def save(
        self,
        path: str | pathlib.Path | io.BufferedIOBase,
        exclude: Any = None,
        include: Any = None,
    ) -> None:
        """
        Save as SB3 does (``data``, ``policy.pth``, optimizers, ``pytorch_variables.pth``) plus
        the JSON member ``sb3_pnn.json`` from which :meth:`load` rebuilds the model without
        unpickling (:mod:`sb3_pnn.safe_io.checkpoint`). Refuses, before writing, a model whose
        policy class or policy kwargs cannot be named safely (register them with
        ``sb3_pnn.safe_io.register_policy_class`` / ``register_safe_class``).
        """
        meta = model_metadata(self)
        sb3_zip = io.BytesIO()
        super().save(sb3_zip, exclude=exclude, include=include)
        save_with_metadata(path, sb3_zip, meta)

    @classmethod
    def load(  # type: ignore[override]
        cls: type[SelfDiscreteSAC],
        path: str | pathlib.Path | io.BufferedIOBase,
        env: GymEnv | None = None,
        device: th.device | str = "auto",
        custom_objects: dict[str, Any] | None = None,
        print_system_info: bool = False,
        force_reset: bool = True,
        trust_pickle: bool = False,
        **kwargs: Any,
    ) -> SelfDiscreteSAC:
        """
        Load a model saved by :meth:`save`, without unpickling anything from the file.

        Reads only the ``sb3_pnn.json`` member and the ``.pth`` weights
        (``torch.load(weights_only=True)``), never SB3's pickled ``data`` part; the model is
        rebuilt through the constructor. A zip without the JSON member (an SB3 checkpoint, or
        one saved before safe checkpoints) is refused with
        :class:`~sb3_pnn.safe_io.checkpoint.UnsafeCheckpointError` (a ``ValueError``).

        :param path: the ``.zip`` file (a path without suffix also finds ``<path>.zip``) or a
            binary file object
        :param env: environment to run on; its spaces must equal the saved ones
        :param device: device of the rebuilt model
        :param custom_objects: replacements for saved entries, as in SB3: ``learning_rate``
            (needed when the model was trained with a custom schedule, which JSON cannot hold),
            any other constructor argument, ``observation_space``/``action_space``;
            ``lr_schedule``, ``exploration_schedule`` and ``clip_range`` (passed by rl_zoo3)
            are ignored, since the model recomputes them
        :param print_system_info: print the current system info
        :param force_reset: accepted for SB3 compatibility; the rebuilt model never keeps the
            last observation, so ``learn`` always starts by resetting the environment
        :param trust_pickle: UNSAFE. Fall back to SB3's ``load``, which unpickles the
            ``data`` part and can run arbitrary code from the file; only for files you trust
            (e.g. to convert an old checkpoint: load once, then ``save`` again)
        :param kwargs: overrides of constructor arguments (e.g. ``buffer_size=1``); other
            names are set as attributes before ``_setup_model``, as SB3 does
        """
        if trust_pickle:
            try:
                return super().load(  # type: ignore[return-value]
                    path,
                    env=env,
                    device=device,
                    custom_objects=custom_objects,
                    print_system_info=print_system_info,
                    force_reset=force_reset,
                    **kwargs,
                )
            except NotADiscreteSACPolicyError as error:
                loader = f"stable_baselines3.{error.algo}.load" if error.algo else "its own class"
                name = repr(str(path)) if isinstance(path, (str, pathlib.Path)) else "the file"
                raise ValueError(
                    f"{name} is not a DiscreteSAC checkpoint: its policy is {error.policy_name}; "
                    f"load it with {loader}, or use it as a prior column "
                    "(policy_kwargs=dict(priors=[path]), read without unpickling)"
                ) from None
        return load_model(  # type: ignore[return-value]
            cls, path, env, device, custom_objects, print_system_info, kwargs
        )

    def save_replay_buffer(self, path: str | pathlib.Path | io.BufferedIOBase) -> None:
        """Save the replay buffer without pickle: an ``.npz`` archive of its arrays plus JSON
        metadata (:mod:`sb3_pnn.safe_io.replay_buffer_io`); SB3 file naming (``.pkl`` added
        to a path without suffix)."""
        if self.replay_buffer is None:
            raise ValueError("the replay buffer is not defined (model not set up)")
        save_buffer(self.replay_buffer, path)

    def load_replay_buffer(
        self,
        path: str | pathlib.Path | io.BufferedIOBase,
        truncate_last_traj: bool = True,
        trust_pickle: bool = False,
    ) -> None:
        """
        Load a replay buffer written by :meth:`save_replay_buffer` with
        ``np.load(allow_pickle=False)``. A pickle (SB3's format) is refused unless
        ``trust_pickle=True`` (UNSAFE: unpickling can run arbitrary code from the file).
        """
        if trust_pickle:
            super().load_replay_buffer(path, truncate_last_traj)
            return
        buffer = load_buffer(path, device=self.device)
        expected = self.observation_space
        if expected is not None and buffer.observation_space != expected:
            raise ValueError(
                f"replay buffer {path!r} holds observations of {buffer.observation_space}, "
                f"the model expects {expected}"
            )
        self.replay_buffer = buffer

    #: The constructor arguments a safe checkpoint stores (``learning_rate`` is stored apart,
    #: as a schedule): :mod:`sb3_pnn.safe_io.checkpoint` rebuilds the model from them.
    CHECKPOINT_KEYS: ClassVar[tuple[str, ...]] = (
        "buffer_size", "learning_starts", "batch_size", "tau", "gamma", "train_freq",
        "gradient_steps", "replay_buffer_class", "replay_buffer_kwargs",
        "optimize_memory_usage", "n_steps", "ent_coef", "target_entropy_ratio",
        "exploration_epsilon", "mirror", "target_update_interval", "stats_window_size",
        "tensorboard_log",
        "policy_kwargs", "verbose", "seed",
    )  # fmt: skip

    def checkpoint_hyperparameters(self) -> dict[str, Any]:
        """The values of :attr:`CHECKPOINT_KEYS` for this model. A replay buffer class that
        ``_setup_model`` picks by itself is stored as None (and the keyword arguments it adds
        are left out), so that a checkpoint does not name a class it need not."""
        buffer_kwargs = dict(self.replay_buffer_kwargs)
        buffer_class = self.replay_buffer_class
        if isinstance(self.observation_space, spaces.Dict):
            automatic = buffer_class is (
                DictNStepReplayBuffer if self.n_steps > 1 else DictReplayBuffer
            )
        else:
            automatic = buffer_class is (NStepReplayBuffer if self.n_steps > 1 else ReplayBuffer)
        if automatic:
            buffer_class = None
            if self.n_steps > 1:  # added by _setup_model, added again on load
                buffer_kwargs.pop("n_steps", None)
                buffer_kwargs.pop("gamma", None)
        train_freq = self.train_freq
        if isinstance(train_freq, TrainFreq):
            train_freq = (train_freq.frequency, train_freq.unit.value)
        values = {
            "buffer_size": self.buffer_size,
            "learning_starts": self.learning_starts,
            "batch_size": self.batch_size,
            "tau": self.tau,
            "gamma": self.gamma,
            "train_freq": train_freq,
            "gradient_steps": self.gradient_steps,
            "replay_buffer_class": buffer_class,
            "replay_buffer_kwargs": buffer_kwargs,
            "optimize_memory_usage": self.optimize_memory_usage,
            "n_steps": self.n_steps,
            "ent_coef": self.ent_coef,
            "target_entropy_ratio": self.target_entropy_ratio,
            "exploration_epsilon": self.exploration_epsilon,
            "mirror": self.mirror,
            "target_update_interval": self.target_update_interval,
            "stats_window_size": self._stats_window_size,
            "tensorboard_log": self.tensorboard_log,
            # the architecture named even when it was the default, so that a later default
            # cannot change what a checkpoint rebuilds
            "policy_kwargs": {"net_arch": self.policy.net_arch, **self.policy_kwargs},
            "verbose": self.verbose,
            "seed": self.seed,
        }
        assert tuple(values) == self.CHECKPOINT_KEYS
        return values

    @classmethod
    def check_checkpoint_hyperparameters(cls, hyper: dict[str, Any], where: str) -> None:
        """Refuse stored values of :attr:`CHECKPOINT_KEYS` that are of the wrong type or out of
        any plausible range, before a model (and its replay buffer) is built from them: a
        checkpoint may come from anyone."""
        for key, low, high in (
            ("buffer_size", 1, MAX_BUFFER_SIZE),
            ("learning_starts", 0, 10**12),
            ("batch_size", 1, 10**6),
            ("gradient_steps", -1, 10**6),
            ("n_steps", 1, 10**4),
            ("target_update_interval", 1, 10**9),
            ("stats_window_size", 1, 10**6),
            ("verbose", 0, 2),
        ):
            check_number(hyper[key], f"{where} {key}", low, high, integer=True)
        for key in ("tau", "gamma"):
            check_number(hyper[key], f"{where} {key}", 0.0, 1.0)
        check_number(hyper["target_entropy_ratio"], f"{where} target_entropy_ratio", 1e-9, 1.0)
        check_number(
            hyper["exploration_epsilon"],
            f"{where} exploration_epsilon",
            0.0,
            math.nextafter(1.0, 0.0),  # [0, 1)
        )
        if hyper["mirror"] is not None and not isinstance(hyper["mirror"], dict):
            raise ValueError(
                f"{where} mirror={hyper['mirror']!r:.100} is not allowed: expected a dict or null"
            )  # its content is checked against the spaces when the model is built
        if hyper["seed"] is not None:
            check_number(hyper["seed"], f"{where} seed", -(2**63), 2**64, integer=True)
        if not isinstance(hyper["optimize_memory_usage"], bool):
            raise ValueError(f"{where} optimize_memory_usage={hyper['optimize_memory_usage']!r}")
        if hyper["tensorboard_log"] is not None and not isinstance(hyper["tensorboard_log"], str):
            raise ValueError(f"{where} tensorboard_log={hyper['tensorboard_log']!r:.100}")
        freq = hyper["train_freq"]
        if isinstance(freq, (list, tuple)) and len(freq) == 2 and freq[1] in ("step", "episode"):
            freq = freq[0]
        check_number(freq, f"{where} train_freq", 1, 10**9, integer=True)
        try:
            _parse_ent_coef(hyper["ent_coef"])
        except (ValueError, TypeError) as error:
            raise ValueError(f"{where} ent_coef: {error}") from None
        buffer_kwargs = hyper["replay_buffer_kwargs"]
        if buffer_kwargs is not None and not isinstance(buffer_kwargs, dict):
            raise ValueError(f"{where} replay_buffer_kwargs={buffer_kwargs!r:.100}")
        buffer_class = hyper["replay_buffer_class"] or ReplayBuffer
        allowed = set(inspect.signature(buffer_class.__init__).parameters) | {"n_steps", "gamma"}
        unknown = sorted(set(buffer_kwargs or {}) - allowed)
        if unknown:
            raise ValueError(
                f"{where} replay_buffer_kwargs names {unknown}, which {buffer_class.__name__} "
                "does not take"
            )

    @classmethod
    def upgrade_checkpoint(cls, meta: dict[str, Any]) -> dict[str, Any]:
        """A checkpoint of an earlier format version as the current one. Version 1 named the
        network architecture only when it was not the default, then [255, 255]. Checkpoints
        written before ``exploration_epsilon`` or ``mirror`` existed trained without them (0,
        None)."""
        hyper = meta.get("hyperparameters")
        if isinstance(hyper, dict):
            hyper.setdefault("exploration_epsilon", 0.0)
            hyper.setdefault("mirror", None)
        if meta.get("version") == 1:
            hyper = meta.get("hyperparameters")
            kwargs = hyper.get("policy_kwargs") if isinstance(hyper, dict) else None
            if isinstance(kwargs, dict) and "net_arch" not in kwargs:
                kwargs["net_arch"] = list(PAPER_NET_ARCH)
        return meta

    def checkpoint_extras(self) -> dict[str, Any]:
        """Entries of a safe checkpoint besides the constructor's: the target entropy (for the
        reader) and the environment the model was trained on (:attr:`trained_env`)."""
        extras: dict[str, Any] = {"target_entropy": float(self.target_entropy)}
        trained_env = self.trained_env
        if trained_env is not None:
            extras["env"] = {
                "id": trained_env["id"],
                "kwargs": encode(trained_env["kwargs"], "env kwargs"),
            }
        return extras

    def restore_checkpoint_extras(self, meta: dict[str, Any], where: str) -> None:
        """Read back what :meth:`checkpoint_extras` stored (``env``, when there)."""
        record = meta.get("env")
        if record is None:
            return
        if not (
            isinstance(record, dict)
            and isinstance(record.get("id"), str)
            and isinstance(record.get("kwargs"), dict)
        ):
            raise ValueError(f"{where}: malformed env entry {record!r:.200}")
        kwargs = decode(record["kwargs"], f"{where} env kwargs")
        self._trained_env = {"id": record["id"], "kwargs": kwargs}

    @property
    def trained_env(self) -> dict[str, Any] | None:
        """``{"id": env id, "kwargs": keyword arguments}`` of the Gymnasium env the model was
        trained on (the one given to the constructor, or the one a loaded checkpoint names),
        without ``render_mode``; None when unknown (an env made without ``gymnasium.make``).
        Evaluation and ``enjoy`` use these keywords unless told otherwise."""
        if self.env is not None:
            try:
                spec = self.env.get_attr("spec", [0])[0]
            except (AttributeError, IndexError):
                spec = None
            if spec is not None and getattr(spec, "id", None):
                registered = gym.registry[spec.id].kwargs if spec.id in gym.registry else {}
                kwargs = {
                    k: v
                    for k, v in (spec.kwargs or {}).items()
                    if k != "render_mode" and registered.get(k, object()) != v
                }
                return {"id": spec.id, "kwargs": kwargs}
        return getattr(self, "_trained_env", None)

    def _excluded_save_params(self) -> list[str]:
        return [
            *super()._excluded_save_params(),
            "actor",
            "critic",
            "critic_target",
            "batch_norm_stats",
            "batch_norm_stats_target",
            "_polyak_cache",
        ]

    def _get_torch_save_params(self) -> tuple[list[str], list[str]]:
        state_dicts = ["policy", "actor.optimizer", "critic.optimizer"]
        if self.ent_coef_optimizer is not None:
            saved_pytorch_variables = ["log_ent_coef"]
            state_dicts.append("ent_coef_optimizer")
        else:
            saved_pytorch_variables = ["ent_coef_tensor"]
        return state_dicts, saved_pytorch_variables


class NotADiscreteSACPolicyError(TypeError):
    """The policy of a DiscreteSAC is not a :class:`DiscreteSACPolicy` (no actor and critics);
    e.g. an SB3 DQN checkpoint loaded with ``DiscreteSAC.load(..., trust_pickle=True)``."""

    def __init__(self, policy: Any) -> None:
        cls = type(policy)
        self.policy_name = f"{cls.__module__}.{cls.__qualname__}"
        parts = cls.__module__.split(".")  # stable_baselines3.dqn.policies -> DQN
        sb3 = parts[0] == "stable_baselines3" and len(parts) > 2
        self.algo = parts[1].upper() if sb3 else None
        super().__init__(
            f"DiscreteSAC needs a DiscreteSACPolicy (actor and critics), got {self.policy_name}"
        )


def _parse_ent_coef(ent_coef: str | float) -> tuple[bool, float]:
    """(learned?, initial value) from a float >= 0 (fixed), "auto" or "auto_<positive float>"."""
    expected = 'a float >= 0, "auto" or "auto_<positive float>" (e.g. "auto_0.2")'
    if isinstance(ent_coef, str):
        if ent_coef == "auto":
            return True, 1.0
        if ent_coef.startswith("auto_"):
            try:
                init_value = float(ent_coef[len("auto_") :])
            except ValueError:
                raise ValueError(f"ent_coef must be {expected}, got {ent_coef!r}") from None
            if init_value > 0 and math.isfinite(init_value):
                return True, init_value
        raise ValueError(f"ent_coef must be {expected}, got {ent_coef!r}")
    if isinstance(ent_coef, (int, float, np.floating)) and not isinstance(ent_coef, bool):
        if ent_coef >= 0 and math.isfinite(ent_coef):
            return False, float(ent_coef)
    raise ValueError(f"ent_coef must be {expected}, got {ent_coef!r}")


def _check_action_space(action_space: spaces.Space) -> None:
    if not isinstance(action_space, spaces.Discrete):
        raise ValueError(
            f"DiscreteSAC only supports gymnasium.spaces.Discrete action spaces, got {action_space}"
        )


def _mean(values: list[th.Tensor]) -> float:
    return th.stack(values).mean().item()
