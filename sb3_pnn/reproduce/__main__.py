"""``python -m sb3_pnn.reproduce``: see :mod:`sb3_pnn.reproduce.cli`."""

import sys

from sb3_pnn.reproduce.cli import main

if __name__ == "__main__":
    sys.exit(main())
