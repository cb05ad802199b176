"""The engine as Gymnasium and Stable-Baselines3 environments: :class:`~.env.RovEnv` (one
vehicle), :class:`~.vector.RovVectorEnv` (Gymnasium's batched API) and
:class:`~.sb3.RovSB3VecEnv` (SB3's ``VecEnv``)."""
