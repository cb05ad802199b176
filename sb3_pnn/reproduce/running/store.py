"""Resume bookkeeping: where each run's outputs live, and how they are committed.

Layout under the study folder ``OUT``::

    OUT/runs/<run_id>/manifest.json      written last, inside the folder, before the rename
    OUT/runs/<run_id>/...                the run's files (model.zip, episodes.json, eval.json ...)
    OUT/runs/.tmp-<run_id>-<pid>-<ns>/   a run in progress (removed or renamed when it ends)
    OUT/failures/<run_id>.json           the last failure of a run that has not finished yet
    OUT/.lock                            held (flock) while a study runs in OUT

A run writes everything into its temporary folder, then the folder is renamed to
``runs/<run_id>`` in one ``os.rename``, which is atomic and refuses to replace a non-empty
folder: a finished run is never overwritten, and a killed study leaves only temporary folders,
which the next start removes. On restart a run whose folder exists is skipped when its manifest's
``config_hash`` equals the planned one, and is an error otherwise (use another ``--out``). A
run's manifest also records the ``config_hash`` of each prior it read (``deps_hashes``), so a
run whose prior was removed and trained again with another configuration is an error too,
not a result silently paired with a column it never read.
"""

from __future__ import annotations

import errno
import fcntl
import json
import os
import shutil
import time
from pathlib import Path
from typing import Any

from sb3_pnn.common.atomic import write_text_atomic
from sb3_pnn.reproduce.planning.plan import RunSpec

MANIFEST = "manifest.json"


class StudyConflictError(RuntimeError):
    """A finished run in the output folder was made with a different configuration."""


def write_json_atomic(path: Path, data: Any) -> None:
    """Write JSON to ``path`` atomically (:func:`sb3_pnn.common.atomic.write_atomic`)."""
    write_text_atomic(path, json.dumps(data, indent=1, sort_keys=True, default=_json_default))


def open_store_or_exit(parser: Any, out: Path) -> RunStore:
    """Open (and lock) the output folder ``out`` of a command line, or exit through
    ``parser.error`` with a one-line message (status 2)."""
    if out.exists() and not out.is_dir():
        parser.error(f"--out {os.fspath(out)!r} exists and is not a folder")
    store = RunStore(out)
    try:
        store.open()
    except (PermissionError, RuntimeError) as error:
        parser.error(str(error))
    return store


def _json_default(value: Any) -> Any:
    if hasattr(value, "tolist"):
        return value.tolist()
    if hasattr(value, "item"):
        return value.item()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


