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
can record the session; running the same command again resumes. SIGTERM to the main process
stops it the same way (a study started in the background from a script ignores SIGINT, and
schedulers end jobs with SIGTERM); its runs in flight finish and commit first.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import signal
import threading
import time
import traceback
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from sb3_pnn.reproduce.planning.plan import RunSpec
from sb3_pnn.reproduce.running.store import RunStore
from sb3_pnn.reproduce.running.worker_init import init_worker, run_manifest

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

    def session_record(self, started: float, jobs: int, executor: str = "local") -> dict[str, Any]:
        """What sessions.json keeps of this invocation (started: its ``time.time()``)."""
        record: dict[str, Any] = {
            "started": started,
            "wall_s": time.time() - started,
            "jobs": jobs,
            "executor": executor,
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


def run_one(work: WorkFn, spec_data: dict[str, Any], out: str) -> tuple[str, str, str]:
    """Do one run in this process and commit it; returns (run_id, status, error text)."""
    init_worker()
    spec = RunSpec.from_dict(spec_data)
    store = RunStore(out)
    tmp = None
    started = time.time()
    cpu_started = time.process_time()
    try:
        tmp = store.begin(spec)
        deps = {dep: store.run_dir(dep) for dep in spec.deps}
        extra = work(spec, tmp, deps)
        manifest = run_manifest(extra, spec.seed, started, cpu_started)
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
        bar_format=("{desc}: {n_fmt}/{total_fmt} done |{bar}| elapsed {elapsed} {postfix}"),
        dynamic_ncols=True,
    )


class LocalPool:
    """Runs in a local process pool (``spawn`` context); each run commits itself in its worker
    (:func:`run_one`), so that a run orphaned by a killed study still commits or leaves
    nothing."""

    def __init__(self, store: RunStore, work: WorkFn, jobs: int) -> None:
        self.store, self.work = store, work
        self._pool = ProcessPoolExecutor(max_workers=jobs, mp_context=mp.get_context("spawn"))

    def submit(self, spec: RunSpec) -> Future:
        return self._pool.submit(run_one, self.work, spec.to_dict(), os.fspath(self.store.out))

    def wait(self, handles: list[Any]) -> list[Any]:
        done, _ = wait(handles, return_when=FIRST_COMPLETED)
        return list(done)

    def outcome(self, handle: Future, spec: RunSpec) -> tuple[str, str]:
        """(status, error) of a finished run: "done", "kept_existing" or "failed".

        A worker that died after its commit (Ctrl-C reaches the workers too, and one interrupted
        while it sends its result back breaks the pool) still finished its run: the store, not
        the lost report, decides."""
        try:
            _, status, error = handle.result()
        except BaseException as exc:  # noqa: BLE001 - a worker died
            if self.store.manifest(spec.run_id) is not None:
                return "done", ""
            status, error = "failed", f"worker process failed: {exc!r}"
            self.store.fail(spec, None, error)
        return status, error

    def close(self) -> None:
        self._pool.shutdown(wait=True, cancel_futures=True)

    def ended_in_flight(self, handles: list[Any]) -> list[Any]:
        """After Ctrl-C and :meth:`close`: the runs in flight whose worker ended them (each
        committed or recorded its run itself), so that the session counts them."""
        return [h for h in handles if h.done() and not h.cancelled()]


