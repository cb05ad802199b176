""" "Did you mean ...?" hints for error messages about a mistyped name."""

from __future__ import annotations

import difflib
from collections.abc import Iterable


def did_you_mean(value: object, choices: Iterable[object]) -> str:
    """``"did you mean 'x'? "`` for the choice closest to ``value`` (difflib), else ``""``."""
    close = difflib.get_close_matches(str(value), [str(c) for c in choices], n=1)
    return f"did you mean {close[0]!r}? " if close else ""
