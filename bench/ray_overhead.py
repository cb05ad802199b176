"""The scheduling overhead of Ray against the local process pool, on the quick study.

Runs the quick study (``python -m sb3_pnn.reproduce --quick``: 23 runs, 2 seeds) twice in one
invocation, into two temporary folders: with the local process pool (the anchor) and on a local
Ray instance of the same number of CPUs (``--executor ray``), alternating which goes first over
``--repeats``. Prints both wall times and their ratio (Ray / local; the goal is at most 1.10 on
2 cores), and checks that both made the same runs (``same_runs``).

Usage: python bench/ray_overhead.py [--jobs 2] [--repeats 1]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.running.executor import execute
from sb3_pnn.reproduce.running.ray_pool import RayPool, connect
from sb3_pnn.reproduce.running.store import RunStore
from sb3_pnn.reproduce.running.work import run_work
from sb3_pnn.reproduce.tools.same_runs import differences, finished


def study(folder: Path, jobs: int, ray=None) -> float:
    """Wall seconds of the quick study in ``folder`` (local pool, or Ray when given)."""
    store = RunStore(folder)
    store.open()
    try:
        pool = RayPool(store, run_work, ray) if ray is not None else None
        start = time.perf_counter()
        summary = execute(build_plan(StudyConfig("quick", seeds=2)), store, run_work, jobs,
                          quiet=True, pool=pool)  # fmt: skip
        wall = time.perf_counter() - start
    finally:
        store.close()
    if summary.failed or summary.blocked:
        raise SystemExit(f"runs failed in {folder}: {sorted(summary.failed)}")
    return wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=2, help="processes / Ray CPUs (default 2)")
    parser.add_argument("--repeats", type=int, default=1, help="pairs of studies (default 1)")
    args = parser.parse_args()
    started = time.perf_counter()
    ray = connect(None, num_cpus=args.jobs)
    print(f"Ray instance of {args.jobs} CPUs started in {time.perf_counter() - started:.1f} s")
    ratios = []
    with tempfile.TemporaryDirectory() as scratch:
        for repeat in range(args.repeats):
            order = ("local", "ray") if repeat % 2 == 0 else ("ray", "local")
            walls = {}
            for kind in order:
                folder = Path(scratch) / f"{kind}-{repeat}"
                walls[kind] = study(folder, args.jobs, ray if kind == "ray" else None)
            local, on_ray = (Path(scratch) / f"{k}-{repeat}" for k in ("local", "ray"))
            same = all(
                not differences(on_ray / "runs" / r, local / "runs" / r) for r in finished(local)
            )
            ratios.append(walls["ray"] / walls["local"])
            print(
                f"quick study ({len(finished(local))} runs, --jobs {args.jobs}): local pool "
                f"{walls['local']:.1f} s (anchor), Ray {walls['ray']:.1f} s: "
                f"{ratios[-1]:.2f}x; runs identical: {same}",
                flush=True,
            )
    print(f"Ray / local, mean over {len(ratios)}: {sum(ratios) / len(ratios):.2f}x")


if __name__ == "__main__":
    main()