class _Schedule:
    """The state of one invocation: which runs are pending, running and finished."""

    def __init__(self, plan: list[RunSpec], store: RunStore, quiet: bool) -> None:
        self.by_id = {spec.run_id: spec for spec in plan}
        self.summary = ExecutionSummary()
        planned = {spec.run_id: spec.config_hash() for spec in plan}
        self.finished = {spec.run_id for spec in plan if store.is_done(spec, planned)}
        self.summary.skipped_finished = [s.run_id for s in plan if s.run_id in self.finished]
        self.pending = [spec for spec in plan if spec.run_id not in self.finished]
        self.running: dict[Any, str] = {}
        self.started = 0
        self.quiet = quiet
        self.bar = _progress(len(plan), len(self.finished), quiet)
        self.t0 = time.time()
        self.episodes_left = sum(spec.episodes for spec in self.pending)
        self.episodes_done = 0

    def eta(self) -> str:
        """The time left, from the episodes this invocation has finished so far (runs differ
        tenfold in length, so counting runs, as a plain progress bar does, misleads; before the
        first run ends there is nothing to go on)."""
        if self.episodes_done == 0:
            return "eta after the first run"
        rate = self.episodes_done / max(time.time() - self.t0, 1e-9)
        left = int(self.episodes_left / rate)
        return f"eta {left // 3600}:{left % 3600 // 60:02d}:{left % 60:02d}"

    def block_failed_dependents(self) -> None:
        """Skip (transitively) the runs whose dependency failed."""
        summary = self.summary
        for spec in list(self.pending):
            bad = [d for d in spec.deps if d in summary.failed or d in summary.blocked]
            if bad:
                summary.blocked[spec.run_id] = bad[0]
                self.pending.remove(spec)
                self.episodes_left -= spec.episodes
                self.bar.update(1)

    def ready(self) -> list[RunSpec]:
        return [s for s in self.pending if all(d in self.finished for d in s.deps)]

    def settle(self, run_id: str, status: str, error: str) -> None:
        episodes = self.by_id[run_id].episodes
        self.episodes_left -= episodes
        self.episodes_done += episodes if status != "failed" else 0
        if status == "failed":
            self.summary.failed[run_id] = error
            if not self.quiet:
                self.bar.write(f"run {run_id} FAILED: {error.strip().splitlines()[-1]}")
        else:
            self.finished.add(run_id)
            self.summary.done.append(run_id)
        self.bar.update(1)

    def count_committed(self, store: RunStore) -> None:
        """After Ctrl-C: count as done every run of this invocation that the store holds
        committed, also one whose report the interrupt cut off (between a worker's commit and
        the bookkeeping here), so that the session counts what it left behind."""
        for run_id in self.by_id:
            if run_id in self.finished or store.manifest(run_id) is None:
                continue
            self.summary.failed.pop(run_id, None)
            self.finished.add(run_id)
            self.summary.done.append(run_id)
            for handle in [h for h, running_id in self.running.items() if running_id == run_id]:
                del self.running[handle]


def _check_plan(plan: list[RunSpec], jobs: int) -> None:
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ValueError(f"jobs={jobs!r} is not allowed: expected an integer >= 1")
    ids = [spec.run_id for spec in plan]
    if len(set(ids)) != len(ids):
        raise ValueError("the plan has duplicate run ids")
    known = set(ids)
    for spec in plan:
        for dep in spec.deps:
            if dep not in known:
                raise ValueError(
                    f"run {spec.run_id!r} depends on {dep!r}, which is not in the plan"
                )


def _launch(schedule: _Schedule, pool: Any, jobs: int, max_new_runs: int | None) -> None:
    """Submit ready runs while fewer than ``jobs`` are running."""
    for spec in schedule.ready():
        if len(schedule.running) >= jobs:
            break
        if max_new_runs is not None and schedule.started >= max_new_runs:
            break
        schedule.pending.remove(spec)
        try:
            handle = pool.submit(spec)
        except BrokenProcessPool as exc:  # a worker died: this run cannot start
            error = f"worker pool broken: {exc}"
            pool.store.fail(spec, None, error)
            schedule.settle(spec.run_id, "failed", error)
            continue
        schedule.running[handle] = spec.run_id
        schedule.started += 1


