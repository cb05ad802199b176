"""Observation-space descriptions read safely from checkpoint text, and the feeding rule.

A prior column must receive exactly the observation it was trained on (design notes, section 4).
SB3 stores the observation space in the zip's ``data`` JSON as a cloudpickle blob *next to*
readable fields (``_shape``, ``dtype``, ``low``/``high`` reprs, and for ``Dict`` spaces a
``spaces`` repr string). :func:`obs_spec_from_saved` reads only those readable fields, with
``json`` / ``ast.literal_eval`` / regular expressions, never unpickling anything.

The description is an :class:`ObsSpec`: an ordered list of :class:`BoxSpec` parts, each with the
``Dict`` key it came from (``None`` for a plain ``Box`` space). The order is the order in which
SB3's ``FlattenExtractor`` / ``CombinedExtractor`` concatenated the flattened parts, so
:meth:`ObsSpec.flatten` rebuilds the prior's network input exactly.

Feeding rule (:func:`match_prior_obs`), given the new environment's observation space:

* ``Dict`` prior: every key of the prior's space must be in the new ``Dict`` observation with an
  equal space (shape, dtype and, where both are known, bounds); the prior gets just those keys,
  flattened in the prior's own key order. Extra keys of the new observation are not fed to it.
* ``Box`` prior: the new observation must be a ``Box`` equal to it (fed whole), or a ``Dict`` with
  exactly one key whose space equals it (that key is fed).
* Anything else is refused with a ``ValueError`` that names both spaces.
"""

from __future__ import annotations

import ast
import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np
import torch as th
from gymnasium import spaces

_KEY_RE = re.compile(r"""\s*(?:'((?:[^'\\]|\\.)*)'|"((?:[^"\\]|\\.)*)")\s*:\s*""")
_SHAPE_DTYPE_RE = re.compile(
    r",\s*(\((?:\s*\d+\s*,)*\s*(?:\d+)?\s*\))\s*,\s*([A-Za-z0-9_]+)\s*\)\s*$"
)
_NUMBER_RE = re.compile(r"^[+-]?(?:inf|nan|\d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)$")


@dataclass(frozen=True)
class BoxSpec:
    """One ``Box`` part of an observation: its ``Dict`` key (``None`` for a plain Box), shape,
    dtype and, where readable, flat bounds (``None`` when they could not be read)."""

    key: str | None
    shape: tuple[int, ...]
    dtype: str
    low: tuple[float, ...] | None = None
    high: tuple[float, ...] | None = None

    @property
    def size(self) -> int:
        return int(np.prod(self.shape)) if self.shape else 1

    def same_space(self, other: BoxSpec) -> bool:
        """Equal shape and dtype, and equal bounds wherever both sides know them."""
        if self.shape != other.shape or self.dtype != other.dtype:
            return False
        for mine, theirs in ((self.low, other.low), (self.high, other.high)):
            if mine is not None and theirs is not None:
                a, b = np.asarray(mine, dtype=np.float64), np.asarray(theirs, dtype=np.float64)
                if a.shape != b.shape or not np.allclose(
                    a, b, rtol=1e-6, atol=1e-6, equal_nan=True
                ):
                    return False
        return True

    def describe(self) -> str:
        low = "?" if self.low is None else _short(self.low)
        high = "?" if self.high is None else _short(self.high)
        return f"Box({low}, {high}, {self.shape}, {self.dtype})"

    def to_json(self) -> dict[str, Any]:
        return {
            "key": self.key,
            "shape": list(self.shape),
            "dtype": self.dtype,
            "low": None if self.low is None else [_json_float(v) for v in self.low],
            "high": None if self.high is None else [_json_float(v) for v in self.high],
        }

    @staticmethod
    def from_json(d: dict[str, Any]) -> BoxSpec:
        def bounds(v: Any) -> tuple[float, ...] | None:
            return None if v is None else tuple(float(x) for x in v)

        return BoxSpec(
            key=d["key"],
            shape=tuple(int(s) for s in d["shape"]),
            dtype=str(d["dtype"]),
            low=bounds(d.get("low")),
            high=bounds(d.get("high")),
        )


@dataclass(frozen=True)
class ObsSpec:
    """An observation space as an ordered list of Box parts (``is_dict`` for a ``Dict`` space)."""

    is_dict: bool
    parts: tuple[BoxSpec, ...]

    @property
    def flat_dim(self) -> int:
        return sum(p.size for p in self.parts)

    @property
    def keys(self) -> tuple[str | None, ...]:
        return tuple(p.key for p in self.parts)

    def describe(self) -> str:
        if not self.is_dict:
            return self.parts[0].describe()
        return "Dict(" + ", ".join(f"{p.key!r}: {p.describe()}" for p in self.parts) + ")"

    def to_json(self) -> dict[str, Any]:
        return {"is_dict": self.is_dict, "parts": [p.to_json() for p in self.parts]}

    @staticmethod
    def from_json(d: dict[str, Any]) -> ObsSpec:
        return ObsSpec(bool(d["is_dict"]), tuple(BoxSpec.from_json(p) for p in d["parts"]))