class RunStore:
    """The runs of one study folder (see the module docstring)."""

    def __init__(self, out: str | os.PathLike[str]) -> None:
        self.out = Path(out)
        self.runs_dir = self.out / "runs"
        self.failures_dir = self.out / "failures"
        self._lock_file: Any = None

    # ---- set-up ----
    def open(self) -> None:
        """Create the folders, take the study lock and remove leftovers of killed runs."""
        try:
            self.runs_dir.mkdir(parents=True, exist_ok=True)
            self.failures_dir.mkdir(exist_ok=True)
            probe = self.out / f".write-probe-{os.getpid()}"
            probe.write_text("ok")
            probe.unlink()
        except OSError as error:
            why = error.strerror or error
            raise PermissionError(
                f"--out {os.fspath(self.out)!r} is not a writable folder ({why})"
            ) from None
        self._lock_file = open(self.out / ".lock", "w")  # noqa: SIM115 - held until close()
        try:
            fcntl.flock(self._lock_file, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self._lock_file.close()
            self._lock_file = None
            raise RuntimeError(
                f"another study is running in {os.fspath(self.out)!r} (its .lock is held)"
            ) from None
        for leftover in self.runs_dir.glob(".tmp-*"):
            shutil.rmtree(leftover, ignore_errors=True)

    def close(self) -> None:
        if self._lock_file is not None:
            self._lock_file.close()
            self._lock_file = None

    # ---- queries ----
    def run_dir(self, run_id: str) -> Path:
        return self.runs_dir / run_id

    def manifest(self, run_id: str) -> dict[str, Any] | None:
        path = self.run_dir(run_id) / MANIFEST
        if not path.is_file():
            return None
        return json.loads(path.read_text())

    def is_done(self, spec: RunSpec, planned: dict[str, str] | None = None) -> bool:
        """True when ``spec`` finished earlier; raises when it finished with another config, or
        (with ``planned``, the plan's ``config_hash`` by run id) on a prior whose planned
        configuration differs from the one it read."""
        folder = self.run_dir(spec.run_id)
        if not folder.exists():
            return False
        manifest = self.manifest(spec.run_id)
        if manifest is None:
            raise StudyConflictError(
                f"{os.fspath(folder)!r} exists but has no {MANIFEST}; it was not written by this "
                "study runner: remove it or choose another --out"
            )
        if manifest.get("config_hash") != spec.config_hash():
            raise StudyConflictError(
                f"run {spec.run_id!r} in {os.fspath(self.out)!r} was made with another "
                f"configuration (hash {manifest.get('config_hash')} != {spec.config_hash()}); "
                "finished results are never overwritten: choose another --out for a changed study"
            )
        for dep, read in (manifest.get("deps_hashes") or {}).items():
            if planned and dep in planned and read != planned[dep]:
                raise StudyConflictError(
                    f"run {spec.run_id!r} in {os.fspath(self.out)!r} was trained on prior "
                    f"{dep!r} with configuration hash {read}, but the plan's {dep!r} has hash "
                    f"{planned[dep]}; finished results are never overwritten: choose another "
                    "--out for a changed study"
                )
        return True

    # ---- a run's life ----
    def begin(self, spec: RunSpec) -> Path:
        """A fresh temporary folder for ``spec``'s outputs."""
        tmp = self.runs_dir / f".tmp-{spec.run_id}-{os.getpid()}-{time.time_ns()}"
        tmp.mkdir(parents=True)
        return tmp

    def commit(self, spec: RunSpec, tmp: Path, manifest: dict[str, Any]) -> bool:
        """Write the manifest into ``tmp`` and rename it into place.

        Returns False (and discards ``tmp``) when the run's folder already exists, e.g. because a
        run orphaned by a killed study finished meanwhile: the existing result is kept.
        """
        manifest = {**manifest, "run_id": spec.run_id, "config_hash": spec.config_hash()}
        if spec.deps:  # what each prior read was (is_done checks it against the plan)
            manifest["deps_hashes"] = {
                dep: (self.manifest(dep) or {}).get("config_hash") for dep in spec.deps
            }
        manifest.setdefault("status", "done")
        manifest["spec"] = spec.to_dict()
        write_json_atomic(tmp / MANIFEST, manifest)
        try:
            os.rename(tmp, self.run_dir(spec.run_id))
        except OSError as error:
            if error.errno in (errno.ENOTEMPTY, errno.EEXIST):
                shutil.rmtree(tmp, ignore_errors=True)
                return False
            raise
        failure = self.failures_dir / f"{spec.run_id}.json"
        if failure.exists():
            failure.unlink()
        return True

    def fail(self, spec: RunSpec, tmp: Path | None, error: str) -> None:
        """Record a failure (kept until the run succeeds) and drop the partial outputs."""
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        write_json_atomic(
            self.failures_dir / f"{spec.run_id}.json",
            {"run_id": spec.run_id, "config_hash": spec.config_hash(), "error": error,
             "time": time.time()},
        )  # fmt: skip

    def failures(self) -> dict[str, dict[str, Any]]:
        out: dict[str, dict[str, Any]] = {}
        if self.failures_dir.is_dir():
            for path in sorted(self.failures_dir.glob("*.json")):
                data = json.loads(path.read_text())
                out[data["run_id"]] = data
        return out
