"""The per-vehicle random streams behind layouts, start noise and sonar noise."""

from __future__ import annotations

import numpy as np

from rov_envs.sim.random_stream import gauss, stream_seed, uniform


def _draws(fn, seed: int, n: int) -> np.ndarray:
    rng = np.array([np.uint64(seed)], dtype=np.uint64)
    return np.array([fn(rng, 0) for _ in range(n)])


def test_uniform_is_uniform_on_unit_interval() -> None:
    u = _draws(uniform, 12345, 20000)
    assert u.min() >= 0.0 and u.max() < 1.0
    counts, _ = np.histogram(u, bins=10, range=(0.0, 1.0))
    # chi-square with 9 degrees of freedom: 27.9 is its 99.9 % quantile
    assert ((counts - 2000.0) ** 2 / 2000.0).sum() < 27.9


def test_gauss_moments() -> None:
    g = _draws(gauss, 7, 20000)
    assert abs(g.mean()) < 0.03 and abs(g.std() - 1.0) < 0.03  # about 4 standard errors
    assert abs(np.mean(g**3)) < 0.1


def test_streams_are_reproducible_and_distinct() -> None:
    assert np.array_equal(_draws(uniform, 1, 50), _draws(uniform, 1, 50))
    assert not np.array_equal(_draws(uniform, 1, 50), _draws(uniform, 2, 50))
    seeds = [stream_seed(np.random.default_rng(s)) for s in (0, 0, 1)]
    assert seeds[0] == seeds[1] != seeds[2]
    assert isinstance(seeds[0], np.uint64)
