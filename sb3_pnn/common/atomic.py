"""Writing files so that a failed write leaves the previous file intact.

Every file sb3_pnn writes (models, replay buffers, study records, reports, figures, videos) goes
through :func:`write_atomic`: the content is written to a temporary file beside the target,
flushed to disk (``fsync``), then renamed over the target in one step (``os.replace``). A full
disk, a crash or Ctrl-C during the write leaves the old file as it was, and no half-written file
under the target's name. :func:`check_writable` lets a command refuse an output path before it
spends time on the work.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable
from pathlib import Path


def _temporary(path: Path) -> Path:
    return path.with_name(f".{path.name}.tmp-{os.getpid()}")


def write_atomic(path: str | os.PathLike[str], write: Callable[[Path], None]) -> Path:
    """``write(tmp)`` writes the content to the path ``tmp``; it then replaces ``path``.

    Parent folders are created. On any failure the temporary file is removed, the target is
    left as it was, and the error propagates. Returns ``path``.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = _temporary(path)
    try:
        write(tmp)
        fd = os.open(tmp, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise
    return path


def write_bytes_atomic(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (see :func:`write_atomic`)."""
    return write_atomic(path, lambda tmp: tmp.write_bytes(data))


def write_text_atomic(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically (see :func:`write_atomic`)."""
    return write_bytes_atomic(path, text.encode("utf-8"))


def check_writable(path: str | os.PathLike[str]) -> Path:
    """``path`` as a ``Path`` if a file can be written there; ``ValueError`` naming the path and
    why not (a folder, a parent that is a file, a folder without write permission)."""
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{str(path)!r} is a folder: expected a file path")
    parent = path.parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise ValueError(f"{str(path)!r} cannot be written: {str(parent)!r} is not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ValueError(f"{str(path)!r} cannot be written: no write permission in {str(parent)!r}")
    return path


def check_writable_folder(path: str | os.PathLike[str]) -> Path:
    """``path`` as a ``Path`` if it is, or can be created as, a folder to write into;
    ``ValueError`` naming the path and why not."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{str(path)!r} is a file: expected a folder")
    existing = path
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        raise ValueError(f"{str(path)!r} cannot be created: {str(existing)!r} is not a folder")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise ValueError(
            f"{str(path)!r} cannot be written: no write permission in {str(existing)!r}"
        )
    return path