def _short(values: tuple[float, ...]) -> str:
    if len(set(values)) == 1:
        return repr(values[0])
    return "[" + " ".join(f"{v:g}" for v in values) + "]"


def _json_float(v: float) -> float | str:
    # JSON has no inf/nan: keep them as strings, float() reads them back.
    return v if math.isfinite(v) else repr(v)


def _parse_bound(text: str, size: int) -> tuple[float, ...] | None:
    """A numpy scalar or array repr (``-1.0``, ``[-4.8 -inf 0.4]``) as ``size`` floats, or
    ``None`` when the repr is summarised (``...``) or unreadable."""
    if text is None or "..." in text:
        return None
    tokens = [t for t in re.split(r"[\s,\[\]]+", text.strip()) if t]
    if not tokens or not all(_NUMBER_RE.match(t.lower()) for t in tokens):
        return None
    values = tuple(float(t) for t in tokens)
    if len(values) == 1:
        return values * size
    return values if len(values) == size else None


def _box_from_fields(key: str | None, fields: dict[str, Any], where: str) -> BoxSpec:
    shape = fields.get("_shape")
    dtype = fields.get("dtype")
    if not isinstance(shape, list) or not all(isinstance(s, int) for s in shape) or not dtype:
        raise ValueError(
            f"{where}: expected readable '_shape' and 'dtype' fields, got {fields!r:.200}"
        )
    size = int(np.prod(shape)) if shape else 1
    return BoxSpec(
        key,
        tuple(shape),
        str(dtype),
        _parse_bound(fields.get("low"), size),
        _parse_bound(fields.get("high"), size),
    )


def _split_bounds(text: str) -> tuple[str, str] | None:
    """Split ``"low, high"`` where each is a scalar or a (possibly nested) bracketed array."""
    text = text.strip()
    if text.startswith("["):
        depth = 0
        for i, ch in enumerate(text):
            depth += ch == "["
            depth -= ch == "]"
            if depth == 0:
                rest = text[i + 1 :].lstrip()
                if not rest.startswith(","):
                    return None
                return text[: i + 1], rest[1:].strip()
        return None
    low, sep, high = text.partition(",")
    return (low.strip(), high.strip()) if sep else None


def _parse_dict_repr(text: str, where: str) -> tuple[BoxSpec, ...]:
    """Parse the ``spaces`` repr of a saved ``Dict`` space:
    ``"{'path': Box(-1.0, 1.0, (2,), float32), 'sonar': Box(0.0, 1.0, (9,), float32)}"``."""
    body = text.strip()
    if body.startswith("Dict(") and body.endswith(")"):
        body = body[5:-1]
    elif body.startswith("{") and body.endswith("}"):
        body = body[1:-1]
    else:
        raise ValueError(f"{where}: unreadable Dict 'spaces' field {text!r:.300}")
    parts: list[BoxSpec] = []
    pos = 0
    while pos < len(body.strip()):
        m = _KEY_RE.match(body, pos)
        if m is None:
            raise ValueError(
                f"{where}: unreadable Dict 'spaces' field near {body[pos : pos + 60]!r}"
            )
        key = ast.literal_eval(body[m.start() : m.end()].strip().rstrip(":").strip())
        pos = m.end()
        if not body.startswith("Box(", pos):
            raise ValueError(
                f"{where}: Dict key {key!r} holds {body[pos : pos + 40]!r}...; only Box parts "
                "(flattened by SB3's CombinedExtractor) are supported in prior checkpoints"
            )
        close = _find_box_end(body, pos)
        if close < 0:
            raise ValueError(f"{where}: unreadable Box repr for key {key!r}")
        box_text = body[pos:close]
        sd = _SHAPE_DTYPE_RE.search(box_text)
        if sd is None:
            raise ValueError(f"{where}: unreadable Box repr {box_text!r:.200} for key {key!r}")
        shape = ast.literal_eval(sd.group(1))
        dtype = sd.group(2)
        size = int(np.prod(shape)) if shape else 1
        bounds = _split_bounds(box_text[4 : sd.start()])
        low = _parse_bound(bounds[0], size) if bounds else None
        high = _parse_bound(bounds[1], size) if bounds else None
        parts.append(BoxSpec(key, tuple(int(s) for s in shape), dtype, low, high))
        pos = close
        rest = body[pos:].lstrip()
        if rest.startswith(","):
            pos = len(body) - len(rest) + 1
        elif rest:
            raise ValueError(f"{where}: unreadable Dict 'spaces' field near {rest[:60]!r}")
        else:
            break
    if not parts:
        raise ValueError(f"{where}: empty Dict observation space")
    return tuple(parts)


