"""Toy ROV-like environment for the progressive tests (rov_envs' observation keys)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from sb3_pnn.progressive.progressive_policy import SONAR_RANGE

PATH = spaces.Box(-1.0, 1.0, (2,), np.float32)
SONAR = spaces.Box(0.0, 1.0, (9,), np.float32)


class ToyRovEnv(gym.Env):
    """Dict observations with rov_envs' keys; reward 1 for action 2; 20-step episodes."""

    def __init__(self, keys: tuple[str, ...] = ("path", "sonar"), extra: dict | None = None):
        parts = {"path": PATH, "sonar": SONAR, **(extra or {})}
        self.observation_space = spaces.Dict({k: parts[k] for k in keys})
        self.action_space = spaces.Discrete(5)
        self.sonar_range = SONAR_RANGE
        self._t = 0

    def reset(self, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self.observation_space.seed(seed)
        self._t = 0
        return self.observation_space.sample(), {}

    def step(self, action):
        self._t += 1
        done = self._t >= 20
        info = {"is_success": True} if done else {}
        return self.observation_space.sample(), float(action == 2), done, False, info


def toy_model(policy_class, policy_kwargs: dict, **kwargs):
    """A DiscreteSAC on :class:`ToyRovEnv` with a small buffer and batch (``kwargs`` override)."""
    from sb3_pnn import DiscreteSAC

    options = dict(learning_starts=20, buffer_size=1000, batch_size=16, seed=0)
    options.update(kwargs)
    return DiscreteSAC(policy_class, ToyRovEnv(), policy_kwargs=policy_kwargs, **options)


def batch(space: spaces.Dict, n: int, seed: int = 0) -> dict[str, np.ndarray]:
    space.seed(seed)
    samples = [space.sample() for _ in range(n)]
    return {k: np.stack([s[k] for s in samples]) for k in space.spaces}


#: Nearest-obstacle distances (m) of the rows that :func:`near_far_batch` builds: with SPNN's
#: d_th = 12.5 m the gate sees far, near, far, near, near.
NEAR_DISTANCES = np.array([13.0, 12.0, 24.0, 0.5, 3.0])


def near_far_batch(space: spaces.Dict, seed: int = 3) -> dict[str, np.ndarray]:
    """A batch whose row i has one sonar sector at NEAR_DISTANCES[i] and the rest clear."""
    obs = batch(space, len(NEAR_DISTANCES), seed=seed)
    sonar = np.ones_like(obs["sonar"])
    rows = np.arange(len(NEAR_DISTANCES))
    sonar[rows, (rows * 2) % 9] = NEAR_DISTANCES / SONAR_RANGE
    obs["sonar"] = sonar.astype(np.float32)
    return obs


def obs_tensor(policy, obs: dict[str, np.ndarray], keys=None):
    """``obs`` (or only its ``keys``) as the policy's tensors."""
    part = obs if keys is None else {k: obs[k] for k in keys}
    return policy.obs_to_tensor(part)[0]


def kl_to_path_checkpoint(policy, obs, path_zip) -> float:
    """mean KL(pi(.|s) || pi_pf(.|s)) over the tensors ``obs``, the path-following checkpoint
    ``path_zip`` read from disk and fed its own "path" part: the hand-made value of a KL term
    toward that prior."""
    import torch as th
    import torch.nn.functional as F

    from sb3_pnn import DiscreteSAC

    pf = DiscreteSAC.load(path_zip, device="cpu").policy
    with th.no_grad():
        log_pi = F.log_softmax(policy.actor(obs), dim=1)
        log_pf = F.log_softmax(pf.actor({"path": obs["path"]}), dim=1)
    return float((log_pi.exp() * (log_pi - log_pf)).sum(dim=1).mean())


def actor_loss_inputs(seed: int = 0, n: int = 8, n_actions: int = 5):
    """Random actor logits, a second logits tensor (a reference or the next state's), twin
    Q-values and the other arguments of ``discrete_sac_losses``, for tests of its actor terms."""
    import torch as th

    gen = th.Generator().manual_seed(seed)
    logits = th.randn(n, n_actions, generator=gen)
    other = th.randn(n, n_actions, generator=gen)
    q = (th.randn(n, n_actions, generator=gen), th.randn(n, n_actions, generator=gen))
    common = dict(target_q_values=th.zeros(n, 1), actions=th.zeros(n, 1), ent_coef=0.2)
    return logits, other, q, common


def two_column_pnn(paths, **kwargs):
    """A PNN on :class:`ToyRovEnv` reading the path-following and the avoidance checkpoint of the
    ``priors`` fixture, started as and referred to the path follower (``kwargs`` override)."""
    from sb3_pnn import ProgressivePolicy

    options = dict(
        priors=[paths["pf_dsac"], paths["oa_dsac"]],
        net_arch=[16, 16],
        start_as_prior=True,
        reference_prior=0,
        lateral_scale_init=0.0,
        prior_kl=1.0,
    )
    options.update(kwargs)
    return toy_model(ProgressivePolicy, options)


def near_reference_pnn(paths, **kwargs):
    """:func:`two_column_pnn` with the near reference: its KL term pulls toward the avoidance
    column on samples with an obstacle within 12.5 m (``kwargs`` override)."""
    return two_column_pnn(
        paths, **{"prior_kl_clearance": 12.5, "near_reference_prior": 1, **kwargs}
    )
