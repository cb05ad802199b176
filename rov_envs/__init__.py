"""rov_envs: a fast BlueROV2 simulator with the tasks of Pan et al. (2025) as Gymnasium envs.

``import rov_envs`` registers the tasks (idempotently) under the ids in :data:`ENV_IDS`:

========================================  ===============================================
id                                        task
========================================  ===============================================
``rov_envs/PathFollowingStraight-v0``     200 m line, observation {"path"}
``rov_envs/PathFollowingSine-v0``         120 m sinusoid, observation {"path"}
``rov_envs/ObstacleAvoidance-v0``         reach a goal 60 m ahead past 2-4 random cylinders
``rov_envs/PlanningStraight-v0``          line + the paper's 4 obstacles
``rov_envs/PlanningSine-v0``              sinusoid + the paper's 2 obstacles
``rov_envs/PlanningStraightUniform-v0``   line, obstacles spread evenly along the route
``rov_envs/PlanningStraightDense-v0``     line, dense obstacles along the route
``rov_envs/PlanningSineDense-v0``         sinusoid, dense obstacles along the curve
========================================  ===============================================

Every task takes ``vehicle="uuv_simulator"`` (default: UUV Simulator's BlueROV2, the paper's
Gazebo model) or ``vehicle="wu2018"`` (Wu's 2018 parameter set), see ``rov_envs.physics.params``.
Single environments: ``gymnasium.make(id, **kwargs)`` (:class:`RovEnv`). Natively batched:
``gymnasium.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point")``
(:class:`RovVectorEnv`), or :class:`RovSB3VecEnv` for Stable-Baselines3. The tasks are
left-right symmetric; :data:`LEFT_RIGHT_MIRROR` maps a sample to its mirror image
(:mod:`rov_envs.sim.symmetry`).
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym

from rov_envs.moved import ROV_ENVS_MOVED, install
from rov_envs.sim.symmetry import LEFT_RIGHT_MIRROR
from rov_envs.sim.tasks import ENV_IDS, TASKS

__all__ = [
    "ENV_IDS",
    "LEFT_RIGHT_MIRROR",
    "TASKS",
    "RovEnv",
    "RovVectorEnv",
    "RovSB3VecEnv",
    "register_envs",
]


def register_envs() -> None:
    """Register every task id with Gymnasium; calling it again changes nothing."""
    for name in TASKS:
        env_id = f"rov_envs/{name}-v0"
        if env_id in gym.registry:
            continue
        gym.register(
            id=env_id,
            entry_point="rov_envs.envs.env:RovEnv",
            vector_entry_point="rov_envs.envs.vector:RovVectorEnv",
            kwargs={"task": name},
            max_episode_steps=None,  # the env truncates itself (the limit depends on kwargs)
        )


def __getattr__(name: str) -> Any:  # lazy: keep `import rov_envs` light
    if name == "RovEnv":
        from rov_envs.envs.env import RovEnv

        return RovEnv
    if name == "RovVectorEnv":
        from rov_envs.envs.vector import RovVectorEnv

        return RovVectorEnv
    if name == "RovSB3VecEnv":
        from rov_envs.envs.sb3 import RovSB3VecEnv

        return RovSB3VecEnv
    raise AttributeError(f"module 'rov_envs' has no attribute {name!r}")


register_envs()
install(ROV_ENVS_MOVED)
