"""The task array the kernels read, built from an :class:`~rov_envs.sim.config.EnvConfig`.

Both environments (single and batched) build their kernel inputs here, so both see exactly the same
task. How an episode is drawn (layout, start-pose perturbation, noise) is in
:func:`rov_envs.sim.kernel.reset_vehicle`.
"""

from __future__ import annotations

import math

import numpy as np

from rov_envs.physics.etd import ETD_SIZE
from rov_envs.physics.integrator import vehicle_coefficients
from rov_envs.physics.params import vehicle_code
from rov_envs.sim import kernel as K
from rov_envs.sim.config import TARGET_RADIUS, U_REF, EnvConfig
from rov_envs.sim.layouts import LAYOUT_CODES, LAYOUT_FIXED, max_obstacles
from rov_envs.sim.tasks import PATH_SINE


def start_heading(config: EnvConfig) -> float:
    """The path's tangent angle at the start point (0 for the straight path)."""
    if config.task.path_kind == PATH_SINE:
        return math.atan(config.amplitude * 2.0 * math.pi / config.wavelength)
    return 0.0


def layout_code(config: EnvConfig) -> int:
    """The kernel's layout code: 0 when the obstacles never change, else the generator's."""
    if config.fixed_obstacles() is not None:
        return LAYOUT_FIXED
    return LAYOUT_CODES[config.layout_name]


def obstacle_capacity(config: EnvConfig) -> int:
    """Rows to reserve for one vehicle's obstacles."""
    fixed = config.fixed_obstacles()
    if fixed is not None:
        return fixed.shape[0]
    return max_obstacles(config.layout_name, config.length)


def cfg_array(config: EnvConfig) -> np.ndarray:
    """The task array read by the kernels (layout: ``rov_envs.sim.kernel.C_*``)."""
    c = np.zeros(K.C_SIZE, dtype=np.float64)
    c[K.C_PATH] = config.task.path_kind
    c[K.C_REWARD] = config.task.reward_kind
    c[K.C_DL] = config.d_L
    c[K.C_LENGTH] = config.length
    c[K.C_AMP] = config.amplitude
    c[K.C_WAVE] = config.wavelength
    c[K.C_SPAN] = config.sonar_span
    c[K.C_RANGE] = config.sonar_range
    c[K.C_NOISE] = config.sonar_noise
    c[K.C_DT] = config.dt
    c[K.C_NSUB] = config.n_substeps
    c[K.C_MAXSTEPS] = config.max_steps
    c[K.C_LOOKAHEAD] = config.los_lookahead
    c[K.C_GOALX], c[K.C_GOALY] = config.target
    c[K.C_SONAR] = 1.0 if config.has_sonar else 0.0
    c[K.C_MOTION] = 1.0 if config.motion_obs else 0.0
    c[K.C_PROGRESS_W] = (
        0.0
        if not config.progress_weighted
        else K.PROGRESS_COURSE
        if config.progress_along == "course"
        else K.PROGRESS_PATH
    )
    c[K.C_HEADING_GOAL] = 1.0 if config.heading_reference == "goal" else 0.0
    c[K.C_GOAL_DIST] = 0.0 if config.goal_distance is None else config.goal_distance
    c[K.C_RULE_GOAL] = 1.0 if config.heading_rule == "goal" else 0.0
    c[K.C_TARGET_R] = TARGET_RADIUS
    c[K.C_SUCCESS_R] = config.success_reward
    c[K.C_OBSTACLE_W] = config.obstacle_penalty
    c[K.C_ARRIVAL_GATE] = 0.0 if config.arrival_gate is None else config.arrival_gate
    c[K.C_UREF] = U_REF
    c[K.C_LAYOUT] = layout_code(config)
    c[K.C_LAYOUT_N] = obstacle_capacity(config)
    c[K.C_START_PSI] = start_heading(config)
    c[K.C_START_POS_STD], c[K.C_START_HEAD_STD] = config.start_noise
    c[K.C_CURRENT_X], c[K.C_CURRENT_Y] = config.current
    c[K.C_VEHICLE] = vehicle_code(config.vehicle)
    coefficients = vehicle_coefficients(int(c[K.C_VEHICLE]), config.dt, config.n_substeps)
    c[K.C_ETD : K.C_ETD + ETD_SIZE] = np.ravel(coefficients)
    return c
