"""What every worker of a study does around a run, in the local pool and in a Ray task alike:
one torch thread per process (on a 2-core machine more threads make the small networks slower,
and several workers each with many threads oversubscribe the cores), and the manifest fields
the worker measures."""

from __future__ import annotations

import os
import time
from typing import Any


def init_worker() -> None:
    """Set torch to one thread in this process (a no-op where torch is absent, as in tests whose
    stand-in work does not need it)."""
    try:
        import torch

        torch.set_num_threads(1)
    except ImportError:
        pass


def run_manifest(
    extra: dict[str, Any], seed: int, started: float, cpu_started: float
) -> dict[str, Any]:
    """A finished run's manifest: what its work returned (``extra``), its seed, and the wall and
    CPU time since ``started`` (``time.time()``) and ``cpu_started`` (``time.process_time()``)."""
    return {
        **extra,
        "seed": seed,
        "started": started,
        "finished": time.time(),
        "wall_s": time.time() - started,
        "cpu_s": time.process_time() - cpu_started,
        "pid": os.getpid(),
    }
