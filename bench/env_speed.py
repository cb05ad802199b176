"""Steps per second of the rov_envs environments beside Gymnasium's Pendulum-v1 (same run).

Usage: ``python bench/env_speed.py [--steps 20000] [--envs 64 256 1024] [--task PlanningStraight]``

Prints, for each measurement, steps/s and the ratio to Pendulum-v1 stepped in the same process:
* single env through ``gymnasium.make`` (wrappers included), random Table 1 actions;
* the natively batched env through ``gymnasium.make_vec(..., "vector_entry_point")`` (total
  vehicle-steps/s, infos included), and the SB3 ``VecEnv`` adapter.
Targets (issue 2): single >= 1x Pendulum-v1, batched (64+ vehicles) >= 50x.
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np

import rov_envs  # noqa: F401  (registers the ids)


def bench_single(env_id: str, steps: int, continuous: bool = False) -> float:
    env = gym.make(env_id, continuous=continuous)
    rng = np.random.default_rng(0)
    if continuous:
        actions = list(rng.uniform(-1, 1, size=(steps, 2)).astype(np.float32))
    else:
        actions = rng.integers(0, env.action_space.n, size=steps).tolist()
    env.reset(seed=0)
    for a in actions[:500]:  # warm-up (numba compile / cache load)
        _, _, te, tr, _ = env.step(a)
        if te or tr:
            env.reset()
    t0 = time.perf_counter()
    for a in actions:
        _, _, te, tr, _ = env.step(a)
        if te or tr:
            env.reset()
    return steps / (time.perf_counter() - t0)


def bench_vector(env_id: str, n: int, steps: int, sb3: bool) -> float:
    if sb3:
        from rov_envs.sb3 import RovSB3VecEnv

        env = RovSB3VecEnv(n, env_id)
        env.seed(0)
        env.reset()
    else:
        env = gym.make_vec(env_id, num_envs=n, vectorization_mode="vector_entry_point")
        env.reset(seed=0)
    rng = np.random.default_rng(0)
    n_calls = max(20, steps // n)
    acts = [rng.integers(0, 5, size=n) for _ in range(min(n_calls, 64))]
    for k in range(10):
        env.step(acts[k % len(acts)])
    t0 = time.perf_counter()
    for k in range(n_calls):
        env.step(acts[k % len(acts)])
    return n * n_calls / (time.perf_counter() - t0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20000, help="env steps per measurement")
    parser.add_argument("--envs", type=int, nargs="+", default=[64, 256, 1024])
    parser.add_argument("--task", default="PlanningStraight")
    args = parser.parse_args()
    env_id = f"rov_envs/{args.task}-v0"

    pend_env = gym.make("Pendulum-v1")
    pend_env.reset(seed=0)
    a = np.zeros(1, np.float32)

    def pendulum() -> float:
        t0 = time.perf_counter()
        for _ in range(args.steps):
            _, _, te, tr, _ = pend_env.step(a)
            if te or tr:
                pend_env.reset()
        return args.steps / (time.perf_counter() - t0)

    pendulum()
    pend = pendulum()
    print(f"{'Pendulum-v1 (gymnasium.make)':52s}{pend:12,.0f} steps/s     1.00x")
    sine = "rov_envs/PathFollowingSine-v0"
    rows = [
        (f"{env_id} single", lambda: bench_single(env_id, args.steps)),
        (f"{sine} single", lambda: bench_single(sine, args.steps)),
        (f"{env_id} single continuous", lambda: bench_single(env_id, args.steps, True)),
    ]
    big = 50 * args.steps
    for n in args.envs:
        for sb3 in (False, True):
            label = "RovSB3VecEnv" if sb3 else "make_vec"
            rows.append(
                (f"{env_id} {label} N={n}", lambda n=n, sb3=sb3: bench_vector(env_id, n, big, sb3))
            )
    for name, fn in rows:
        sps = fn()
        pend = 0.5 * (pend + pendulum())  # re-anchor beside each row (the load drifts)
        print(f"{name:52s}{sps:12,.0f} steps/s {sps / pend:8.2f}x Pendulum-v1 ({pend:,.0f})")


if __name__ == "__main__":
    main()
