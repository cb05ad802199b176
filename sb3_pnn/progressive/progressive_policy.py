"""Progressive policy (PNN, paper section 3.1-3.2, eq. 13) for :class:`sb3_pnn.DiscreteSAC`.

``DiscreteSAC(ProgressivePolicy, env, policy_kwargs=dict(priors=["pf.zip", ...]))`` builds, in the
actor and in every critic Q-network, one frozen column per prior checkpoint and a new trainable
column k that reads them through lateral adapters (:class:`.columns.ProgressiveNet`).

* The actor's prior columns are the priors' actors (for a DQN prior, its Q-network: see
  :mod:`.prior_loading`); critic Q-network i's prior column from a prior is that prior's critic
  ``i mod n`` (n = the prior's number of Q-networks; 1 for DQN).
* Every prior column gets exactly the observation its checkpoint was trained on
  (:func:`.obs_spec.match_prior_obs`); the new column gets the whole new observation through the
  usual SB3 features extractor.
* Prior weights are buffers of :class:`.columns.FrozenColumn`: not parameters, so they are in no
  optimizer and untouched by the Polyak update; they are saved in the policy's state dict.
* Self-contained models: after construction, ``portable_policy_kwargs()`` replaces
  ``priors=[paths]`` by ``prior_specs=[...]`` (JSON-able :class:`.prior_loading.PriorSpec` dicts),
  which DiscreteSAC saves; ``DiscreteSAC.load`` rebuilds the columns from the specs and then loads
  the prior weights from the saved state dict, so the prior files are no longer needed.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from typing import Any

import torch as th
from gymnasium import spaces
from stable_baselines3.common.policies import BaseModel, BasePolicy
from stable_baselines3.common.preprocessing import preprocess_obs
from stable_baselines3.common.torch_layers import (
    BaseFeaturesExtractor,
    CombinedExtractor,
    FlattenExtractor,
)
from stable_baselines3.common.type_aliases import PyTorchObs, Schedule
from torch import nn
from torch.nn import functional as F

from sb3_pnn.common.checks import is_finite_number
from sb3_pnn.dsac.policies import DiscreteSACPolicy, actions_from_logits
from sb3_pnn.progressive.columns import FrozenColumn, ProgressiveNet, activation_name
from sb3_pnn.progressive.gates import DistanceGate, checked_corridor
from sb3_pnn.progressive.obs_spec import Feed, match_prior_obs, obs_spec_from_space
from sb3_pnn.progressive.obstacle_copies import obstacle_copies
from sb3_pnn.progressive.off_path import PATH_KEY, off_path_copies
from sb3_pnn.progressive.prior_loading import Layers, PriorCheckpoint, PriorSpec, load_prior
from sb3_pnn.progressive.weight_copy import copy_layers, input_columns
from sb3_pnn.safe_io.policy_registry import register_policy_class

#: The sonar observation key and range (m) that obstacle distances are read from (rov_envs'
#: own; sonar sectors are distance / range): the KL term's clearance here, SPNN's gate too.
SONAR_KEY, SONAR_RANGE = "sonar", 25.0


def _has_part(
    observation_space: spaces.Space, key: str, shape: tuple[int, ...] | None = None
) -> bool:
    """Whether a Dict observation space has the part ``key`` (of ``shape`` where given)."""
    if not isinstance(observation_space, spaces.Dict) or key not in observation_space.spaces:
        return False
    return shape is None or observation_space.spaces[key].shape == shape


def _checked_clearance(clearance: Any, observation_space: spaces.Space) -> float | None:
    """``prior_kl_clearance`` as a float (None stays None); refuses a bad distance or an
    observation without the sonar it reads."""
    if clearance is None:
        return None
    if not is_finite_number(clearance) or clearance <= 0:
        raise ValueError(
            f"prior_kl_clearance must be a distance > 0 (m) or None, got {clearance!r}"
        )
    if not _has_part(observation_space, SONAR_KEY):
        raise ValueError(
            f"prior_kl_clearance={clearance!r} reads the nearest obstacle from a {SONAR_KEY!r} "
            f"observation key, which this observation space lacks: {observation_space}"
        )
    return float(clearance)


def _checked_near_reference(
    prior: Any, corridor: Any, policy: ProgressivePolicy, observation_space: spaces.Space
) -> tuple[int | None, float | None]:
    """``near_reference_prior`` and ``near_reference_corridor`` checked against the policy's
    priors, ``reference_prior`` and ``prior_kl_clearance``; a ValueError names a bad value."""
    if prior is None:
        if corridor is not None:
            raise ValueError(
                f"near_reference_corridor={corridor!r} needs near_reference_prior (it bounds "
                "where the near samples' reference applies)"
            )
        return None, None
    n = len(policy.prior_specs)
    if isinstance(prior, bool) or not isinstance(prior, int) or not 0 <= prior < n:
        raise ValueError(
            f"near_reference_prior={prior!r} is not allowed: expected None or a prior index in "
            f"[0, {n - 1}]"
        )
    if policy.reference_prior is None or prior == policy.reference_prior:
        raise ValueError(
            f"near_reference_prior={prior!r} needs a reference_prior other than it, got "
            f"reference_prior={policy.reference_prior!r}"
        )
    if policy.prior_kl_clearance is None:
        raise ValueError(
            f"near_reference_prior={prior!r} needs prior_kl_clearance, the distance (m) that "
            "tells near samples from far ones"
        )
    corridor = checked_corridor(corridor, "near_reference_corridor")
    if corridor is not None and not _has_part(observation_space, PATH_KEY):
        raise ValueError(
            f"near_reference_corridor={corridor!r} reads the observation's {PATH_KEY!r} part "
            f"[a_c / pi, g / d_L], which this observation space lacks: {observation_space}"
        )
    return prior, corridor


def _lateral_weights(
    gate: nn.Module | None, sigma: float, pre: Any, features: th.Tensor
) -> tuple[th.Tensor | None, th.Tensor | None]:
    """(c_j(s) = sigma * g_j(s), g(s)) for the SPNN; (None, None) = all laterals weigh 1 (PNN)."""
    if gate is None:
        return None, None
    g = gate(pre, features)
    return sigma * g, g


class ProgressiveActor(BasePolicy):
    """Softmax policy whose logits are the output of a :class:`ProgressiveNet` (eq. 13/15)."""

    action_space: spaces.Discrete

    def __init__(
        self,
        observation_space: spaces.Space,
        action_space: spaces.Discrete,
        features_extractor: BaseFeaturesExtractor,
        features_dim: int,
        net: ProgressiveNet,
        feeds: Sequence[Feed],
        gate: nn.Module | None = None,
        sigma: float = 1.0,
        own_weight: float = 1.0,
        normalize_images: bool = True,
        kl_gate: DistanceGate | None = None,
        reference_prior: int | None = None,
        near_reference_prior: int | None = None,
    ):
        super().__init__(
            observation_space,
            action_space,
            features_extractor=features_extractor,
            normalize_images=normalize_images,
        )
        self.kl_gate = kl_gate
        self.reference_prior = reference_prior
        self.near_reference_prior = near_reference_prior
        self.features_dim = features_dim
        self.net = net
        self.feeds = list(feeds)
        self.gate = gate
        self.sigma = sigma
        self.own_weight = own_weight
        # Column-lead counts since the last extra_logs(): [rollout steps, training batches];
        # the gate weights of each pass wait in _pending_leads until lead_counts is read
        self._lead_counts = th.zeros(2, len(feeds))
        self._pending_leads: tuple[list[th.Tensor], list[th.Tensor]] = ([], [])

    def forward(self, obs: PyTorchObs) -> th.Tensor:
        """Logits (B, n_actions) of column k."""
        pre = preprocess_obs(obs, self.observation_space, normalize_images=self.normalize_images)
        features = self.features_extractor(pre)
        hidden = self.net.prior_hidden([feed(pre) for feed in self.feeds])
        weights, g = _lateral_weights(self.gate, self.sigma, pre, features)
        if g is not None:
            self._count_leads(g)
        return self.net(features, hidden, weights, self.own_weight)

    def logits_and_prior_log_probs(
        self, obs: PyTorchObs, count_leads: bool = True
    ) -> tuple[th.Tensor, th.Tensor]:
        """The logits of column k (with gradient) and, without gradient, the log-probabilities
        of the priors' own policy pi_0: for the SPNN the gate-selected prior's (a soft or learned
        gate mixes the priors' log-probabilities by its weights, then renormalises); for a PNN
        the prior's (the mean over several, or the ``reference_prior``'s alone; with a
        ``near_reference_prior``, that prior's on the samples ``kl_gate`` finds near an
        obstacle). One pass: the priors' hidden activations feed both the laterals and pi_0.
        ``count_leads=False`` leaves the gate's lead counts alone (states made up for a loss
        term, not replayed)."""
        pre = preprocess_obs(obs, self.observation_space, normalize_images=self.normalize_images)
        features = self.features_extractor(pre)
        inputs = [feed(pre) for feed in self.feeds]
        hidden = self.net.prior_hidden(inputs)
        weights, g = _lateral_weights(self.gate, self.sigma, pre, features)
        if g is not None and count_leads:
            self._count_leads(g)
        logits = self.net(features, hidden, weights, self.own_weight)
        with th.no_grad():
            if self.reference_prior is not None:
                j = self.reference_prior
                col = self.net.priors[j]
                reference = F.log_softmax(col.output(hidden[j], inputs[j]), dim=1)
                k = self.near_reference_prior
                if k is None or self.kl_gate is None:
                    return logits, reference
                near = F.log_softmax(self.net.priors[k].output(hidden[k], inputs[k]), dim=1)
                is_near = self.kl_gate(pre)[:, 1:] > 0.5  # (B, 1): the hard switch's choice
                return logits, th.where(is_near, near, reference)
            own = [
                F.log_softmax(col.output(h, x), dim=1)
                for col, h, x in zip(self.net.priors, hidden, inputs, strict=True)
            ]
            stacked = th.stack(own, dim=1)  # (B, n_priors, n_actions)
            mixed = stacked.mean(dim=1) if g is None else (g.unsqueeze(2) * stacked).sum(dim=1)
            prior_log_probs = F.log_softmax(mixed, dim=1)
        return logits, prior_log_probs

    def prior_kl_weights(self, obs: PyTorchObs) -> th.Tensor | None:
        """Per-sample weights (B,) of the KL term toward pi_0: 1 where the nearest obstacle is
        farther than the policy's ``prior_kl_clearance``, 0 where it is nearer (eq. 15's switch
        with that distance); None: the term weighs every sample (also when the near samples
        have a reference of their own, ``near_reference_prior``)."""
        if self.kl_gate is None or self.near_reference_prior is not None:
            return None
        return self.kl_gate(obs)[:, 0]

    #: Gate-weight tensors held per row before they are counted (bounds their memory when
    #: many predictions run without a training call, e.g. an evaluation).
    PENDING_LEADS = 256

    @property
    def lead_counts(self) -> th.Tensor:
        """(2, n_priors) counts of the samples on which each prior column led (the gate's
        largest weight) since they were last zeroed: row 0 rollout / evaluation steps (eval
        mode), row 1 the actor-loss passes (training mode, with gradients)."""
        self._flush_leads()
        return self._lead_counts

    def _count_leads(self, g: th.Tensor) -> None:
        # Rollout steps are predicted in eval mode; the actor-loss pass is a training pass with
        # gradients (the TD-target pass runs without gradients and is not counted). Counting
        # waits for lead_counts: an argmax and bincount per prediction cost about a tenth of
        # SPNN's predict; counted at once, the counts are the same integers.
        if not self.training:
            row = 0
        elif th.is_grad_enabled():
            row = 1
        else:
            return
        pending = self._pending_leads[row]
        pending.append(g.detach())
        if len(pending) >= self.PENDING_LEADS:
            self._flush_leads()

    def _flush_leads(self) -> None:
        """Add the pending gate weights to the counts."""
        for row, pending in enumerate(self._pending_leads):
            if not pending:
                continue
            g = th.cat(pending) if len(pending) > 1 else pending[0]
            pending.clear()
            with th.no_grad():
                if self._lead_counts.device != g.device:
                    self._lead_counts = self._lead_counts.to(g.device)
                self._lead_counts[row] += th.bincount(g.argmax(dim=1), minlength=g.shape[1])

    def _predict(self, observation: PyTorchObs, deterministic: bool = False) -> th.Tensor:
        return actions_from_logits(self(observation), deterministic)


class ProgressiveCritic(BaseModel):
    """``n_critics`` Q-networks, each a :class:`ProgressiveNet` over its own prior columns."""

    action_space: spaces.Discrete
    features_extractor: BaseFeaturesExtractor

    def __init__(
        self,
        observation_space: spaces.Space,
        action_space: spaces.Discrete,
        features_extractor: BaseFeaturesExtractor,
        features_dim: int,
        q_networks: Sequence[ProgressiveNet],
        feeds: Sequence[Feed],
        gates: Sequence[nn.Module | None],
        sigma: float = 1.0,
        own_weight: float = 1.0,
        normalize_images: bool = True,
        share_features_extractor: bool = False,
    ):
        super().__init__(
            observation_space,
            action_space,
            features_extractor=features_extractor,
            normalize_images=normalize_images,
        )
        self.features_dim = features_dim
        self.n_critics = len(q_networks)
        self.q_networks = nn.ModuleList(q_networks)
        self.gates = nn.ModuleList(g if g is not None else nn.Identity() for g in gates)
        self._has_gate = [g is not None for g in gates]
        self.feeds = list(feeds)
        self.sigma = sigma
        self.own_weight = own_weight
        self.share_features_extractor = share_features_extractor

    def forward(self, obs: PyTorchObs) -> tuple[th.Tensor, ...]:
        """Q-values of every action from each Q-network: ``n_critics`` tensors (B, n_actions)."""
        pre = preprocess_obs(obs, self.observation_space, normalize_images=self.normalize_images)
        with th.set_grad_enabled(th.is_grad_enabled() and not self.share_features_extractor):
            features = self.features_extractor(pre)
        prior_inputs = [feed(pre) for feed in self.feeds]
        out = []
        # distance gates with the same rule give the same weights: computed once per forward
        by_rule: dict[tuple, th.Tensor | None] = {}
        for q_net, gate, has_gate in zip(self.q_networks, self.gates, self._has_gate, strict=True):
            rule = gate.rule() if isinstance(gate, DistanceGate) else None
            if rule is not None and rule in by_rule:
                weights = by_rule[rule]
            else:
                weights, _ = _lateral_weights(gate if has_gate else None, self.sigma, pre, features)
                if rule is not None:
                    by_rule[rule] = weights
            out.append(q_net(features, q_net.prior_hidden(prior_inputs), weights, self.own_weight))
        return tuple(out)


def _resolve_priors(
    priors: Sequence[str | os.PathLike[str]] | None,
    prior_specs: Sequence[dict[str, Any] | PriorSpec] | None,
) -> tuple[list[PriorSpec], list[PriorCheckpoint] | None]:
    if priors is not None and prior_specs is not None:
        raise ValueError("give either priors (checkpoint paths) or prior_specs, not both")
    if priors is not None:
        if isinstance(priors, (str, os.PathLike)) or len(priors) == 0:
            raise ValueError(f"priors must be a non-empty list of checkpoint paths, got {priors!r}")
        checkpoints = [load_prior(p) for p in priors]
        return [c.spec for c in checkpoints], checkpoints
    if prior_specs is None or len(prior_specs) == 0:
        raise ValueError(
            "a progressive policy needs policy_kwargs priors=[checkpoint.zip, ...] "
            "(or prior_specs from a saved model)"
        )
    specs = [s if isinstance(s, PriorSpec) else PriorSpec.from_json(s) for s in prior_specs]
    return specs, None


class ProgressivePolicy(DiscreteSACPolicy):
    """
    DiscreteSAC policy with progressive columns (PNN, eq. 13): frozen priors + a new column.

    Arguments as :class:`sb3_pnn.dsac.policies.DiscreteSACPolicy` (``net_arch`` is the new column's
    hidden widths; ``features_extractor_class`` defaults to Combined/Flatten by observation space),
    and:

    :param priors: Prior checkpoint paths (DiscreteSAC or SB3 DQN ``.zip``), column 1..k-1
    :param prior_specs: Instead of ``priors``: the architecture specs a saved model stores
        (weights then come from the saved state dict); set by :meth:`portable_policy_kwargs`
    :param learn_lateral_scale: Learn Rusu et al.'s scalar per lateral connection
    :param lateral_scale_init: Initial value of that scalar (the constant when not learned)
    :param critic_priors: Give the critics' Q-networks the priors' critic columns (the paper's
        Algorithm 1 transfers Q too); False: the critics are plain MLPs over the new observation
        and only the actor reads the priors (an ablation)
    :param start_as_prior: Before any update, every network that reads priors outputs its
        prior's own output (the actor the prior's logits, a critic the prior's Q-values; the
        SPNN the gate-selected prior's): output laterals with a bias copy the priors' output
        layers and the new column's own output layer starts at zero
        (:meth:`.columns.ProgressiveNet.start_as_priors_`; not in the paper, which starts the
        new column at random). A PNN needs exactly one prior for it, or ``reference_prior``
    :param init_from_prior: The new column starts as a copy of the first prior's column (the
        actor's from the prior's actor, critic i's from the prior's critic i mod n; observation
        inputs the prior does not see get zero first-layer weights): section 3.1's "the
        parameters of the second column are usually initialized with Theta^(1) or randomly"
        (section 3.2 then starts it at random). Needs the new column's hidden widths to be the
        first prior's
    :param prior_kl: Weight beta of a term beta * KL(pi || pi_0) added to the actor's loss,
        pi_0 the frozen priors' own policy (the SPNN's gate-selected prior,
        :meth:`ProgressiveActor.logits_and_prior_log_probs`): it keeps the new policy near what
        its priors do where reward does not say otherwise (not in the paper; 0: off). With
        alpha the entropy coefficient, the actor's optimum becomes
        pi ~ pi_0^(beta / (alpha + beta)) exp(Q / (alpha + beta))
    :param prior_kl_clearance: With a distance in metres, the KL term counts only on samples
        whose nearest obstacle (the ``sonar`` observation, eq. 15's d) is farther than it: a
        path-following prior has never seen an obstacle, so its policy is the reference only
        where none is near (not in the paper; None: every sample). Needs a ``sonar`` key
    :param action_smoothness: Weight lambda of a temporal smoothness term
        lambda * E[KL(pi(.|s) || pi(.|s'))] over replayed transitions (s, s') added to the
        actor's loss: CAPS's temporal term (Mysore et al. 2021, "Regularizing action policies
        for smooth control") for a categorical policy. It discourages a policy that turns left
        on one control step and right on the next (not in the paper; 0: off). With n-step
        returns it needs a ``Dict`` observation, whose replay buffer samples s_t+1 beside s_t+n
    :param reference_prior: With several priors, the index of the one whose policy a PNN
        starts as (``start_as_prior``; the other priors' output laterals then start at zero)
        and that ``prior_kl`` pulls toward, e.g. 0 for a PNN that reads a path-following
        column first and an obstacle-avoidance column beside it, as eq. 13 reads every
        earlier column (the paper's PNN has the path follower alone). None (default): every
        prior (the KL term's reference is their mean)
    :param near_reference_prior: With ``reference_prior`` and ``prior_kl_clearance``, the
        index of the prior whose policy the KL term pulls toward on the samples nearer an
        obstacle than the clearance (inside ``near_reference_corridor`` where that is set),
        instead of leaving them out: e.g. 1 for a PNN that reads an obstacle-avoidance column
        beside its path-following one, so that near obstacles its new column is held to the
        avoidance skill as beyond them to the route (eq. 15's switch choosing the KL term's
        reference, the output still eq. 13's). None (default): those samples are left out
    :param near_reference_corridor: With ``near_reference_prior``, a fraction c of the
        corridor half-width d_L: samples with abs(g) / d_L >= c keep the path reference whatever
        the sonar reads (the SPNN gate's corridor bound; needs a "path" observation part).
        None: the distance alone decides
    :param off_path_kl: Weight beta_off of the same KL term over off-path copies of each
        minibatch (:mod:`.off_path`: the "path" part redrawn 0.3-1 corridor half-widths off the
        path, the sonar clear), states a learner that keeps its path seldom replays, where its
        new column would otherwise extrapolate freely (not in the paper; 0: off). Needs a Dict
        observation with a "path" part
    :param clear_kl: Weight of the same KL term over copies of each minibatch whose sonar reads
        clear and whose path part is kept (:mod:`.off_path`): with ``prior_kl_clearance`` the
        reference there is the path-following prior, so a new column that reads an avoidance
        column keeps following the path as its prior does in open water (not in the paper; 0:
        off). Needs a ``sonar`` observation part
    :param obstacle_kl: Weight of the same KL term over copies of each minibatch whose sonar
        also reads 1-3 cylinders drawn around the vehicle (:mod:`.obstacle_copies`): where one
        is nearer than ``prior_kl_clearance`` the reference there is ``near_reference_prior``
        (the avoidance prior), so the new column keeps to what that prior does among obstacles
        the training layout never showed (not in the paper; 0: off). Needs a ``sonar``
        observation part
    :param obstacle_kl_span: The sonar's span S (rad, centred ahead; rov_envs' ``sonar_span``)
        that places the drawn cylinders in its sectors
    """

    actor: ProgressiveActor  # type: ignore[assignment]
    critic: ProgressiveCritic  # type: ignore[assignment]
    critic_target: ProgressiveCritic  # type: ignore[assignment]

    def __init__(
        self,
        observation_space: spaces.Space,
        action_space: spaces.Discrete,
        lr_schedule: Schedule,
        net_arch: list[int] | dict[str, list[int]] | None = None,
        activation_fn: type[nn.Module] = nn.ReLU,
        features_extractor_class: type[BaseFeaturesExtractor] | None = None,
        features_extractor_kwargs: dict[str, Any] | None = None,
        normalize_images: bool = True,
        optimizer_class: type[th.optim.Optimizer] = th.optim.Adam,
        optimizer_kwargs: dict[str, Any] | None = None,
        n_critics: int = 2,
        share_features_extractor: bool = False,
        priors: Sequence[str | os.PathLike[str]] | None = None,
        prior_specs: Sequence[dict[str, Any] | PriorSpec] | None = None,
        learn_lateral_scale: bool = True,
        lateral_scale_init: float = 1.0,
        critic_priors: bool = True,
        start_as_prior: bool = False,
        init_from_prior: bool = False,
        prior_kl: float = 0.0,
        prior_kl_clearance: float | None = None,
        action_smoothness: float = 0.0,
        reference_prior: int | None = None,
        off_path_kl: float = 0.0,
        near_reference_prior: int | None = None,
        near_reference_corridor: float | None = None,
        clear_kl: float = 0.0,
        obstacle_kl: float = 0.0,
        obstacle_kl_span: float = math.pi,
    ):
        activation_name(activation_fn)  # refuse unsupported activations early
        for name, value in (
            ("prior_kl", prior_kl),
            ("action_smoothness", action_smoothness),
            ("off_path_kl", off_path_kl),
            ("clear_kl", clear_kl),
            ("obstacle_kl", obstacle_kl),
        ):
            if not is_finite_number(value) or value < 0:
                raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
        if off_path_kl > 0 and not _has_part(observation_space, PATH_KEY, (2,)):
            raise ValueError(
                f"off_path_kl={off_path_kl!r} redraws the observation's {PATH_KEY!r} part "
                f"[a_c / pi, g / d_L], which this observation space lacks: {observation_space}"
            )
        for name, weight, verb in (
            ("clear_kl", clear_kl, "clears"),
            ("obstacle_kl", obstacle_kl, "draws obstacles into"),
        ):
            if weight > 0 and not _has_part(observation_space, SONAR_KEY):
                raise ValueError(
                    f"{name}={weight!r} {verb} the observation's {SONAR_KEY!r} part, which "
                    f"this observation space lacks: {observation_space}"
                )
        if not (is_finite_number(obstacle_kl_span) and 0 < obstacle_kl_span <= 2 * math.pi):
            raise ValueError(
                f"obstacle_kl_span={obstacle_kl_span!r} is not allowed: expected the sonar's "
                "span in (0, 2 pi] (rad)"
            )
        self.off_path_kl = float(off_path_kl)
        self.clear_kl = float(clear_kl)
        self.obstacle_kl = float(obstacle_kl)
        self.obstacle_kl_span = float(obstacle_kl_span)
        self.prior_kl = float(prior_kl)
        self.action_smoothness = float(action_smoothness)
        self.prior_kl_clearance = _checked_clearance(prior_kl_clearance, observation_space)
        if features_extractor_class is None:
            features_extractor_class = (
                CombinedExtractor
                if isinstance(observation_space, spaces.Dict)
                else FlattenExtractor
            )
        if features_extractor_class not in (CombinedExtractor, FlattenExtractor):
            raise ValueError(
                "progressive policies feed the new column the flattened observation: "
                f"features_extractor_class must be CombinedExtractor or FlattenExtractor, got "
                f"{features_extractor_class!r}"
            )
        # Set before super().__init__, which builds the networks through make_actor/make_critic.
        self.prior_specs, self._checkpoints = _resolve_priors(priors, prior_specs)
        self._validate_priors(self.prior_specs, action_space)
        if reference_prior is not None and (
            isinstance(reference_prior, bool)
            or not isinstance(reference_prior, int)
            or not 0 <= reference_prior < len(self.prior_specs)
        ):
            raise ValueError(
                f"reference_prior={reference_prior!r} is not allowed: expected None or a prior "
                f"index in [0, {len(self.prior_specs) - 1}]"
            )
        self.reference_prior = reference_prior
        self.near_reference_prior, self.near_reference_corridor = _checked_near_reference(
            near_reference_prior, near_reference_corridor, self, observation_space
        )
        new_obs = obs_spec_from_space(observation_space)
        self.feeds = [
            match_prior_obs(s.obs, new_obs, f"prior {i} ({s.source or s.algo})")
            for i, s in enumerate(self.prior_specs)
        ]
        self.learn_lateral_scale = learn_lateral_scale
        self.lateral_scale_init = lateral_scale_init
        if not isinstance(critic_priors, bool):
            raise ValueError(f"critic_priors must be True or False, got {critic_priors!r}")
        self.critic_priors = critic_priors
        if not isinstance(start_as_prior, bool):
            raise ValueError(f"start_as_prior must be True or False, got {start_as_prior!r}")
        if reference_prior is None:
            self._check_start_as_prior(start_as_prior, len(self.prior_specs))
        self.start_as_prior = start_as_prior
        if not isinstance(init_from_prior, bool):
            raise ValueError(f"init_from_prior must be True or False, got {init_from_prior!r}")
        self.init_from_prior = init_from_prior
        self._user_kwargs = dict(
            net_arch=net_arch,
            activation_fn=activation_fn,
            features_extractor_class=features_extractor_class,
            features_extractor_kwargs=features_extractor_kwargs,
            normalize_images=normalize_images,
            optimizer_class=optimizer_class,
            optimizer_kwargs=optimizer_kwargs,
            n_critics=n_critics,
            share_features_extractor=share_features_extractor,
        )
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
        self._checkpoints = None  # weights are in the columns now; drop the copies

    # --- hooks for SelectivePolicy -------------------------------------------------------
    def _validate_priors(self, specs: list[PriorSpec], action_space: spaces.Discrete) -> None:
        """Subclass hook (SelectivePolicy checks it has exactly two priors)."""

    def _make_gate(self, features_dim: int) -> nn.Module | None:
        return None

    def _check_start_as_prior(self, start_as_prior: bool, n_priors: int) -> None:
        """A PNN's laterals all weigh 1, so several priors' outputs would add up; the SPNN's
        gate weights sum to 1 (it overrides this)."""
        if start_as_prior and n_priors != 1:
            raise ValueError(
                f"start_as_prior=True needs exactly one prior for a ProgressivePolicy (the "
                f"priors' outputs would add up), got {n_priors}"
            )

    def _mixing(self) -> tuple[float, float]:
        """(sigma, own_weight): the weights of the laterals and of the own path (1, 1 for PNN)."""
        return 1.0, 1.0

    def _progressive_kwargs(self) -> dict[str, Any]:
        kwargs = dict(
            learn_lateral_scale=self.learn_lateral_scale,
            lateral_scale_init=self.lateral_scale_init,
            critic_priors=self.critic_priors,
            start_as_prior=self.start_as_prior,
            init_from_prior=self.init_from_prior,
            prior_kl=self.prior_kl,
        )
        if self.prior_kl_clearance is not None:  # named only when set (the SPNN never sets it)
            kwargs["prior_kl_clearance"] = self.prior_kl_clearance
        if self.action_smoothness > 0:  # named only when on, as saved models before it
            kwargs["action_smoothness"] = self.action_smoothness
        if self.reference_prior is not None:  # named only when set, as saved models before it
            kwargs["reference_prior"] = self.reference_prior
        if self.off_path_kl > 0:  # named only when on, as saved models before it
            kwargs["off_path_kl"] = self.off_path_kl
        if self.near_reference_prior is not None:  # named only when set, as saved models before
            kwargs["near_reference_prior"] = self.near_reference_prior
            if self.near_reference_corridor is not None:
                kwargs["near_reference_corridor"] = self.near_reference_corridor
        if self.clear_kl > 0:  # named only when on, as saved models before it
            kwargs["clear_kl"] = self.clear_kl
        if self.obstacle_kl > 0:  # named only when on, as saved models before it
            kwargs["obstacle_kl"] = self.obstacle_kl
            kwargs["obstacle_kl_span"] = self.obstacle_kl_span
        return kwargs

    # --- networks -------------------------------------------------------------------------
    def _columns(self, role: str, index: int = 0) -> list[FrozenColumn]:
        cols = []
        for j, spec in enumerate(self.prior_specs):
            col_spec = spec.actor if role == "actor" else spec.critics[index % len(spec.critics)]
            col = FrozenColumn(col_spec)
            if self._checkpoints is not None:
                ckpt = self._checkpoints[j]
                layers = (
                    ckpt.actor_layers
                    if role == "actor"
                    else ckpt.critic_layers[index % len(ckpt.critic_layers)]
                )
                col.load_layers(layers)
            cols.append(col)
        return cols

    def _init_layers(self, role: str, index: int = 0) -> Layers | None:
        """The first prior's layers the new column starts from (``init_from_prior``), or None:
        off, or the policy is being rebuilt from a saved model (whose state dict then loads)."""
        if not self.init_from_prior or self._checkpoints is None:
            return None
        ckpt = self._checkpoints[0]
        if role == "actor":
            return ckpt.actor_layers
        return ckpt.critic_layers[index % len(ckpt.critic_layers)]

    def _net(
        self,
        features_dim: int,
        hidden: list[int],
        columns: list[FrozenColumn],
        init_layers: Layers | None = None,
    ) -> ProgressiveNet:
        start = self.start_as_prior and len(columns) > 0
        net = ProgressiveNet(
            features_dim,
            hidden,
            int(self.action_space.n),
            self.activation_fn,
            columns,
            learn_lateral_scale=self.learn_lateral_scale,
            lateral_scale_init=self.lateral_scale_init,
            output_lateral_bias=start,
        )
        if init_layers is not None:
            prior_hidden = [int(w.shape[0]) for w, _ in init_layers[:-1]]
            if prior_hidden != list(hidden):
                raise ValueError(
                    f"init_from_prior=True copies the first prior's column, whose hidden widths "
                    f"are {prior_hidden}, into a new column of hidden widths {list(hidden)}: "
                    "pass net_arch with the prior's widths"
                )
            columns_seen = input_columns(
                self.feeds[0].keys, obs_spec_from_space(self.observation_space)
            )
            copy_layers(list(net.layers), init_layers, columns_seen)
        if start:  # (a saved model's state dict then overwrites these weights)
            net.start_as_priors_(multiplier=self._mixing()[0], only=self.reference_prior)
        return net

    def make_actor(
        self, features_extractor: BaseFeaturesExtractor | None = None
    ) -> ProgressiveActor:  # type: ignore[override]
        kwargs = self._update_features_extractor(self.actor_kwargs, features_extractor)
        sigma, own = self._mixing()
        fdim = kwargs["features_dim"]
        actor = ProgressiveActor(
            self.observation_space,
            self.action_space,
            kwargs["features_extractor"],
            fdim,
            self._net(
                fdim,
                list(kwargs["net_arch"]),
                self._columns("actor"),
                self._init_layers("actor"),
            ),
            self.feeds,
            gate=self._make_gate(fdim),
            sigma=sigma,
            own_weight=own,
            normalize_images=self.normalize_images,
            reference_prior=self.reference_prior,
            near_reference_prior=self.near_reference_prior,
            kl_gate=(
                None
                if self.prior_kl_clearance is None
                else DistanceGate(
                    "hard",
                    self.prior_kl_clearance,
                    SONAR_RANGE,
                    SONAR_KEY,
                    corridor=self.near_reference_corridor,
                    path_key=PATH_KEY,
                )
            ),
        )
        return actor.to(self.device)

    def make_critic(
        self, features_extractor: BaseFeaturesExtractor | None = None
    ) -> ProgressiveCritic:  # type: ignore[override]
        kwargs = self._update_features_extractor(self.critic_kwargs, features_extractor)
        sigma, own = self._mixing()
        fdim = kwargs["features_dim"]
        hidden = list(kwargs["net_arch"])
        feeds = self.feeds if self.critic_priors else []

        def columns(i: int) -> list[FrozenColumn]:
            return self._columns("critic", i) if self.critic_priors else []

        critic = ProgressiveCritic(
            self.observation_space,
            self.action_space,
            kwargs["features_extractor"],
            fdim,
            [
                self._net(fdim, hidden, columns(i), self._init_layers("critic", i))
                for i in range(self.n_critics)
            ],
            feeds,
            [self._make_gate(fdim) for _ in range(self.n_critics)],
            sigma=sigma,
            own_weight=own,
            normalize_images=self.normalize_images,
            share_features_extractor=self.share_features_extractor,
        )
        return critic.to(self.device)

    # --- hooks DiscreteSAC calls (saving, logging) ------------------------------------------
    def portable_policy_kwargs(self) -> dict[str, Any]:
        """Policy kwargs that rebuild this policy without the prior files: ``priors`` replaced by
        JSON-able ``prior_specs`` (the prior weights travel in the saved state dict)."""
        return {
            **self._user_kwargs,
            **self._progressive_kwargs(),
            "prior_specs": [s.to_json() for s in self.prior_specs],
        }

    def off_path_kl_term(self, observations: PyTorchObs, redraw_path: bool = True) -> th.Tensor:
        """mean_s' KL(pi(.|s') || pi_0(.|s')) over off-path copies s' of a replayed batch
        (:mod:`.off_path`), with gradient to the actor; ``off_path_kl`` weighs it. With
        ``redraw_path=False`` the copies keep their path part and only read a clear sonar
        (the term ``clear_kl`` weighs)."""
        sonar_key, zeroed = self._off_path_keys()
        copies = off_path_copies(observations, sonar_key, zeroed, redraw_path=redraw_path)  # type: ignore[arg-type]
        return self._copies_kl(copies)

    def obstacle_kl_term(self, observations: PyTorchObs) -> th.Tensor:
        """mean_s' KL(pi(.|s') || pi_0(.|s')) over copies s' of a replayed batch whose sonar
        also reads drawn obstacles (:mod:`.obstacle_copies`), with gradient to the actor;
        ``obstacle_kl`` weighs it."""
        copies = obstacle_copies(
            observations,  # type: ignore[arg-type]
            SONAR_KEY,
            self.obstacle_kl_span,
            SONAR_RANGE,
        )
        return self._copies_kl(copies)

    def _copies_kl(self, copies: dict[str, th.Tensor]) -> th.Tensor:
        """mean KL(pi || pi_0) over made-up states (the gate's lead counts left alone)."""
        logits, prior_log_probs = self.actor.logits_and_prior_log_probs(copies, count_leads=False)
        log_probs = F.log_softmax(logits, dim=1)
        return (log_probs.exp() * (log_probs - prior_log_probs)).sum(dim=1).mean()

    def _off_path_keys(self) -> tuple[str | None, tuple[str, ...]]:
        """(the sonar's key or None, the keys zeroed) in the off-path copies."""
        spaces_ = self.observation_space.spaces  # type: ignore[attr-defined]
        return (SONAR_KEY if SONAR_KEY in spaces_ else None), ()

    def extra_logs(self) -> dict[str, float]:
        """Extra training logs (none for the PNN; the SPNN logs its gate, see subclass)."""
        return {}

    def _get_constructor_parameters(self) -> dict[str, Any]:
        data = super()._get_constructor_parameters()
        data.update(self._progressive_kwargs())
        data["prior_specs"] = [s.to_json() for s in self.prior_specs]
        return data


register_policy_class("ProgressivePolicy", ProgressivePolicy)
