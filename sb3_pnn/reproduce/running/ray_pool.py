"""Runs of a study as Ray tasks, for a cluster (``--executor ray``; ``pip install sb3-pnn[ray]``).

Each run is one Ray task with ``num_cpus=1`` (:func:`remote_run`): the worker gets the run's
spec and the files of the runs it depends on (the priors' folders, sent through Ray's object
store, so no shared filesystem is needed), does the run's work in a temporary folder of its own,
and sends back the folder's files and the run's manifest. The driver commits them into the study
folder through the same :class:`~sb3_pnn.reproduce.running.store.RunStore` the local pool uses
(temporary folder, manifest with the config hash, atomic rename): a study started on Ray can be
finished locally and the other way round, and ``--report-only`` reads either. Dependencies stay
with the driver's scheduler (:func:`sb3_pnn.reproduce.running.executor.execute`): a run is
submitted once its priors are committed.

A task whose worker dies (a node lost, a process killed) is retried once by Ray
(``max_retries=1``); if that fails too, the run is recorded as failed, like a run that raised.
Runs finished and committed are never redone. Ctrl-C cancels the tasks in flight; the same
command resumes.
"""

from __future__ import annotations

import os
import socket
import tempfile
import time
from pathlib import Path
from typing import Any

from sb3_pnn.reproduce.planning.plan import RunSpec
from sb3_pnn.reproduce.running.store import RunStore
from sb3_pnn.reproduce.running.worker_init import init_worker, run_manifest

#: The Ray release this package is tested with (``pip install sb3-pnn[ray]`` pins it).
RAY_VERSION = "2.60.0"
#: Seconds to wait for a TCP connection to a cluster address before calling it unreachable
#: (``ray.init`` itself would retry for minutes).
CONNECT_TIMEOUT_S = 5.0


class RayUnavailableError(RuntimeError):
    """Ray cannot run the study: not installed, no cluster at the address, or no free CPU."""


def _files(folder: Path) -> dict[str, bytes]:
    """Every file below ``folder``, by relative path."""
    return {
        os.fspath(path.relative_to(folder)): path.read_bytes()
        for path in sorted(folder.rglob("*"))
        if path.is_file()
    }


def _write_files(folder: Path, files: dict[str, bytes]) -> None:
    """Write ``files`` (relative path -> bytes) below ``folder``, refusing any path that would
    leave it."""
    root = folder.resolve()
    for name, data in files.items():
        target = (folder / name).resolve()
        if root not in target.parents:
            raise ValueError(f"a run's file {name!r} lies outside its folder")
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(data)


def run_remotely(
    work: Any, spec_data: dict[str, Any], dep_names: list[str], *dep_files: dict[str, bytes]
) -> tuple[str, dict[str, bytes], dict[str, Any]]:
    """What a Ray task does: the run's work in a temporary folder of its own, the files of the
    runs it depends on (``dep_files[i]`` those of ``dep_names[i]``; top-level arguments, so that
    Ray hands over their objects) written beside it; returns (error text, "" if none; the
    output files; the manifest fields the worker measured). Importable without Ray."""
    import traceback

    init_worker()
    spec = RunSpec.from_dict(spec_data)
    started, cpu_started = time.time(), time.process_time()
    with tempfile.TemporaryDirectory(prefix=f"sb3pnn-{spec.run_id}-") as scratch:
        root = Path(scratch)
        deps = {}
        for dep, files in zip(dep_names, dep_files, strict=True):
            deps[dep] = root / "deps" / dep
            deps[dep].mkdir(parents=True)
            _write_files(deps[dep], files)
        out = root / "out"
        out.mkdir()
        try:
            extra = work(spec, out, deps)
        except BaseException:  # noqa: BLE001 - reported to the driver, which records it
            return traceback.format_exc(), {}, {}
        manifest = {
            **run_manifest(extra, spec.seed, started, cpu_started),
            "host": socket.gethostname(),
        }
        return "", _files(out), manifest