@contextmanager
def _sigterm_stops() -> Iterator[None]:
    """While inside: SIGTERM raises ``KeyboardInterrupt`` in the main thread (module
    docstring); elsewhere, or outside, signals keep their handlers."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum: int, frame: Any) -> None:
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, stop)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def execute(
    plan: list[RunSpec],
    store: RunStore,
    work: WorkFn,
    jobs: int,
    quiet: bool = False,
    max_new_runs: int | None = None,
    pool: Any = None,
) -> ExecutionSummary:
    """Run every unfinished run of ``plan`` (see the module docstring).

    :param pool: where the runs run: None for a :class:`LocalPool` of ``jobs`` processes, or
        another pool with the same methods (:class:`sb3_pnn.reproduce.running.ray_pool.RayPool`),
        of which at most ``jobs`` runs are in flight
    :param max_new_runs: stop submitting after this many runs were started (tests use it to
        simulate an interrupted study); None = all.
    """
    _check_plan(plan, jobs)
    with _sigterm_stops():
        return _execute(plan, store, work, jobs, quiet, max_new_runs, pool)


def _execute(
    plan: list[RunSpec],
    store: RunStore,
    work: WorkFn,
    jobs: int,
    quiet: bool,
    max_new_runs: int | None,
    pool: Any,
) -> ExecutionSummary:
    start = time.time()
    schedule = _Schedule(plan, store, quiet)
    try:
        pool = pool if pool is not None else LocalPool(store, work, jobs)
        try:
            while schedule.pending or schedule.running:
                schedule.block_failed_dependents()
                _launch(schedule, pool, jobs, max_new_runs)
                names = ", ".join(sorted(schedule.running.values()))
                schedule.bar.set_postfix_str(f"{schedule.eta()}; running: {names}"[:140])
                if not schedule.running:
                    break  # nothing can start (limit reached or all blocked)
                for handle in pool.wait(list(schedule.running)):
                    run_id = schedule.running.pop(handle)
                    schedule.settle(run_id, *pool.outcome(handle, schedule.by_id[run_id]))
        finally:
            pool.close()
    except KeyboardInterrupt:  # the runs in flight have ended or been cancelled (docstring)
        schedule.summary.stopped = True
        ended = getattr(pool, "ended_in_flight", None)
        for handle in ended(list(schedule.running)) if ended is not None else []:
            run_id = schedule.running.pop(handle)
            schedule.settle(run_id, *pool.outcome(handle, schedule.by_id[run_id]))
        schedule.count_committed(store)
    finally:
        schedule.bar.close()
    schedule.summary.wall_s = time.time() - start
    return schedule.summary


def add_executor_arguments(parser: Any) -> None:
    """``--jobs``, ``--executor`` and ``--ray-address`` of the study and ablation commands."""
    from sb3_pnn.common.checks import positive_int

    parser.add_argument(
        "--jobs",
        type=positive_int("--jobs"),
        default=None,
        help="runs in parallel (default: this machine's cores; with --executor ray, the "
        "cluster's CPUs)",
    )
    parser.add_argument(
        "--executor",
        choices=("local", "ray"),
        default="local",
        help="where the runs run: a local process pool (default) or a Ray cluster (one task "
        "per run; pip install 'sb3-pnn[ray]'; see docs/ray.md)",
    )
    parser.add_argument(
        "--ray-address",
        default=None,
        metavar="ADDRESS",
        help="with --executor ray: the cluster's head, HOST:PORT (default: a Ray instance of "
        "this machine's cores)",
    )


def pool_from_arguments(args: Any, store: RunStore, work: WorkFn) -> tuple[Any, int]:
    """(the pool ``args`` ask for, None for the local pool; the runs to keep in flight).
    Joins the Ray cluster here, before any run starts; ``RayUnavailableError`` (a
    ``RuntimeError``) names why it cannot."""
    if args.executor == "local":
        if args.ray_address is not None:
            from sb3_pnn.reproduce.running.ray_pool import RayUnavailableError

            raise RayUnavailableError("--ray-address goes with --executor ray")
        return None, args.jobs or os.cpu_count() or 1
    from sb3_pnn.reproduce.running.ray_pool import RayPool, connect

    ray = connect(args.ray_address)
    cpus = int(ray.cluster_resources().get("CPU", 1))
    return RayPool(store, work, ray), args.jobs or cpus
