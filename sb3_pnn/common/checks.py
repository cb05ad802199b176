"""Argument checks shared across sb3_pnn, and the "did you mean" hint of its error messages.

Every check raises ``ValueError("<name>=<value> is not allowed: expected ...")`` (or returns the
value converted), so that bad input reads the same wherever it is refused.
"""

from __future__ import annotations

import argparse
import difflib
import math
from collections.abc import Iterable
from typing import Any

import numpy as np


def is_finite_number(value: Any) -> bool:
    """A finite int or float; not a bool (``--set`` and JSON may hand one over) or a string."""
    return not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value)


def check_int(name: str, value: Any, low: int) -> int:
    """``value`` as an int when it is an integer (not a bool) >= ``low``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
        raise ValueError(f"{name}={value!r} is not allowed: expected an int >= {low}")
    return int(value)


def check_nonnegative(name: str, value: Any, allow_zero: bool = True) -> float:
    """``value`` as a float when it is a finite number >= 0 (> 0 with ``allow_zero=False``)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}={value!r} is not allowed: expected a finite float") from None
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        what = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name}={value!r} is not allowed: expected a finite float {what}")
    return v


def check_step_budget(value: Any, name: str) -> int:
    """A training or watching budget in environment steps: an integer >= 1.

    ``learn(0)`` or ``learn(-100)`` would otherwise return at once without a word."""
    number = isinstance(value, (int, np.integer, float, np.floating)) and not isinstance(
        value, (bool, np.bool_)
    )
    if not (number and math.isfinite(value) and value >= 1 and value == int(value)):
        raise ValueError(f"{name} must be a positive number of environment steps, got {value!r}")
    return int(value)


def did_you_mean(value: object, choices: Iterable[object]) -> str:
    """``"did you mean 'x'? "`` for the choice closest to ``value`` (difflib), else ``""``."""
    close = difflib.get_close_matches(str(value), [str(c) for c in choices], n=1)
    return f"did you mean {close[0]!r}? " if close else ""


def positive_int(name: str) -> Any:
    """An argparse ``type``: an integer >= 1; the error names the option ``name``."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{name} must be an integer >= 1, got {text!r}"
            ) from None
        if value < 1:
            raise argparse.ArgumentTypeError(f"{name} must be an integer >= 1, got {value}")
        return value

    return parse


def float_in(name: str, low: float, high: float, unit: str) -> Any:
    """An argparse ``type``: a finite float in (``low``, ``high``] when ``low`` is 0, else in
    [``low``, ``high``]; the error names the option ``name`` and the range."""
    allowed = f"({low:g}, {high:g}]" if low == 0 else f"[{low:g}, {high:g}]"

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        inside = low < value <= high if low == 0 else low <= value <= high
        if not inside:  # NaN is never inside
            raise argparse.ArgumentTypeError(
                f"{name} must be a number in {allowed} ({unit}), got {text!r}"
            )
        return value

    return parse
