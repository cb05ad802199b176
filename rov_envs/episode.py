"""Episode set-up shared by the single and the batched environments.

Both draw an episode the same way from a ``numpy.random.Generator`` (the single env's
``np_random``; vehicle i's own generator in the batch), in this order: the obstacle layout
(:mod:`rov_envs.layouts`, only for generated layouts), the start-pose perturbation (only when its
std is non-zero), then a 64-bit seed for the kernel's in-episode noise stream. Same generator
state, same episode, bit for bit.
"""

from __future__ import annotations

import math

import numpy as np

from rov_envs import kernel as K
from rov_envs.config import TARGET_RADIUS, U_REF, EnvConfig
from rov_envs.layouts import LAYOUTS, max_obstacles
from rov_envs.physics.dynamics import DEFAULT_SUBSTEPS, STATE_DIM
from rov_envs.physics.guidance import DEFAULT_LOOKAHEAD
from rov_envs.tasks import PATH_SINE


def cfg_array(config: EnvConfig) -> np.ndarray:
    """The task array read by the kernels (layout: ``rov_envs.kernel.C_*``)."""
    c = np.zeros(K.C_SIZE, dtype=np.float64)
    c[K.C_PATH] = config.task.path_kind
    c[K.C_REWARD] = config.task.reward_kind
    c[K.C_DL] = config.task.d_L
    c[K.C_LENGTH] = config.length
    c[K.C_AMP] = config.amplitude
    c[K.C_WAVE] = config.wavelength
    c[K.C_SPAN] = config.sonar_span
    c[K.C_RANGE] = config.sonar_range
    c[K.C_NOISE] = config.sonar_noise
    c[K.C_DT] = config.dt
    c[K.C_NSUB] = DEFAULT_SUBSTEPS
    c[K.C_MAXSTEPS] = config.max_steps
    c[K.C_LOOKAHEAD] = DEFAULT_LOOKAHEAD
    c[K.C_GOALX], c[K.C_GOALY] = config.target
    c[K.C_SONAR] = 1.0 if config.has_sonar else 0.0
    c[K.C_TARGET_R] = TARGET_RADIUS
    c[K.C_SUCCESS_R] = config.success_reward
    c[K.C_UREF] = U_REF
    return c


def obstacle_capacity(config: EnvConfig) -> int:
    """Rows to reserve for one vehicle's obstacles."""
    fixed = config.fixed_obstacles()
    if fixed is not None:
        return fixed.shape[0]
    return max_obstacles(config.task.layout, config.length)


def start_heading(config: EnvConfig) -> float:
    """The path's tangent angle at the start point (0 for the straight path)."""
    if config.task.path_kind == PATH_SINE:
        return math.atan(config.amplitude * 2.0 * math.pi / config.wavelength)
    return 0.0


def sample_episode(
    config: EnvConfig, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray, np.uint64]:
    """Draw (start state (18,), obstacles (M, 3), noise-stream seed) for one episode."""
    obstacles = config.fixed_obstacles()
    if obstacles is None:
        obstacles = LAYOUTS[config.task.layout](
            rng, config.length, config.amplitude, config.wavelength
        )
    state = np.zeros(STATE_DIM, dtype=np.float64)
    psi = start_heading(config)
    pos_std, head_std = config.start_noise
    if pos_std > 0.0:
        state[0], state[1] = rng.normal(0.0, pos_std, size=2)
    if head_std > 0.0:
        psi += float(rng.normal(0.0, head_std))
    state[5] = psi
    seed = np.uint64(rng.integers(0, 2**63 - 1, dtype=np.int64))
    return state, obstacles, seed
