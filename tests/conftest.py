"""One torch thread per test process: the tiny networks here gain nothing from more, and the
suite runs under pytest-xdist on few cores."""

from collections.abc import Iterator

import pytest
import torch as th


@pytest.fixture(autouse=True)
def _one_torch_thread() -> Iterator[None]:
    n_threads = th.get_num_threads()
    th.set_num_threads(1)
    yield
    th.set_num_threads(n_threads)
