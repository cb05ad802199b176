"""One torch thread per test process: the tiny networks here gain nothing from more, and the
suite runs under pytest-xdist on few cores.

Every test runs on the CPU, also on a machine with a GPU, unless it is marked ``cuda``: the
suite's references (bit-for-bit equalities, tensors built by the tests) are the CPU's, and
SB3's default ``device="auto"`` would otherwise put the models on the GPU. The ``cuda`` tests
(tests/sb3_pnn/dsac/test_cuda.py, tests/sb3_pnn/reproduce/test_cuda_agents.py) check training
there; they are skipped where no GPU is present."""

from collections.abc import Iterator

import pytest
import torch as th

#: torch's own answer, kept for the tests marked ``cuda``
CUDA_AVAILABLE = th.cuda.is_available


@pytest.fixture(autouse=True, scope="session")
def _cpu_by_default() -> Iterator[None]:
    """SB3's get_device("auto") answers the CPU (session-wide: session-scoped fixtures build
    models before any test's own fixtures run)."""
    th.cuda.is_available = lambda: False
    yield
    th.cuda.is_available = CUDA_AVAILABLE


@pytest.fixture(autouse=True)
def _cuda_where_marked(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> None:
    if request.node.get_closest_marker("cuda") is not None:
        monkeypatch.setattr(th.cuda, "is_available", CUDA_AVAILABLE)


@pytest.fixture(autouse=True)
def _one_torch_thread() -> Iterator[None]:
    n_threads = th.get_num_threads()
    th.set_num_threads(1)
    yield
    th.set_num_threads(n_threads)