def _find_box_end(body: str, start: int) -> int:
    """Index just after the ')' that closes the ``Box(`` starting at ``start``."""
    depth = 0
    for i in range(start + 3, len(body)):
        ch = body[i]
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                return i + 1
    return -1


def obs_spec_from_saved(field: Any, where: str) -> ObsSpec:
    """Read an observation space from its entry in a SB3 zip's ``data`` JSON, using only the
    readable fields SB3 writes beside the ``:serialized:`` blob (which is never decoded)."""
    if not isinstance(field, dict) or ":type:" not in field:
        raise ValueError(f"{where}: expected a saved gymnasium space, got {field!r:.200}")
    type_name = str(field[":type:"])
    if type_name.endswith(".Box'>"):
        return ObsSpec(False, (_box_from_fields(None, field, where),))
    if type_name.endswith(".Dict'>"):
        text = field.get("spaces")
        if not isinstance(text, str):
            raise ValueError(f"{where}: saved Dict space has no readable 'spaces' field")
        return ObsSpec(True, _parse_dict_repr(text, where))
    raise ValueError(
        f"{where}: observation space of type {type_name} is not supported "
        "(expected gymnasium Box or Dict of Box spaces)"
    )


def obs_spec_from_space(space: spaces.Space) -> ObsSpec:
    """The :class:`ObsSpec` of a live gymnasium space (the new environment's)."""

    def box(key: str | None, b: spaces.Space) -> BoxSpec:
        if not isinstance(b, spaces.Box):
            raise ValueError(f"observation part {key!r} is {b}; only Box parts are supported")
        return BoxSpec(
            key,
            tuple(int(s) for s in b.shape),
            str(b.dtype),
            tuple(float(v) for v in np.asarray(b.low, dtype=np.float64).ravel()),
            tuple(float(v) for v in np.asarray(b.high, dtype=np.float64).ravel()),
        )

    if isinstance(space, spaces.Dict):
        return ObsSpec(True, tuple(box(k, s) for k, s in space.spaces.items()))
    if isinstance(space, spaces.Box):
        return ObsSpec(False, (box(None, space),))
    raise ValueError(f"observation space {space} is not supported (expected Box or Dict of Box)")


@dataclass(frozen=True)
class Feed:
    """How to build a prior's input from the new observation: the new observation's keys to
    flatten and concatenate, in the prior's order (``None`` = the whole Box observation)."""

    keys: tuple[str | None, ...]

    def __call__(self, obs: th.Tensor | dict[str, th.Tensor]) -> th.Tensor:
        if self.keys == (None,):
            assert isinstance(obs, th.Tensor)
            return obs.float().flatten(1)
        assert isinstance(obs, dict)
        return th.cat([obs[k].float().flatten(1) for k in self.keys], dim=1)  # type: ignore[index]


def match_prior_obs(prior: ObsSpec, new: ObsSpec, prior_name: str = "prior") -> Feed:
    """The feeding rule (module docstring): which parts of the new observation a prior gets."""

    def refuse(why: str) -> ValueError:
        return ValueError(
            f"{prior_name} cannot be fed from the new environment: {why}. "
            f"Prior observation space: {prior.describe()}; new observation space: {new.describe()}"
        )

    if prior.is_dict:
        if not new.is_dict:
            raise refuse("the prior expects a Dict observation but the new one is a Box")
        by_key = {p.key: p for p in new.parts}
        for part in prior.parts:
            if part.key not in by_key:
                raise refuse(f"key {part.key!r} is missing from the new observation")
            if not part.same_space(by_key[part.key]):
                raise refuse(
                    f"key {part.key!r} is {by_key[part.key].describe()} in the new observation "
                    f"but {part.describe()} in the prior"
                )
        return Feed(tuple(p.key for p in prior.parts))
    box = prior.parts[0]
    if not new.is_dict:
        if not box.same_space(new.parts[0]):
            raise refuse("the Box spaces differ")
        return Feed((None,))
    matches = [p.key for p in new.parts if box.same_space(p)]
    if len(matches) != 1:
        why = "no key" if not matches else f"several keys ({matches})"
        raise refuse(f"{why} of the new Dict observation equals the prior's Box space")
    return Feed((matches[0],))
