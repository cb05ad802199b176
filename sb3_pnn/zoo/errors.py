"""Command-line error handling for the rl-zoo style commands.

Bad input (an unknown algo or env id, a malformed YAML entry, an out-of-range tuning bound, a
missing prior checkpoint) raises :class:`ZooUsageError`. The entry points turn it into one line on
stderr and exit status 2, instead of a traceback. Set ``SB3_PNN_TRACEBACK=1`` to see the traceback.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable

USAGE_EXIT_CODE = 2


class ZooUsageError(ValueError):
    """Bad user input for ``python -m sb3_pnn.train`` / ``python -m sb3_pnn.enjoy``."""


def run_cli(main: Callable[[], None], prog: str) -> None:
    """Run ``main``; report a :class:`ZooUsageError` as ``<prog>: error: <message>``, exit 2."""
    try:
        main()
    except ZooUsageError as error:
        if os.environ.get("SB3_PNN_TRACEBACK"):
            raise
        message = " ".join(str(error).split())
        print(f"{prog}: error: {message}", file=sys.stderr)
        raise SystemExit(USAGE_EXIT_CODE) from None
