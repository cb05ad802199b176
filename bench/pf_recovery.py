"""How well path-following columns come back to their path from a wide start.

Evaluates each column on its own task (50 episodes, validation seeds 20000+ by default, never the
study's evaluation seeds) from the evaluation library's start noise (1 m, 5 deg) and from a wide
one (5 m, 25 deg, where an avoidance detour can leave the vehicle), and prints success, mean
|g| and mean |a_c| for both. The criterion by which ``pf_start_spread`` was chosen
(docs/ablation, section 9).

Usage: python bench/pf_recovery.py --straight A.zip [B.zip ...] --sine C.zip [...]
       (e.g. STUDY/runs/prior-pf_straight-s0/model.zip, STUDY/runs/prior-pf_sine-s0/model.zip)
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import torch as th

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC
from sb3_pnn.evaluation import DEFAULT_START_NOISE, evaluate_policy_on_task
from sb3_pnn.reproduce.planning.setups import OURS

ENVS = {"straight": "rov_envs/PathFollowingStraight-v0", "sine": "rov_envs/PathFollowingSine-v0"}
WIDE_START_NOISE = (5.0, math.radians(25.0))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--straight", nargs="*", default=[], help="straight-line columns (zip)")
    parser.add_argument("--sine", nargs="*", default=[], help="sinusoid columns (zip)")
    parser.add_argument("--episodes", type=int, default=50)
    parser.add_argument("--seed", type=int, default=20000, help="first episode seed")
    args = parser.parse_args()
    if not (args.straight or args.sine) or args.episodes < 1 or args.seed < 0:
        parser.error("give at least one column, --episodes >= 1 and --seed >= 0")
    missing = [c for c in args.straight + args.sine if not Path(c).is_file()]
    if missing:
        parser.error(f"no such column file: {', '.join(missing)} (expected model.zip files)")
    th.set_num_threads(1)
    for path, columns in (("straight", args.straight), ("sine", args.sine)):
        for column in columns:
            model = DiscreteSAC.load(column, device="cpu")
            for noise in (DEFAULT_START_NOISE, WIDE_START_NOISE):
                r = evaluate_policy_on_task(model, ENVS[path], n_episodes=args.episodes,
                                            seed=args.seed, start_noise=noise,
                                            env_kwargs=OURS.env_kwargs())  # fmt: skip
                print(f"{path:8s} start {noise[0]:.0f} m / {math.degrees(noise[1]):2.0f} deg  "
                      f"success {100 * r.success_rate:3.0f} %  mean |g| "
                      f"{r.mean_abs_cross_track:4.2f} m  mean |a_c| "
                      f"{math.degrees(r.mean_abs_heading_error):4.1f} deg  "
                      f"{dict(sorted(r.end_reasons.items()))}  {column}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
