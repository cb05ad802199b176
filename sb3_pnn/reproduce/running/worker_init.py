"""What every worker process of a study does first, local pool and Ray alike: one torch thread
(on a 2-core machine more threads make the small networks slower, and several workers each with
many threads oversubscribe the cores)."""

from __future__ import annotations


def init_worker() -> None:
    """Set torch to one thread in this process (a no-op where torch is absent, as in tests whose
    stand-in work does not need it)."""
    try:
        import torch

        torch.set_num_threads(1)
    except ImportError:
        pass
