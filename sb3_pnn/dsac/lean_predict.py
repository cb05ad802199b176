"""Observations to tensors for ``predict`` without SB3's per-call copies and checks.

SB3's ``BasePolicy.predict`` runs before every environment step; for a Dict observation it deep
copies the dict, copies every array, walks the policy's parameters to find its device and checks
every shape with generic helpers, which for the small networks here costs more than a
fraction of the actor's own arithmetic per step (``bench/lean_overheads.py`` measures it).
:func:`lean_obs_to_tensor` gives the tensors SB3's ``obs_to_tensor`` gives (same dtype, same
values, same batch reshape, same "vectorized" answer) for the common case, a ``Box`` or a
``Dict`` of ``Box`` spaces that are not images fed NumPy arrays, and ``None`` for anything else,
so that the caller falls back to SB3 (which also raises SB3's errors for bad shapes).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import torch as th
from gymnasium import spaces
from stable_baselines3.common.preprocessing import is_image_space


def lean_space_shapes(space: spaces.Space) -> dict[str | None, tuple[int, ...]] | None:
    """{key: shape} of a Dict of non-image Boxes ({None: shape} for a lone non-image Box), or
    None when :func:`lean_obs_to_tensor` does not handle ``space``."""
    if isinstance(space, spaces.Box):
        return None if is_image_space(space) else {None: tuple(space.shape)}
    if isinstance(space, spaces.Dict):
        shapes: dict[str | None, tuple[int, ...]] = {}
        for key, sub in space.spaces.items():
            if not isinstance(sub, spaces.Box) or is_image_space(sub):
                return None
            shapes[key] = tuple(sub.shape)
        return shapes
    return None


def _batched(array: Any, shape: tuple[int, ...]) -> tuple[np.ndarray, bool] | None:
    """(array with a batch axis, whether it had one), or None (not an ndarray, or a shape that
    SB3 refuses: let SB3 raise its error)."""
    if type(array) is not np.ndarray:
        return None
    if array.shape == shape:
        return array.reshape((1, *shape)), False
    if array.shape[1:] == shape:
        return array, True
    return None


def lean_obs_to_tensor(
    shapes: dict[str | None, tuple[int, ...]], observation: Any, device: th.device
) -> tuple[th.Tensor | dict[str, th.Tensor], bool] | None:
    """(tensor or dict of tensors, vectorized) as SB3's ``obs_to_tensor`` gives them, or None
    when this observation needs SB3's general path (see the module docstring).

    :param shapes: :func:`lean_space_shapes` of the policy's observation space
    :param observation: what ``predict`` was given
    :param device: the policy's device
    """
    if None in shapes:
        batched = _batched(observation, shapes[None])
        if batched is None:
            return None
        # a copy, as SB3's np.array(observation): the tensor never shares the caller's memory
        return th.tensor(batched[0], device=device), batched[1]
    if not isinstance(observation, dict) or observation.keys() != shapes.keys():
        return None
    tensors: dict[str, th.Tensor] = {}
    vectorized = None
    for key, shape in shapes.items():
        batched = _batched(observation[key], shape)
        if batched is None or (vectorized is not None and batched[1] != vectorized):
            return None
        vectorized = batched[1]
        tensors[key] = th.tensor(batched[0], device=device)  # type: ignore[index]
    return tensors, bool(vectorized)
