"""Where a study's kept policies leave their route: near obstacles or clear of them.

Replays each run's kept policy (as the study played it; a PID baseline's run replays the
baseline) on its own planning task (the run's ``"original"`` evaluation task) on the fresh
validation seeds 40000+ of ``tools.fresh_route``, and splits the steps by the distance to the
nearest obstacle's surface: within ``--near`` metres (12.5, SPNN's switch distance d_th) and
beyond. It prints per run the share of steps near, and mean abs(g) and abs(a_c) near, beyond and
over all steps. A wide route near obstacles is a wide detour; a wide route beyond them is a
policy that does not come back after one (``tools.offset_return`` then shows whether it holds
a parallel offset).

Usage: python -m sb3_pnn.reproduce.tools.route_split STUDY --agent pnn --path straight
    [--seeds 0 1 2] [--episodes 10] [--near 12.5]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import gymnasium as gym
import numpy as np
import torch as th

from sb3_pnn.common.checks import positive_int
from sb3_pnn.reproduce.tools.fresh_route import FRESH_SEED, add_run_arguments, chosen_runs
from sb3_pnn.reproduce.tools.replay import run_baseline, run_eval_task, run_model, run_played

#: The default distance (m) that tells near steps from clear ones: SPNN's d_th (eq. 15).
NEAR = 12.5


def split_route(policy, env: gym.Env, episodes: int, near: float) -> dict[str, np.ndarray]:
    """Per step of ``episodes`` greedy episodes on seeds 40000+: abs(g), abs(a_c) and whether
    the nearest obstacle's surface was within ``near`` metres."""
    g, a_c, close = [], [], []
    for episode in range(episodes):
        obs, _ = env.reset(seed=FRESH_SEED + episode)
        state, start, done = None, np.array([True]), False
        while not done:
            action, state = policy.predict(
                obs, state=state, episode_start=start, deterministic=True
            )
            start = np.array([False])
            obs, _, terminated, truncated, info = env.step(action)
            g.append(abs(info["cross_track"]))
            a_c.append(abs(info["heading_error"]))
            close.append(info["obstacle_distance"] < near)
            done = terminated or truncated
    return {"g": np.array(g), "ac": np.degrees(np.array(a_c)), "near": np.array(close)}


def summary(steps: dict[str, np.ndarray]) -> dict[str, float]:
    """Share of steps near (%), and mean abs(g) (m) and abs(a_c) (deg) near, beyond and over
    all steps (nan where no step falls in a part)."""
    out = {"share": 100.0 * float(steps["near"].mean())}
    for part, mask in (
        ("near", steps["near"]),
        ("clear", ~steps["near"]),
        ("all", np.ones_like(steps["near"])),
    ):
        for key in ("g", "ac"):
            values = steps[key][mask]
            out[f"{part}_{key}"] = float(values.mean()) if values.size else math.nan
    return out


def run_split(parser: argparse.ArgumentParser, run: Path, episodes: int, near: float) -> dict:
    """:func:`summary` of the run's kept policy (or its PID baseline) on its planning task."""
    env_id, env_kwargs = run_eval_task(parser, run, "original")
    env = gym.make(env_id, **env_kwargs)
    model = run_model(parser, run)
    policy = run_baseline(run, env) if model is None else run_played(parser, run, model)
    return summary(split_route(policy, env, episodes, near))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_run_arguments(parser)
    parser.add_argument("--episodes", type=positive_int("--episodes"), default=10)
    parser.add_argument("--near", type=float, default=NEAR, help="metres to the nearest surface")
    args = parser.parse_args(argv)
    if not (math.isfinite(args.near) and args.near > 0):
        parser.error(f"--near {args.near} is not allowed: expected a distance > 0 (m)")
    th.set_num_threads(1)
    runs = chosen_runs(parser, args)
    print(f"{args.agent} on its {args.path} planning task, {args.episodes} episodes per run")
    print(
        f"| seed | steps within {args.near:g} m | near: abs(g), abs(a_c) | "
        "beyond: abs(g), abs(a_c) | all steps |"
    )
    print("|---|---|---|---|---|")
    for seed, run in runs:
        s = run_split(parser, run, args.episodes, args.near)
        print(
            f"| {seed} | {s['share']:.0f} % | {s['near_g']:.2f} m, {s['near_ac']:.1f} deg | "
            f"{s['clear_g']:.2f} m, {s['clear_ac']:.1f} deg | "
            f"{s['all_g']:.2f} m, {s['all_ac']:.1f} deg |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
