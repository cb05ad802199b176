"""Reading a checkpoint-like file from a path or a binary file object (shared by the loaders)."""

from __future__ import annotations

import io
import os
import pathlib

from sb3_pnn.common.atomic import write_bytes_atomic
from sb3_pnn.safe_io.limits import check_file_size


def read_file_bytes(
    path: str | os.PathLike[str] | io.BufferedIOBase,
    suffix: str,
    what: str,
    noun: str,
    limit: int,
) -> tuple[io.BytesIO, str]:
    """The file's bytes and a name for messages.

    As SB3 does, a path without suffix also finds ``<path>.<suffix>``. ``what`` names the kind of
    file in errors ("DiscreteSAC checkpoint", "replay buffer file"): a missing path raises
    ``FileNotFoundError`` naming it; anything that is neither a path nor readable, or a file
    larger than ``limit`` bytes (checked before reading), raises ``ValueError``.
    """
    if isinstance(path, (str, os.PathLike)):
        p = pathlib.Path(path)
        if not p.is_file() and p.suffix == "" and pathlib.Path(f"{p}.{suffix}").is_file():
            p = pathlib.Path(f"{p}.{suffix}")
        if not p.is_file():
            raise FileNotFoundError(f"{what} {str(path)!r} does not exist")
        check_file_size(p.stat().st_size, limit, str(p), what)
        return io.BytesIO(p.read_bytes()), str(p)
    if hasattr(path, "read"):
        data = path.read(limit + 1)
        check_file_size(len(data), limit, repr(path), what)
        return io.BytesIO(data), repr(path)
    raise ValueError(f"expected a {noun} path or binary file object, got {path!r:.100}")


def write_checkpoint_bytes(
    path: str | os.PathLike[str] | io.BufferedIOBase, data: bytes, suffix: str
) -> None:
    """Write a whole checkpoint-like file: to a path atomically (a failed write leaves the
    previous file intact; as SB3 does, a path without suffix gets ``.<suffix>``), or into a
    binary file object."""
    if isinstance(path, (str, os.PathLike)):
        p = pathlib.Path(path)
        if p.suffix == "":
            p = p.with_suffix(f".{suffix}")
        write_bytes_atomic(p, data)
    elif hasattr(path, "write"):
        path.write(data)
    else:
        raise ValueError(f"expected a path or binary file object to write to, got {path!r:.100}")
