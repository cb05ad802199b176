"""JSON codec for gymnasium spaces: Box, Discrete, MultiDiscrete, MultiBinary and Dict of them.

Bounds are stored as nested lists of Python floats (the exact value of each float32/float64
element; non-finite values as the strings "inf", "-inf", "nan"), so a decoded space compares
equal (``==``) to the encoded one. Decoding only calls the space constructors with numbers.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from typing import Any

import numpy as np
from gymnasium import spaces

from sb3_pnn.safe_io.limits import check_number

#: dtypes a decoded space may have (numpy names)
_DTYPES = {
    "float16", "float32", "float64", "int8", "int16", "int32", "int64",
    "uint8", "uint16", "uint32", "uint64", "bool",
}  # fmt: skip


def _num_list(array: np.ndarray) -> Any:
    def conv(v: Any) -> Any:
        if isinstance(v, list):
            return [conv(x) for x in v]
        if isinstance(v, float) and not math.isfinite(v):
            return repr(v)  # "inf", "-inf", "nan"
        return v

    return conv(np.asarray(array).tolist())


def _array(value: Any, dtype: str, shape: tuple[int, ...], where: str) -> np.ndarray:
    def conv(v: Any) -> Any:
        if isinstance(v, list):
            return [conv(x) for x in v]
        if isinstance(v, str) and v in ("inf", "-inf", "nan"):
            return float(v)
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            return v
        if isinstance(v, bool):
            return v
        raise ValueError(f"{where}: expected numbers, got {v!r}")

    arr = np.asarray(conv(value), dtype=np.float64 if dtype.startswith("float") else None)
    try:
        arr = arr.astype(dtype)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{where}: cannot read bounds as {dtype} ({e})") from e
    if arr.shape != shape:
        raise ValueError(f"{where}: bounds have shape {arr.shape}, expected {shape}")
    return arr


#: Most elements (product of the shape) a stored space may have, and most parts of a Dict.
MAX_ELEMENTS = 10**7
MAX_DICT_KEYS = 64


def _shape(value: Any, where: str) -> tuple[int, ...]:
    """A stored shape: at most 8 dimensions of ints >= 0 with at most ``MAX_ELEMENTS``."""
    if not isinstance(value, (list, tuple)) or len(value) > 8:
        raise ValueError(f"{where}: shape {value!r:.100} is not allowed: expected <= 8 dims")
    dims = tuple(check_number(d, f"{where} shape", 0, MAX_ELEMENTS, integer=True) for d in value)
    if math.prod(dims) > MAX_ELEMENTS:
        raise ValueError(f"{where}: shape {dims} has more than {MAX_ELEMENTS} elements")
    return dims


def space_to_json(space: spaces.Space) -> dict[str, Any]:
    """A JSON-able description of ``space`` (ValueError for unsupported space types)."""
    if isinstance(space, spaces.Box):
        return {
            "type": "Box",
            "shape": list(space.shape),
            "dtype": str(space.dtype),
            "low": _num_list(space.low),
            "high": _num_list(space.high),
        }
    if isinstance(space, spaces.Discrete):
        return {"type": "Discrete", "n": int(space.n), "start": int(space.start)}
    if isinstance(space, spaces.MultiDiscrete):
        return {
            "type": "MultiDiscrete",
            "nvec": np.asarray(space.nvec).tolist(),
            "start": np.asarray(space.start).tolist(),
            "dtype": str(space.dtype),
        }
    if isinstance(space, spaces.MultiBinary):
        return {"type": "MultiBinary", "n": np.asarray(space.n).tolist()}
    if isinstance(space, spaces.Dict):
        return {
            "type": "Dict",
            "spaces": [[key, space_to_json(sub)] for key, sub in space.spaces.items()],
        }
    raise ValueError(
        f"cannot store observation/action space {space} in a safe checkpoint: expected "
        "gymnasium Box, Discrete, MultiDiscrete, MultiBinary or Dict of these"
    )


def space_from_json(data: Any, where: str = "space") -> spaces.Space:
    """The space described by :func:`space_to_json`'s output; ValueError naming ``where`` on
    any malformed entry."""
    if not isinstance(data, dict) or "type" not in data:
        raise ValueError(f"{where}: expected a space description dict, got {data!r:.200}")
    kind = data["type"]
    try:
        if kind == "Box":
            dtype = str(data["dtype"])
            if dtype not in _DTYPES:
                raise ValueError(f"unsupported dtype {dtype!r}")
            shape = _shape(data["shape"], where)
            low = _array(data["low"], dtype, shape, f"{where}.low")
            high = _array(data["high"], dtype, shape, f"{where}.high")
            return spaces.Box(low=low, high=high, shape=shape, dtype=np.dtype(dtype))
        if kind == "Discrete":
            n = check_number(data["n"], f"{where}.n", 1, MAX_ELEMENTS, integer=True)
            start = check_number(data.get("start", 0), f"{where}.start", -(2**62), 2**62, True)
            return spaces.Discrete(n, start=start)
        if kind == "MultiDiscrete":
            _shape([len(data["nvec"])], where)
            dtype = str(data.get("dtype", "int64"))
            if dtype not in _DTYPES:
                raise ValueError(f"unsupported dtype {dtype!r}")
            return spaces.MultiDiscrete(
                np.asarray(data["nvec"], dtype=np.int64),
                dtype=np.dtype(dtype),
                start=np.asarray(data.get("start", 0), dtype=np.int64),
            )
        if kind == "MultiBinary":
            n = data["n"]
            n = _shape([n] if isinstance(n, int) else n, where)
            return spaces.MultiBinary(list(n) if len(n) > 1 else n[0])
        if kind == "Dict":
            parts: OrderedDict[str, spaces.Space] = OrderedDict()  # keeps the saved key order
            if len(data["spaces"]) > MAX_DICT_KEYS:
                raise ValueError(f"more than {MAX_DICT_KEYS} parts")
            for key, sub in data["spaces"]:
                if not isinstance(key, str):
                    raise ValueError(f"Dict key {key!r} is not a string")
                parts[key] = space_from_json(sub, f"{where}[{key!r}]")
            return spaces.Dict(parts)
    except (KeyError, TypeError) as e:
        raise ValueError(f"{where}: malformed {kind} description ({e!r})") from e
    raise ValueError(
        f"{where}: unsupported space type {kind!r} (expected Box, Discrete, MultiDiscrete, "
        "MultiBinary or Dict)"
    )