def _check_address(address: str) -> None:
    """Refuse an address no cluster answers at, quickly (before ``ray.init`` would hang)."""
    if address in ("auto", "local"):
        return
    target = address.split("://", 1)[-1]
    host, sep, port = target.rpartition(":")
    if not sep or not port.isdigit():
        raise RayUnavailableError(
            f"--ray-address {address!r} is not allowed: expected HOST:PORT (the head node's "
            "GCS port, 6379 by default), ray://HOST:PORT or auto"
        )
    try:
        with socket.create_connection((host, int(port)), timeout=CONNECT_TIMEOUT_S):
            pass
    except OSError as error:
        raise RayUnavailableError(
            f"--ray-address {address!r}: no Ray cluster answers there ({error}); start one with "
            "`ray start --head` (see docs/ray.md)"
        ) from None


def connect(address: str | None, num_cpus: int | None = None) -> Any:
    """Import Ray and join the cluster at ``address`` (None: start a local Ray instance with
    ``num_cpus``), refusing with :class:`RayUnavailableError` when Ray is missing, the address
    is unreachable or the cluster has no CPU to give a run."""
    try:
        import ray
    except ImportError:
        raise RayUnavailableError(
            f"--executor ray needs Ray: pip install 'sb3-pnn[ray]' (ray=={RAY_VERSION})"
        ) from None
    if address is not None:
        _check_address(address)
    if not ray.is_initialized():
        kwargs: dict[str, Any] = {"log_to_driver": False, "include_dashboard": False}
        if address is not None:
            kwargs["address"] = address
        else:
            kwargs["num_cpus"] = num_cpus
        try:
            ray.init(**kwargs)
        except (ConnectionError, RuntimeError, ValueError) as error:
            raise RayUnavailableError(f"Ray could not start or connect: {error}") from None
    cpus = ray.cluster_resources().get("CPU", 0.0)
    if cpus < 1:
        raise RayUnavailableError(
            f"the Ray cluster has {cpus:g} CPUs: each run needs one (num_cpus=1)"
        )
    return ray


class RayPool:
    """The executor's pool for Ray (see the module docstring)."""

    def __init__(self, store: RunStore, work: Any, ray: Any) -> None:
        self.store, self.work, self.ray = store, work, ray
        self._task = ray.remote(num_cpus=1, max_retries=1)(run_remotely)
        self._dep_refs: dict[str, Any] = {}
        self._specs: dict[Any, RunSpec] = {}

    def _dep_ref(self, dep: str) -> Any:
        """The files of a committed run, put in Ray's object store once for all its users."""
        if dep not in self._dep_refs:
            self._dep_refs[dep] = self.ray.put(_files(self.store.run_dir(dep)))
        return self._dep_refs[dep]

    def submit(self, spec: RunSpec) -> Any:
        refs = [self._dep_ref(dep) for dep in spec.deps]
        ref = self._task.remote(self.work, spec.to_dict(), list(spec.deps), *refs)
        self._specs[ref] = spec
        return ref

    def wait(self, handles: list[Any]) -> list[Any]:
        done, _ = self.ray.wait(handles, num_returns=1)
        return done

    def outcome(self, handle: Any, spec: RunSpec) -> tuple[str, str]:
        """Commit the run the task sent back, as the local pool's workers do."""
        self._specs.pop(handle, None)
        try:
            error, files, manifest = self.ray.get(handle)
        except Exception as exc:  # noqa: BLE001 - the worker died twice, or Ray failed
            error, files, manifest = f"Ray task failed: {exc!r}", {}, {}
        if error:
            self.store.fail(spec, None, error)
            return "failed", error
        tmp = self.store.begin(spec)
        try:
            _write_files(tmp, files)
        except (OSError, ValueError) as exc:
            message = f"cannot write the run's files: {exc!r}"
            self.store.fail(spec, tmp, message)
            return "failed", message
        committed = self.store.commit(spec, tmp, manifest)
        return ("done" if committed else "kept_existing"), ""

    def close(self) -> None:
        """Cancel what is still in flight (Ctrl-C): those runs are simply run again later."""
        for ref in list(self._specs):
            try:
                self.ray.cancel(ref, force=True)
            except Exception:  # noqa: BLE001, S110 - the task may have ended meanwhile
                pass
        self._specs.clear()
