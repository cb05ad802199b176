"""Reading a checkpoint-like file from a path or a binary file object (shared by the loaders)."""

from __future__ import annotations

import io
import os
import pathlib


def read_file_bytes(
    path: str | os.PathLike[str] | io.BufferedIOBase, suffix: str, what: str, noun: str
) -> tuple[io.BytesIO, str]:
    """The file's bytes and a name for messages.

    As SB3 does, a path without suffix also finds ``<path>.<suffix>``. ``what`` names the kind of
    file in errors ("DiscreteSAC checkpoint", "replay buffer file"): a missing path raises
    ``FileNotFoundError`` naming it; anything that is neither a path nor readable raises
    ``ValueError`` ("expected a <noun> path or binary file object").
    """
    if isinstance(path, (str, os.PathLike)):
        p = pathlib.Path(path)
        if not p.is_file() and p.suffix == "" and pathlib.Path(f"{p}.{suffix}").is_file():
            p = pathlib.Path(f"{p}.{suffix}")
        if not p.is_file():
            raise FileNotFoundError(f"{what} {str(path)!r} does not exist")
        return io.BytesIO(p.read_bytes()), str(p)
    if hasattr(path, "read"):
        return io.BytesIO(path.read()), repr(path)
    raise ValueError(f"expected a {noun} path or binary file object, got {path!r:.100}")
