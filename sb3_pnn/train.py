"""``python -m sb3_pnn.train``: rl_zoo3's train command with dsac, sac_multi, pnn and spnn.

Examples::

    python -m sb3_pnn.train --algo dsac --env rov_envs/PathFollowingStraight-v0
    python -m sb3_pnn.train --algo dsac --env rov_envs/ObstacleAvoidance-v0
    python -m sb3_pnn.train --algo spnn --env rov_envs/PlanningStraight-v0 -tb runs
    python -m sb3_pnn.train --algo spnn --env rov_envs/PlanningStraight-v0 -optimize \\
        --n-trials 50 -n 50000 --tune d_th=5:20

See :mod:`sb3_pnn.zoo.cli` for the flags added to rl_zoo3's.
"""

from __future__ import annotations

from sb3_pnn.zoo.cli import TRAIN_PROG, train_main
from sb3_pnn.zoo.errors import run_cli


def main() -> None:
    run_cli(train_main, TRAIN_PROG)


if __name__ == "__main__":
    main()
