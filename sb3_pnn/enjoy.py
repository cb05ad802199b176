"""``python -m sb3_pnn.enjoy``: watch or record a model trained with ``python -m sb3_pnn.train``.

Examples::

    python -m sb3_pnn.enjoy --algo spnn --env rov_envs/PlanningStraight-v0 -f logs --no-render
    python -m sb3_pnn.enjoy --algo spnn --env rov_envs/PlanningStraight-v0 -f logs \\
        --record videos/spnn.mp4 -n 2000
"""

from __future__ import annotations

from sb3_pnn.zoo.cli import ENJOY_PROG, enjoy_main
from sb3_pnn.zoo.errors import run_cli


def main() -> None:
    run_cli(enjoy_main, ENJOY_PROG)


if __name__ == "__main__":
    main()
