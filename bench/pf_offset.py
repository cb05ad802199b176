"""Why a path-following column rides beside its path: its actions, and what coming back pays.

1. The column's greedy actions on its own task (validation seeds 20000+, never the study's
   evaluation seeds): the share of each of Table 1's actions, and mean g (signed), |g|, |a_c|.
2. What the reward pays for coming back (no column involved): the discounted return (gamma
   0.99, ``--steps`` steps) of scripted action sequences from a pose ``--offset`` metres beside
   the straight path with the heading parallel to it: always "Go straight", one "Turn left 1"
   then straight, and a turn paired with a counter-turn. A correction pays only with its
   counter-turn (docs/ablation section 10).

Usage: python bench/pf_offset.py --straight STUDY/runs/prior-pf_straight-s0/model.zip
       [--sine STUDY/runs/prior-pf_sine-s0/model.zip] [--episodes 10] [--offset 1.6]
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np
import torch as th

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC
from sb3_pnn.reproduce.planning.setups import OURS

ENVS = {"straight": "rov_envs/PathFollowingStraight-v0", "sine": "rov_envs/PathFollowingSine-v0"}
ACTIONS = ("Turn left 1", "Turn left 2", "Go straight", "Turn right 1", "Turn right 2")
TURN_LEFT_1, GO_STRAIGHT, TURN_RIGHT_1 = 0, 2, 3
#: name -> the first actions of the sequence (then "Go straight" to the end)
SEQUENCES = {
    "always straight": [],
    "one Turn left 1, then straight": [TURN_LEFT_1],
    "2 x Turn left 1, 18 straight, 2 x Turn right 1": (
        [TURN_LEFT_1] * 2 + [GO_STRAIGHT] * 18 + [TURN_RIGHT_1] * 2
    ),
}


def column_actions(path: str, model_path: str, episodes: int, seed: int) -> None:
    model = DiscreteSAC.load(model_path, device="cpu")
    env = gym.make(ENVS[path], **OURS.env_kwargs())
    keys = list(model.observation_space.spaces)
    actions, g, a_c = [], [], []
    for ep in range(episodes):
        obs, _ = env.reset(seed=seed + ep)
        done = False
        while not done:
            action, _ = model.predict({k: obs[k] for k in keys}, deterministic=True)
            obs, _, terminated, truncated, info = env.step(action)
            actions.append(int(action))
            g.append(info["cross_track"])
            a_c.append(abs(info["heading_error"]))
            done = terminated or truncated
    shares = np.bincount(actions, minlength=len(ACTIONS)) / len(actions)
    print(f"{path} column {model_path}: {episodes} episodes from seed {seed}")
    print("  greedy actions: " + ", ".join(f"{n} {s:.1%}" for n, s in zip(ACTIONS, shares)))
    print(
        f"  mean g {np.mean(g):+.2f} m, mean |g| {np.mean(np.abs(g)):.2f} m, "
        f"mean |a_c| {np.degrees(np.mean(a_c)):.1f} deg"
    )


def scripted_return(first: list[int], offset: float, steps: int, gamma: float = 0.99) -> tuple:
    env = gym.make(ENVS["straight"], **{**OURS.env_kwargs(), "start_noise": (0.0, 0.0)})
    env.reset(seed=0)
    env.unwrapped.set_pose(50.0, -offset, 0.0)
    total, discount = 0.0, 1.0
    for t in range(steps):
        _, reward, terminated, truncated, info = env.step(first[t] if t < len(first) else 2)
        total += discount * reward
        discount *= gamma
        if terminated or truncated:
            break
    return total, info["cross_track"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--straight", required=True, help="a PathFollowingStraight column")
    parser.add_argument("--sine", help="a PathFollowingSine column")
    parser.add_argument("--episodes", type=int, default=10)
    parser.add_argument("--seed", type=int, default=20_000, help="first episode seed")
    parser.add_argument("--offset", type=float, default=1.6, help="start beside the path (m)")
    parser.add_argument("--steps", type=int, default=150)
    args = parser.parse_args()
    if args.episodes < 1 or args.steps < 1 or not 0 < args.offset < 30:
        parser.error("expected --episodes >= 1, --steps >= 1 and 0 < --offset < 30 (m)")
    th.set_num_threads(1)
    column_actions("straight", args.straight, args.episodes, args.seed)
    if args.sine:
        column_actions("sine", args.sine, args.episodes, args.seed)
    print(f"discounted return of {args.steps} steps from {args.offset} m beside the straight path:")
    for name, first in SEQUENCES.items():
        total, g_end = scripted_return(first, args.offset, args.steps)
        print(f"  {name:48} {total:6.1f}  (g at the end {g_end:+.2f} m)")


if __name__ == "__main__":
    main()
