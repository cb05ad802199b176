"""Run a plan's independent runs in parallel, priors before the runs that need them.

:func:`execute` keeps up to ``jobs`` runs going in a process pool (``spawn`` context: no forked
torch/numba state; every worker sets ``torch.set_num_threads(1)``). A run is submitted once all
its ``deps`` have finished; a run whose dependency failed is skipped (and reported). Each run's
whole life (temporary folder, work, manifest, atomic rename) happens in :func:`run_one`, in the
worker, so that a run orphaned by a killed study still either commits a complete result or
nothing. The work itself is a plain function ``work(spec, tmp_dir, dep_dirs) -> dict`` (the
manifest's extra fields): :func:`sb3_pnn.reproduce.running.work.run_work` in the real study, small
stand-ins in tests.

Ctrl-C (``KeyboardInterrupt``) stops the invocation: nothing new is started, the runs in
flight end (a worker that got the interrupt too records its run as failed; one that did not
commits it), and :func:`execute` returns its summary with ``stopped`` set, so that the caller
can record the session; running the same command again resumes.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import time
import traceback
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from sb3_pnn.reproduce.planning.plan import RunSpec
from sb3_pnn.reproduce.running.store import RunStore

WorkFn = Callable[[RunSpec, Path, dict[str, Path]], dict[str, Any]]


@dataclass
class ExecutionSummary:
    """What one invocation did: run ids by outcome and its wall-clock time."""

    done: list[str] = field(default_factory=list)  # finished in this invocation
    skipped_finished: list[str] = field(default_factory=list)  # finished earlier (resume)
    failed: dict[str, str] = field(default_factory=dict)  # run id -> error
    blocked: dict[str, str] = field(default_factory=dict)  # run id -> failed dependency
    wall_s: float = 0.0
    stopped: bool = False  # ended by Ctrl-C before every run was done

    def session_record(self, started: float, jobs: int) -> dict[str, Any]:
        """What sessions.json keeps of this invocation (started: its ``time.time()``)."""
        record: dict[str, Any] = {
            "started": started,
            "wall_s": time.time() - started,
            "jobs": jobs,
            "runs_done": len(self.done),
            "runs_skipped_finished": len(self.skipped_finished),
            "runs_failed": len(self.failed),
            "runs_blocked": len(self.blocked),
        }
        if self.stopped:
            record["stopped"] = True
            record["note"] = f"stopped by the user after {len(self.done)} new run(s)"
        return record

    def stopped_message(self) -> str:
        """What a command line prints when Ctrl-C stopped it (it then writes no report)."""
        return (
            f"stopped after {len(self.done)} new run(s), no report written; the same command "
            "resumes (a run cut short is run again)"
        )


def _init_worker() -> None:
    try:
        import torch

        torch.set_num_threads(1)
    except ImportError:  # stand-in work in tests does not need torch
        pass


def run_one(work: WorkFn, spec_data: dict[str, Any], out: str) -> tuple[str, str, str]:
    """Do one run in this process and commit it; returns (run_id, status, error text)."""
    _init_worker()
    spec = RunSpec.from_dict(spec_data)
    store = RunStore(out)
    tmp = None
    started = time.time()
    cpu_started = time.process_time()
    try:
        tmp = store.begin(spec)
        deps = {dep: store.run_dir(dep) for dep in spec.deps}
        extra = work(spec, tmp, deps)
        manifest = {
            **extra,
            "seed": spec.seed,
            "started": started,
            "finished": time.time(),
            "wall_s": time.time() - started,
            "cpu_s": time.process_time() - cpu_started,
            "pid": os.getpid(),
        }
        committed = store.commit(spec, tmp, manifest)
        return spec.run_id, "done" if committed else "kept_existing", ""
    except BaseException:  # noqa: BLE001 - a failed run must not stop the study
        error = traceback.format_exc()
        store.fail(spec, tmp, error)
        return spec.run_id, "failed", error


def _progress(total: int, initial: int, quiet: bool) -> Any:
    from tqdm.auto import tqdm

    return tqdm(
        total=total,
        initial=initial,
        desc="runs",
        unit="run",
        disable=quiet,
        bar_format=(
            "{desc}: {n_fmt}/{total_fmt} done |{bar}| elapsed {elapsed} (eta {remaining}) {postfix}"
        ),
        dynamic_ncols=True,
    )


def execute(
    plan: list[RunSpec],
    store: RunStore,
    work: WorkFn,
    jobs: int,
    quiet: bool = False,
    max_new_runs: int | None = None,
) -> ExecutionSummary:
    """Run every unfinished run of ``plan`` (see the module docstring).

    :param max_new_runs: stop submitting after this many runs were started (tests use it to
        simulate an interrupted study); None = all.
    """
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ValueError(f"jobs={jobs!r} is not allowed: expected an integer >= 1")
    ids = [spec.run_id for spec in plan]
    if len(set(ids)) != len(ids):
        raise ValueError("the plan has duplicate run ids")
    by_id = {spec.run_id: spec for spec in plan}
    for spec in plan:
        for dep in spec.deps:
            if dep not in by_id:
                raise ValueError(
                    f"run {spec.run_id!r} depends on {dep!r}, which is not in the plan"
                )
    summary = ExecutionSummary()
    start = time.time()
    finished: set[str] = set()
    for spec in plan:
        if store.is_done(spec):
            finished.add(spec.run_id)
            summary.skipped_finished.append(spec.run_id)
    pending = [spec for spec in plan if spec.run_id not in finished]
    bar = _progress(len(plan), len(finished), quiet)
    running: dict[Future, str] = {}
    started = 0
    ctx = mp.get_context("spawn")
    try:
        with ProcessPoolExecutor(max_workers=jobs, mp_context=ctx) as pool:
            while pending or running:
                # block runs whose dependency failed (transitively)
                for spec in list(pending):
                    bad = [d for d in spec.deps if d in summary.failed or d in summary.blocked]
                    if bad:
                        summary.blocked[spec.run_id] = bad[0]
                        pending.remove(spec)
                        bar.update(1)
                ready = [s for s in pending if all(d in finished for d in s.deps)]
                for spec in ready:
                    if len(running) >= jobs:
                        break
                    if max_new_runs is not None and started >= max_new_runs:
                        break
                    try:
                        future = pool.submit(run_one, work, spec.to_dict(), os.fspath(store.out))
                    except BrokenProcessPool as exc:  # a worker died: this run cannot start
                        summary.failed[spec.run_id] = f"worker pool broken: {exc}"
                        store.fail(spec, None, summary.failed[spec.run_id])
                        pending.remove(spec)
                        bar.update(1)
                        continue
                    running[future] = spec.run_id
                    pending.remove(spec)
                    started += 1
                bar.set_postfix_str(f"running: {', '.join(sorted(running.values()))}"[:120])
                if not running:
                    break  # nothing can start (limit reached or all blocked)
                done, _ = wait(list(running), return_when=FIRST_COMPLETED)
                for future in done:
                    run_id = running.pop(future)
                    try:
                        _, status, error = future.result()
                    except BaseException as exc:  # noqa: BLE001 - a worker died
                        status, error = "failed", f"worker process failed: {exc!r}"
                        store.fail(by_id[run_id], None, error)
                    if status == "failed":
                        summary.failed[run_id] = error
                        if not quiet:
                            bar.write(f"run {run_id} FAILED: {error.strip().splitlines()[-1]}")
                    else:
                        finished.add(run_id)
                        summary.done.append(run_id)
                    bar.update(1)
    except KeyboardInterrupt:  # the pool has let its runs in flight end (module docstring)
        summary.stopped = True
    finally:
        bar.close()
    summary.wall_s = time.time() - start
    return summary
