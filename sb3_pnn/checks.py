"""Small argument checks shared by the policies and the study's set-up."""

from __future__ import annotations

import math
from typing import Any


def is_finite_number(value: Any) -> bool:
    """A finite int or float; not a bool (``--set`` and JSON may hand one over) or a string."""
    return not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value)
