"""How a study's kept policies pace near obstacles: the share of each action and the speed over
ground within d_th of an obstacle and beyond it.

SPNN's failures among drawn obstacles are mostly crawls to the time limit (docs/ablation
section 27): the turning actions drive two of the four horizontal thrusters and move the
vehicle at about half the speed of "Go straight". This replays each run's kept policy (greedy
actions, the evaluation's start noise, validation seeds 20000+) and classes every decision by
the nearest sonar reading: within d_th (eq. 15's 12.5 m) or beyond. Learners and PID baselines
replay their planning task (``--drawn``: among obstacles drawn afresh by the ``scatter``
generator, as ``tools.drawn_layouts``); a source column (``--agent oa``) replays its own task.

Usage: python -m sb3_pnn.reproduce.tools.obstacle_pace STUDY --agent spnn --path straight
    [--drawn] [--seeds 0 1 2] [--episodes 30]
"""

from __future__ import annotations

from collections import Counter

import gymnasium as gym
import numpy as np
import torch as th

from rov_envs.physics.thrusters import ACTION_NAMES
from sb3_pnn.baselines import BASELINE_NAMES
from sb3_pnn.common.callbacks import DRAWN_VALIDATION_LAYOUT, VALIDATION_SEED
from sb3_pnn.evaluation import DEFAULT_START_NOISE
from sb3_pnn.progressive.selective_policy import PAPER_D_TH
from sb3_pnn.reproduce.planning.plan import AGENTS, PRIOR_ENVS
from sb3_pnn.reproduce.tools.replay import (
    ended,
    run_env_kwargs,
    run_folders,
    run_policy,
    task_id,
    task_parser,
)


def pace(policy, env: gym.Env, episodes: int, d_th: float) -> dict:
    """Replay ``policy`` for ``episodes`` episodes from the validation seed; per class (``near``:
    the nearest reading within ``d_th``, ``far``) the action counts and the mean speed (m/s)."""
    dt = env.unwrapped.config.dt
    sonar_range = env.unwrapped.config.sonar_range
    counts = {"near": Counter(), "far": Counter()}
    speeds: dict[str, list[float]] = {"near": [], "far": []}
    ends: Counter = Counter()
    for episode in range(episodes):
        obs, info = env.reset(seed=VALIDATION_SEED + episode)
        if hasattr(policy, "reset"):
            policy.reset()
        done = False
        while not done:
            nearest = float(np.min(obs["sonar"])) * sonar_range if "sonar" in obs else np.inf
            action, _ = policy.predict(obs, deterministic=True)
            before = np.asarray(env.unwrapped.state[:2])
            obs, _, terminated, truncated, info = env.step(action)
            done = terminated or truncated
            key = "near" if nearest <= d_th else "far"
            counts[key][int(action)] += 1
            moved = np.asarray(env.unwrapped.state[:2]) - before
            speeds[key].append(float(np.hypot(*moved)) / dt)
        ends[info["end_reason"]] += 1
    return {"counts": counts, "speeds": speeds, "ends": ends}


def row(label: str, result: dict) -> str:
    """One table row of :func:`pace`'s result: endings, then per class its share of the
    decisions, its share of "Go straight" and its mean speed."""
    cells = [label, ended(result["ends"])]
    decisions = sum(len(v) for v in result["speeds"].values())
    straight = ACTION_NAMES.index("Go straight")
    for key in ("near", "far"):
        total = sum(result["counts"][key].values())
        share = result["counts"][key][straight] / total if total else 0.0
        speed = f"{np.mean(result['speeds'][key]):.2f} m/s" if total else "-"
        cells += [f"{100 * total / max(1, decisions):.0f} %", f"{100 * share:.0f} %", speed]
    return "| " + " | ".join(cells) + " |"


def main(argv: list[str] | None = None) -> int:
    parser = task_parser(__doc__, episodes=30)
    parser.add_argument("--agent", default="spnn", help="a learner, a PID baseline or a column")
    parser.add_argument("--seeds", type=int, nargs="*", default=None)
    parser.add_argument("--drawn", action="store_true", help="among obstacles drawn afresh")
    args = parser.parse_args(argv)
    th.set_num_threads(1)
    column = args.agent in PRIOR_ENVS
    if column and args.drawn:
        parser.error(f"--drawn replays a planning task; --agent {args.agent} is a source column")
    if column:
        seeds = args.seeds if args.seeds is not None else [0]
        runs = [(s, args.study / "runs" / f"prior-{args.agent}-s{s}") for s in seeds]
    else:
        runs = run_folders(args.study, args.agent, args.path, args.seeds)
    if not runs:
        known = [*AGENTS, *BASELINE_NAMES, *PRIOR_ENVS]
        parser.error(
            f"{args.study / 'runs'} holds no run of --agent {args.agent!r} on the {args.path} "
            f"path: expected a study folder and one of {known}"
        )
    print(
        "| seed | endings | decisions within d_th | Go straight there | speed there "
        "| decisions beyond | Go straight there | speed there |\n|---|---|---|---|---|---|---|---|"
    )
    for seed, run in runs:
        if column:  # a source column replays its own task
            env_id, kwargs = PRIOR_ENVS[args.agent], run_env_kwargs(parser, run, "own")
        else:
            env_id, kwargs = task_id(parser, args), run_env_kwargs(parser, run)
        if args.drawn:
            kwargs["layout"] = DRAWN_VALIDATION_LAYOUT
        kwargs.setdefault("start_noise", DEFAULT_START_NOISE)
        env = gym.make(env_id, **kwargs)
        policy = run_policy(parser, run, env)
        print(row(str(seed), pace(policy, env, args.episodes, PAPER_D_TH)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
