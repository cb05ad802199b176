"""The simulation core: tasks, their arguments, rewards, layouts and the numba kernels that step
N vehicles at once (:mod:`.engine`'s :class:`~rov_envs.sim.engine.RovBatch`). No Gymnasium
wrappers here: :mod:`rov_envs.envs` adapts the engine to Gymnasium and Stable-Baselines3."""
