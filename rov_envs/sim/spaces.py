"""Observation and action spaces of a task (shared by the single and the batched environments)."""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from rov_envs.physics.thrusters import ACTION_TABLE
from rov_envs.sim.config import EnvConfig
from rov_envs.sim.kernel import MOTION_SWAY_LIMIT, MOTION_YAW_RATE_LIMIT

#: ``"motion"`` = (sway v in m/s, yaw rate r in rad/s), body frame, clipped to these bounds.
MOTION_SPACE = spaces.Box(
    np.array([-MOTION_SWAY_LIMIT, -MOTION_YAW_RATE_LIMIT], dtype=np.float32),
    np.array([MOTION_SWAY_LIMIT, MOTION_YAW_RATE_LIMIT], dtype=np.float32),
    dtype=np.float32,
)


def make_spaces(config: EnvConfig) -> tuple[spaces.Dict, spaces.Space]:
    """``Dict([path][, goal][, sonar][, motion][, latch])`` observations (``config.obs_parts``);
    ``Discrete(5)`` or ``Box(-1, 1, (2,))`` actions."""
    parts: dict[str, spaces.Space] = {}
    if "path" in config.obs_parts:
        parts["path"] = spaces.Box(-1.0, 1.0, (2,), np.float32)
    if "goal" in config.obs_parts:
        parts["goal"] = spaces.Box(-1.0, 1.0, (2 if config.goal_offset else 1,), np.float32)
    if config.has_sonar:
        parts["sonar"] = spaces.Box(0.0, 1.0, (config.sonar_sectors,), np.float32)
    if config.motion_obs:
        parts["motion"] = MOTION_SPACE
    if config.obstacle_latch is not None:  # 1 while a near obstacle is remembered, else 0
        parts["latch"] = spaces.Box(0.0, 1.0, (1,), np.float32)
    action: spaces.Space
    if config.continuous:
        action = spaces.Box(-1.0, 1.0, (2,), np.float32)
    else:
        action = spaces.Discrete(ACTION_TABLE.shape[0])
    return spaces.Dict(parts), action
