"""Per-vehicle random streams (splitmix64) used inside the numba kernels.

Every vehicle owns one ``uint64`` state in an array ``rng``; the kernels draw from ``rng[i]``
everything random in an episode: the obstacle layout, the start-pose perturbation and the sonar
noise. A stream is seeded from a ``numpy.random.Generator`` (the single environment's
``np_random``, or vehicle i's own generator in the batch) when the environment is reset with a
seed, or at its first reset, and then runs on across episodes. So the same seed gives the same
episodes bit for bit, in a single environment and in the batch alike, without a Python call
per episode.

splitmix64 (Steele, Lea, Flood 2014) passes BigCrush; floats take its top 53 bits.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["stream_seed", "uniform", "gauss"]

_M1 = np.uint64(0x9E3779B97F4A7C15)
_M2 = np.uint64(0xBF58476D1CE4E5B9)
_M3 = np.uint64(0x94D049BB133111EB)
_S30 = np.uint64(30)
_S27 = np.uint64(27)
_S31 = np.uint64(31)
_S11 = np.uint64(11)


def stream_seed(generator: np.random.Generator) -> np.uint64:
    """A stream state drawn from ``generator`` (one draw)."""
    return np.uint64(generator.integers(0, 2**63 - 1, dtype=np.int64))


@njit(cache=True, inline="always")
def uniform(rng: np.ndarray, i: int) -> float:
    """A float in [0, 1) from stream ``rng[i]`` (advances it)."""
    z = rng[i] + _M1
    rng[i] = z
    z = (z ^ (z >> _S30)) * _M2
    z = (z ^ (z >> _S27)) * _M3
    z = z ^ (z >> _S31)
    return float(z >> _S11) * (1.0 / 9007199254740992.0)


@njit(cache=True, inline="always")
def gauss(rng: np.ndarray, i: int) -> float:
    """A standard normal draw (Box-Muller) from stream ``rng[i]``."""
    u1 = 1.0 - uniform(rng, i)
    u2 = uniform(rng, i)
    return math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * math.pi * u2)
