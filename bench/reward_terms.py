"""Where the planning tasks' return comes from: eq. 17-21's terms per episode, PID against models.

Rolls out the adaptive PID and the given models (greedy) on PlanningStraight / PlanningSine,
validation seeds 20000+ by default (never the study's evaluation seeds), the evaluation's start
noise, each model in the env keywords it was trained with, and prints per episode the sums of
r_c (eq. 18/19, route keeping), r_v (eq. 20, -2 / -4 per step within 8 m / 5 m of an obstacle's
surface) and r_terminal (eq. 21 and the success reward), the steps taken, the steps within 8 m of
an obstacle, and mean |g| and |a_c|. It shows what the task's reward pays for keeping the route
among obstacles against keeping clear of them (docs/ablation section 10).

Usage: python bench/reward_terms.py --straight STUDY/runs/spnn-straight-s0/model.zip ...
       [--sine STUDY/runs/spnn-sine-s0/model.zip ...] [--episodes 50] [--seed 20000]
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np
import torch as th

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC
from sb3_pnn.baselines import make_baseline
from sb3_pnn.evaluation.evaluate import DEFAULT_START_NOISE, trained_env_kwargs

ENVS = {"straight": "rov_envs/PlanningStraight-v0", "sine": "rov_envs/PlanningSine-v0"}
NEAR = 8.0  # eq. 20's outer band (m from the obstacle's surface)


def episode_terms(env: gym.Env, policy, seed: int) -> np.ndarray:
    """[r_c, r_v, r_terminal, steps, steps within NEAR, sum |g|, sum |a_c|] of one episode."""
    obs, _ = env.reset(seed=seed)
    if hasattr(policy, "reset"):
        policy.reset()
    sums = np.zeros(7)
    done = False
    while not done:
        action, _ = policy.predict(obs, deterministic=True)
        obs, _, terminated, truncated, info = env.step(int(action))
        sums += (
            info["r_c"],
            info["r_v"],
            info["r_terminal"],
            1,
            info["obstacle_distance"] <= NEAR,
            abs(info["cross_track"]),
            abs(info["heading_error"]),
        )
        done = terminated or truncated
    return sums


def report(path: str, name: str, policy, env_kwargs: dict, episodes: int, seed: int) -> None:
    env = gym.make(ENVS[path], **{**env_kwargs, "start_noise": DEFAULT_START_NOISE})
    rc, rv, rt, steps, near, g, a_c = np.mean(
        [episode_terms(env, policy, seed + i) for i in range(episodes)], axis=0
    )
    print(
        f"{path:8} {name:32} r_c {rc:6.1f}  r_v {rv:7.1f}  r_terminal {rt:6.1f}  "
        f"return {rc + rv + rt:6.1f}  steps {steps:4.0f} (within {NEAR:.0f} m: {near:5.1f})  "
        f"mean |g| {g / steps:.2f} m, |a_c| {np.degrees(a_c / steps):.1f} deg",
        flush=True,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--straight", nargs="*", default=[], help="PlanningStraight models")
    parser.add_argument("--sine", nargs="*", default=[], help="PlanningSine models")
    parser.add_argument("--episodes", type=int, default=50)
    parser.add_argument("--seed", type=int, default=20_000, help="first episode seed")
    args = parser.parse_args()
    if args.episodes < 1 or args.seed < 0:
        parser.error(f"expected --episodes >= 1 and --seed >= 0, got {args.episodes}, {args.seed}")
    th.set_num_threads(1)
    for path, models in (("straight", args.straight), ("sine", args.sine)):
        pid = make_baseline("adaptive_pid", gym.make(ENVS[path]))
        report(path, "adaptive PID", pid, {}, args.episodes, args.seed)
        for model_path in models:
            model = DiscreteSAC.load(model_path, device="cpu")
            kwargs = trained_env_kwargs(model, ENVS[path])
            name = "/".join(model_path.split("/")[-2:])[-32:]
            report(path, name, model, kwargs, args.episodes, args.seed)


if __name__ == "__main__":
    main()
