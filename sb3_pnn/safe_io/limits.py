"""Bounds on what the loaders read from a file they cannot trust.

A checkpoint, prior or replay buffer may come from anyone. Before the loaders read a member of
a zip archive they check its declared sizes (:func:`read_member`): a small file whose member
inflates to gigabytes, or a JSON document nested a hundred thousand levels deep
(:func:`parse_json`), is refused with a ``ValueError`` naming the file and the member, not
answered with exhausted memory or a ``RecursionError``. The limits are far above what this
package writes (a model with [255, 255] networks is about 2 MB, its JSON member a few kB).
"""

from __future__ import annotations

import json
import zipfile
import zlib
from typing import Any

#: Largest checkpoint or prior file read (bytes).
#: What zipfile raises on a damaged archive: BadZipFile, and, from a flipped header field or a
#: corrupt member, NotImplementedError (an unsupported zip version or compression method) and
#: zlib.error (a broken deflate stream). The loaders turn each into a ValueError naming the file.
ZIP_DAMAGE: tuple[type[Exception], ...] = (zipfile.BadZipFile, NotImplementedError, zlib.error)

MAX_CHECKPOINT_BYTES = 1 << 30
#: Largest JSON member read from a checkpoint (``sb3_pnn.json``, SB3's ``data``), uncompressed.
MAX_JSON_BYTES = 16 << 20
#: Largest total of the weights members (``*.pth``) read from a checkpoint, uncompressed.
MAX_WEIGHTS_BYTES = 1 << 30
#: Largest replay buffer file read, and largest total of its arrays, uncompressed (bytes).
MAX_BUFFER_BYTES = 64 << 30
#: Deepest nesting accepted in a JSON document.
MAX_JSON_DEPTH = 64


def check_file_size(size: int, limit: int, name: str, what: str) -> None:
    """Refuse a file of ``size`` bytes above ``limit``."""
    if size > limit:
        raise ValueError(
            f"{name!r} is {size} bytes: larger than any {what} this package writes "
            f"(at most {limit} bytes are read)"
        )


def member_sizes(archive: zipfile.ZipFile, names: list[str], limit: int, where: str) -> int:
    """The total uncompressed size of ``names`` in ``archive``, refused above ``limit``."""
    total = sum(archive.getinfo(n).file_size for n in names)
    if total > limit:
        raise ValueError(
            f"{where}: members {names[:4]} inflate to {total} bytes: more than the {limit} bytes "
            "accepted (a corrupt or hostile file)"
        )
    return total


def read_member(archive: zipfile.ZipFile, name: str, limit: int, where: str) -> bytes:
    """The bytes of member ``name``, its declared uncompressed size checked first (zipfile
    never returns more than that size)."""
    member_sizes(archive, [name], limit, where)
    try:
        return archive.read(name)
    except (*ZIP_DAMAGE, OSError, EOFError, ValueError) as error:
        raise ValueError(f"{where}: member {name!r} is corrupt ({error})") from None


def _depth(value: Any) -> int:
    """Nesting depth of a parsed JSON value (iterative: no recursion limit)."""
    deepest, stack = 0, [(value, 1)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, dict):
            deepest = max(deepest, depth)
            stack.extend((v, depth + 1) for v in item.values())
        elif isinstance(item, list):
            deepest = max(deepest, depth)
            stack.extend((v, depth + 1) for v in item)
    return deepest


def parse_json(raw: bytes, where: str) -> Any:
    """``raw`` (UTF-8 JSON) parsed, nesting at most :data:`MAX_JSON_DEPTH` deep."""
    try:
        value = json.loads(raw.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise ValueError(f"{where} is not valid JSON ({error})") from None
    except RecursionError:
        raise ValueError(f"{where}: JSON nested too deep (a corrupt or hostile file)") from None
    if _depth(value) > MAX_JSON_DEPTH:
        raise ValueError(
            f"{where}: JSON nested deeper than {MAX_JSON_DEPTH} levels (a corrupt or hostile file)"
        )
    return value


#: Widest hidden layer, and most hidden layers, accepted in a stored network architecture.
MAX_LAYER_WIDTH = 4096
MAX_LAYERS = 16


def check_widths(widths: Any, where: str) -> list[int]:
    """A stored list of hidden-layer widths: ints in [1, :data:`MAX_LAYER_WIDTH`], at most
    :data:`MAX_LAYERS` of them."""
    ok = (
        isinstance(widths, (list, tuple))
        and len(widths) <= MAX_LAYERS
        and all(isinstance(w, int) and not isinstance(w, bool) for w in widths)
        and all(1 <= w <= MAX_LAYER_WIDTH for w in widths)
    )
    if not ok:
        raise ValueError(
            f"{where}={widths!r:.100} is not allowed: expected at most {MAX_LAYERS} layer widths, "
            f"each an int in [1, {MAX_LAYER_WIDTH}]"
        )
    return list(widths)


def check_number(
    value: Any, where: str, low: float, high: float, integer: bool = False
) -> int | float:
    """A stored number (not a bool, not a string) in [low, high]; an int when ``integer``."""
    kinds = (int,) if integer else (int, float)
    if isinstance(value, bool) or not isinstance(value, kinds) or not low <= value <= high:
        kind = "an int" if integer else "a number"
        raise ValueError(
            f"{where}={value!r:.100} is not allowed: expected {kind} in [{low}, {high}]"
        )
    return value
