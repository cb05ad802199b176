"""Selective progressive policy (SPNN, paper section 3.3, eq. 15, Figure 4, Algorithm 1).

Three columns: 1 = path-following prior, 2 = obstacle-avoidance prior (both frozen, given as
``priors=[path_following_zip, obstacle_avoidance_zip]`` in that order), 3 = the new column.

Reading of eq. (15). The paper writes h_i^(3) = sigma * h_{i-1}^(j) + tau * h_{i-1}^(3), with j = 1
when d > d_th and j = 2 when d <= d_th. Taken literally it has no weights (the new column could
not learn) and adds activations of possibly different widths. We read it as eq. (13) with the two
terms weighted, the weighted sum taken before the non-linearity::

    h_i^(3) = f( own_weight * W_i h_{i-1}^(3)
                 + sigma * sum_{j=1,2} g_j(s) * U_i^(3:j) h_{i-1}^(j) + b_i )

where g(s) is the gate: the hard gate of the paper gives g = (1, 0) or (0, 1) per sample, so
exactly one prior contributes and "the unselected policy network does not contribute"; U_i^(3:j)
maps prior j's width to the new column's (the "parameter-sharing module" of Figure 4). The
paper's tau is ``own_weight`` here (``tau`` is SB3's Polyak coefficient). Rusu's extra learned
scalar per lateral is off by default (``learn_lateral_scale=False``) so that sigma keeps its
meaning. The same gate acts in the actor and in every critic (Algorithm 1 transfers pi and Q).

d = min(obs[sonar_key]) * sonar_range is the nearest-obstacle distance in metres (rov_envs'
sonar sectors are distances / sonar_range). Gates: see :mod:`.gates` (``"hard"`` = paper,
``"soft"``, ``"learned"``). The share of samples on which each prior leads (largest gate
weight) is returned by :meth:`SelectivePolicy.extra_logs`, which DiscreteSAC logs as
``train/gate/step_share_<prior>`` (rollout steps) and ``train/gate/batch_share_<prior>``
(training batches).
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from typing import Any

import torch as th
from gymnasium import spaces
from stable_baselines3.common.preprocessing import preprocess_obs
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor
from stable_baselines3.common.type_aliases import Schedule
from torch import nn

from sb3_pnn.common.checks import is_finite_number
from sb3_pnn.progressive.gates import GATES, DistanceGate, LearnedGate, checked_corridor
from sb3_pnn.progressive.prior_loading import PriorSpec
from sb3_pnn.progressive.progressive_policy import SONAR_KEY, SONAR_RANGE, ProgressivePolicy
from sb3_pnn.safe_io.policy_registry import register_policy_class

PRIOR_NAMES = ("path_following", "obstacle_avoidance")
#: The paper's switch distance d_th (m), "set to be 12.5 m after a number of experimental trials".
PAPER_D_TH = 12.5
#: The paper's weights of the selected prior's input (sigma) and of the new column's own input
#: (tau, our ``own_weight``) in eq. 15: "both set to be 0.5".
PAPER_SIGMA = 0.5
PAPER_OWN_WEIGHT = 0.5
#: The recommended set-up's weights (eq. 13's unit weights, the gate still selecting one prior),
#: used with ``start_as_prior=True``: chosen on validation episodes (docs/ablation).
DEFAULT_SIGMA = 1.0
DEFAULT_OWN_WEIGHT = 1.0
#: The recommended set-up's weight beta of KL(pi || the gate-selected prior) in the actor's loss
#: (the paper has none: 0), chosen on validation episodes (docs/ablation, section 9).
DEFAULT_PRIOR_KL = 1.0


def check_prior_order(specs: Sequence[PriorSpec], sonar_key: str = SONAR_KEY) -> None:
    """Refuse priors given in the wrong order: the path-following column comes first and does not
    observe the sonar, the obstacle-avoidance column second and does (their observation spaces
    tell them apart; a gate fed the swapped columns would silently hand obstacles to the
    path follower)."""
    first, second = (sonar_key in spec.obs.keys for spec in specs)
    if first and not second:
        pf, oa = (spec.source or spec.algo for spec in specs[::-1])
        raise ValueError(
            f"SelectivePolicy priors are swapped: {oa!r} observes {sonar_key!r} (an "
            f"obstacle-avoidance column) and {pf!r} does not (a path-following column); "
            f"expected [path_following_zip, obstacle_avoidance_zip], i.e. [{pf!r}, {oa!r}]"
        )


class SelectivePolicy(ProgressivePolicy):
    """
    SPNN policy for DiscreteSAC (eq. 15): two frozen priors selected per sample + a new column.

    Arguments as :class:`ProgressivePolicy`, and:

    :param priors: ``[path_following_zip, obstacle_avoidance_zip]``, in that order
    :param sigma: Weight of the selected prior's lateral input (default 1; paper: 0.5)
    :param own_weight: Weight of the new column's own input, the paper's tau (default 1; paper:
        0.5)
    :param start_as_prior: the networks start as the gate-selected prior (default True; the
        paper's new column starts at random: False), see :class:`ProgressivePolicy`
    :param d_th: Switching distance in metres (paper: 12.5)
    :param sonar_range: Sonar range in metres (sonar observations are distance / range)
    :param sonar_key: Observation key of the sonar
    :param gate: ``"hard"`` (paper), ``"soft"`` or ``"learned"`` (see :mod:`.gates`); the study
        uses the soft gate on the sinusoid, whose 15 m corridor leaves no room for the
        avoidance prior's detours (set-up factor ``spnn_gate_sine``, docs/ablation section 11)
    :param temperature: Temperature (metres) of the soft gate (the study's: 2)
    :param gate_corridor: With a hard or soft gate, the fraction of the corridor half-width d_L
        beyond which the path column steers whatever the sonar reads (``|g| / d_L >= c``, read
        from the observation's "path" part; see :mod:`.gates`). None (default, the paper): the
        distance alone decides.
    :param gate_latch_key: With the hard gate, an observation key that remembers a near
        obstacle (rov_envs' ``obstacle_latch`` part: 1 from a reading within its ``on`` metres
        until one beyond its ``off``): the avoidance column has control while it reads 1,
        instead of while d <= d_th, so the switch keeps control through the turn away from an
        obstacle, which the sonar loses behind the vehicle (docs/ablation section 42). The
        memory is part of the observation, so the replayed samples switch as the acting policy
        did. None (default, eq. 15): the switch has no memory.
    :param gate_hidden: Hidden width of the learned gate
    :param prior_kl: Weight of KL(pi || the gate-selected prior's policy) in the actor's loss
        (see :class:`ProgressivePolicy`; default 1; 0: off, the paper)
    :param action_smoothness: Weight of the temporal smoothness term in the actor's loss (see
        :class:`ProgressivePolicy`; 0: off, the paper)
    :param off_path_kl: Weight of the KL term over off-path copies of each minibatch (see
        :class:`ProgressivePolicy`; the copies' sonar reads clear and their latch, if any, 0,
        so the gate selects the path-following prior; 0: off, the paper)
    :param clear_kl: Weight of the same KL term over copies of each minibatch that keep their
        path part and read a clear sonar (see :class:`ProgressivePolicy`): the gate selects the
        path-following prior there, so the new column is held to how that prior follows the
        path wherever the vehicle is (0: off, the paper)
    :param obstacle_kl: Weight of the same KL term over copies of each minibatch whose sonar
        also reads drawn obstacles (see :class:`ProgressivePolicy`): the gate selects the
        avoidance prior where one is within d_th (0: off, the paper)
    :param obstacle_kl_span: The sonar's span (rad) that places the drawn obstacles
    """

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
        learn_lateral_scale: bool = False,
        lateral_scale_init: float = 1.0,
        sigma: float = DEFAULT_SIGMA,
        own_weight: float = DEFAULT_OWN_WEIGHT,
        d_th: float = PAPER_D_TH,
        sonar_range: float = SONAR_RANGE,
        sonar_key: str = SONAR_KEY,
        gate: str = "hard",
        temperature: float = 1.0,
        gate_corridor: float | None = None,
        gate_latch_key: str | None = None,
        gate_hidden: int = 32,
        critic_priors: bool = True,
        start_as_prior: bool = True,
        init_from_prior: bool = False,
        prior_kl: float = DEFAULT_PRIOR_KL,
        action_smoothness: float = 0.0,
        off_path_kl: float = 0.0,
        clear_kl: float = 0.0,
        obstacle_kl: float = 0.0,
        obstacle_kl_span: float = math.pi,
    ):
        if gate not in GATES:
            raise ValueError(f"gate must be one of {GATES}, got {gate!r}")
        if (
            not isinstance(observation_space, spaces.Dict)
            or sonar_key not in observation_space.spaces
        ):
            raise ValueError(
                f"SelectivePolicy needs a Dict observation with a {sonar_key!r} key (the sonar "
                f"gives the obstacle distance d of eq. 15), got {observation_space}"
            )
        if gate_corridor is not None:
            if gate == "learned":
                raise ValueError(
                    f"gate_corridor={gate_corridor!r} needs a distance gate ('hard' or 'soft'), "
                    "got gate='learned' (set gate_corridor=None)"
                )
            if "path" not in observation_space.spaces:
                raise ValueError(
                    f"gate_corridor={gate_corridor!r} needs the observation's 'path' part "
                    f"[a_c / pi, g / d_L], got {observation_space}"
                )
        if gate_latch_key is not None and (
            gate != "hard" or gate_latch_key not in observation_space.spaces
        ):
            raise ValueError(
                f"gate_latch_key={gate_latch_key!r} is not allowed: expected None, or with "
                f"gate='hard' (got {gate!r}) a key of the observation (got "
                f"{list(observation_space.spaces)})"
            )
        for name, value in (("sigma", sigma), ("own_weight", own_weight), ("d_th", d_th)):
            if not is_finite_number(value) or value < 0:
                raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
        self.sigma = float(sigma)
        self.own_weight = float(own_weight)
        self.d_th = float(d_th)
        self.sonar_range = float(sonar_range)
        self.sonar_key = sonar_key
        self.gate = gate
        self.temperature = float(temperature)
        self.gate_corridor = checked_corridor(gate_corridor, "gate_corridor")
        self.gate_latch_key = gate_latch_key
        self.gate_hidden = int(gate_hidden)
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
            priors,
            prior_specs,
            learn_lateral_scale,
            lateral_scale_init,
            critic_priors,
            start_as_prior,
            init_from_prior,
            prior_kl,
            action_smoothness=action_smoothness,
            off_path_kl=off_path_kl,
            clear_kl=clear_kl,
            obstacle_kl=obstacle_kl,
            obstacle_kl_span=obstacle_kl_span,
        )

    def _validate_priors(self, specs: list[PriorSpec], action_space: spaces.Discrete) -> None:
        if len(specs) != 2:
            raise ValueError(
                "SelectivePolicy takes exactly two priors, [path_following_zip, "
                f"obstacle_avoidance_zip], got {len(specs)}"
            )
        if self._checkpoints is not None:  # files given now (a saved model was checked then)
            check_prior_order(specs, self.sonar_key)

    def _check_start_as_prior(self, start_as_prior: bool, n_priors: int) -> None:
        """Any number of priors: the gate weights sum to 1, so the output starts as the
        gate-weighted mix of the priors' outputs (the selected prior's with the hard gate)."""

    def _make_gate(self, features_dim: int) -> nn.Module | None:
        if self.gate == "learned":
            return LearnedGate(features_dim, 2, self.gate_hidden)
        return DistanceGate(
            self.gate,
            self.d_th,
            self.sonar_range,
            self.sonar_key,
            self.temperature,
            corridor=self.gate_corridor,
            latch_key=self.gate_latch_key,
        )

    def _mixing(self) -> tuple[float, float]:
        return self.sigma, self.own_weight

    def _off_path_keys(self) -> tuple[str | None, tuple[str, ...]]:
        latch = () if self.gate_latch_key is None else (self.gate_latch_key,)
        return self.sonar_key, latch

    def _progressive_kwargs(self) -> dict[str, Any]:
        return dict(
            **super()._progressive_kwargs(),
            sigma=self.sigma,
            own_weight=self.own_weight,
            d_th=self.d_th,
            sonar_range=self.sonar_range,
            sonar_key=self.sonar_key,
            gate=self.gate,
            temperature=self.temperature,
            gate_corridor=self.gate_corridor,
            gate_latch_key=self.gate_latch_key,
            gate_hidden=self.gate_hidden,
        )

    def gate_weights(self, obs: dict[str, Any]) -> th.Tensor:
        """The actor's gate weights g(s) (B, 2) over [path following, obstacle avoidance], for
        a batch of observations (numpy arrays as from the env, or tensors)."""
        if not all(isinstance(v, th.Tensor) for v in obs.values()):
            obs, _ = self.obs_to_tensor(obs)
        pre = preprocess_obs(obs, self.observation_space, normalize_images=self.normalize_images)
        with th.no_grad():
            return self.actor.gate(pre, self.actor.features_extractor(pre))  # type: ignore[misc]

    def extra_logs(self) -> dict[str, float]:
        """Share of samples on which each prior column led since the last call (then reset)."""
        logs: dict[str, float] = {}
        counts = self.actor.lead_counts
        for row, prefix in ((0, "gate/step_share"), (1, "gate/batch_share")):
            total = float(counts[row].sum())
            if total > 0:
                for j, name in enumerate(PRIOR_NAMES):
                    logs[f"{prefix}_{name}"] = float(counts[row, j]) / total
        counts.zero_()
        return logs


register_policy_class("SelectivePolicy", SelectivePolicy)
