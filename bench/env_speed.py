"""Steps per second of the rov_envs environments beside Gymnasium's Pendulum-v1 (same run).

Usage: ``python bench/env_speed.py [--seconds 1.0] [--rounds 5] [--envs 64 256 1024 4096]
[--task PlanningStraight] [--extra-tasks PlanningStraightDense PathFollowingSine]
[--vehicle uuv_simulator] [--control-period 1.0]``

Each row is timed in ``--rounds`` rounds, each round right after a round of the anchor, and the
best round of each is kept (the least disturbed by other load). The anchor is Pendulum-v1 made
with ``gymnasium.make`` (its default wrappers included) and stepped with actions drawn
beforehand, exactly as the rov_envs rows are: no ``action_space.sample()`` in the loop (that
call alone costs about twice Pendulum's step and would flatter every ratio); the
``action_space.sample()`` figure is printed too, for comparison with published numbers.

Rows: one environment through ``gymnasium.make`` (wrappers included) with random Table 1 actions
(and with continuous actions); the natively batched environment through
``gymnasium.make_vec(..., vectorization_mode="vector_entry_point")`` (total vehicle-steps per
second, infos and autoresets included) and the SB3 ``VecEnv`` adapter, for each N; every row runs
the vehicle preset ``--vehicle`` (default ``uuv_simulator``, the environments' default) at the
control period ``--control-period`` (default: the environments' default). A step integrates one
control period in substeps of at most 0.05 s, so a 1.0 s step runs five times the physics of a
0.2 s step; the header prints the period and each row's simulated seconds per wall second
(summed over its vehicles).
Targets (issue 2, set when the default period was 0.2 s): single >= 1x Pendulum-v1; batched, 64
or more vehicles, >= 50x.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import gymnasium as gym
import numba
import numpy as np

import rov_envs  # noqa: F401  (registers the ids)
from rov_envs.envs.sb3 import RovSB3VecEnv
from rov_envs.physics.params import DEFAULT_VEHICLE, VEHICLES
from rov_envs.sim.config import CONTROL_PERIOD, CONTROL_PERIOD_RANGE

#: Pendulum-v1's time step (s), for its simulated seconds per wall second.
PENDULUM_DT = 0.05


def timed(step: Callable[[int], None], seconds: float) -> float:
    """Calls per second of ``step(k)``, k = 0, 1, ..., over about ``seconds``."""
    n, k = 16, 0
    while True:
        t0 = time.perf_counter()
        for _ in range(n):
            step(k)
            k += 1
        el = time.perf_counter() - t0
        if el >= seconds:
            return n / el
        n = max(n + 1, int(n * min(8.0, 1.2 * seconds / max(el, 1e-6))))


def single_stepper(
    env_id: str, vehicle: str, period: float, continuous: bool = False
) -> Callable[[int], None]:
    env = gym.make(env_id, continuous=continuous, vehicle=vehicle, control_period=period)
    rng = np.random.default_rng(0)
    if continuous:
        acts = list(rng.uniform(-1, 1, size=(4096, 2)).astype(np.float32))
    else:
        acts = rng.integers(0, 5, size=4096).tolist()
    env.reset(seed=0)

    def step(k: int) -> None:
        _, _, te, tr, _ = env.step(acts[k % 4096])
        if te or tr:
            env.reset()

    return step


def pendulum_stepper(sample: bool) -> Callable[[int], None]:
    env = gym.make("Pendulum-v1")
    env.reset(seed=0)
    env.action_space.seed(0)
    acts = list(np.random.default_rng(0).uniform(-2, 2, size=(4096, 1)).astype(np.float32))

    def step(k: int) -> None:
        a = env.action_space.sample() if sample else acts[k % 4096]
        _, _, te, tr, _ = env.step(a)
        if te or tr:
            env.reset()

    return step


def vector_stepper(
    env_id: str, n: int, sb3: bool, vehicle: str, period: float
) -> Callable[[int], None]:
    if sb3:
        env = RovSB3VecEnv(n, env_id, vehicle=vehicle, control_period=period)
        env.seed(0)
        env.reset()
    else:
        env = gym.make_vec(
            env_id,
            num_envs=n,
            vectorization_mode="vector_entry_point",
            vehicle=vehicle,
            control_period=period,
        )
        env.reset(seed=0)
    rng = np.random.default_rng(0)
    acts = [rng.integers(0, 5, size=n) for _ in range(64)]

    def step(k: int) -> None:
        env.step(acts[k % 64])

    return step


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=1.0, help="length of one timed round")
    ap.add_argument("--rounds", type=int, default=5, help="rounds per row (best is kept)")
    ap.add_argument("--envs", type=int, nargs="+", default=[64, 256, 1024, 4096])
    ap.add_argument("--task", default="PlanningStraight")
    ap.add_argument("--extra-tasks", nargs="*", default=[], help="batched rows at the largest N")
    ap.add_argument("--no-sb3", action="store_true", help="skip the SB3 VecEnv rows")
    ap.add_argument("--vehicle", default=DEFAULT_VEHICLE, choices=VEHICLES, help="vehicle preset")
    ap.add_argument(
        "--control-period", type=float, default=CONTROL_PERIOD, help="seconds per env step"
    )
    args = ap.parse_args()
    if args.seconds <= 0 or args.rounds < 1 or min(args.envs) < 1:
        raise SystemExit("--seconds must be > 0, --rounds >= 1 and every --envs value >= 1")
    lo, hi = CONTROL_PERIOD_RANGE
    if not lo <= args.control_period <= hi:
        raise SystemExit(f"--control-period {args.control_period:g} is not in [{lo:g}, {hi:g}] s")
    env_id = f"rov_envs/{args.task}-v0"
    v, cp = args.vehicle, args.control_period

    anchor = pendulum_stepper(sample=False)
    # (name, stepper, vehicles per call, simulated seconds per vehicle-step)
    rows: list[tuple[str, Callable[[int], None], int, float]] = [
        (
            "Pendulum-v1, action_space.sample() in the loop",
            pendulum_stepper(sample=True),
            1,
            PENDULUM_DT,
        ),
        (f"{env_id} single", single_stepper(env_id, v, cp), 1, cp),
        (f"{env_id} single, continuous", single_stepper(env_id, v, cp, True), 1, cp),
    ]
    for n in args.envs:
        rows.append((f"{env_id} make_vec N={n}", vector_stepper(env_id, n, False, v, cp), n, cp))
        if not args.no_sb3:
            rows.append(
                (f"{env_id} RovSB3VecEnv N={n}", vector_stepper(env_id, n, True, v, cp), n, cp)
            )
    big = max(args.envs)
    for task in args.extra_tasks:
        tid = f"rov_envs/{task}-v0"
        rows.append((f"{tid} make_vec N={big}", vector_stepper(tid, big, False, v, cp), big, cp))

    print(
        f"vehicle {v}, control period {cp:g} s; numba {numba.__version__}, "
        f"{numba.get_num_threads()} threads; best of "
        f"{args.rounds} rounds of {args.seconds:g} s; anchor: Pendulum-v1 (gymnasium.make), "
        "actions drawn beforehand"
    )
    print(f"{'row':58s} {'steps/s':>12s} {'x anchor':>9s} {'anchor':>9s} {'sim s/s':>12s}")
    best_anchor_all = 0.0
    for name, step, n, dt in rows:
        step(0)  # numba cache load / first call outside the timing
        best, best_anchor = 0.0, 0.0
        for _ in range(args.rounds):
            best_anchor = max(best_anchor, timed(anchor, args.seconds / 2))
            best = max(best, timed(step, args.seconds) * n)
        best_anchor_all = max(best_anchor_all, best_anchor)
        sim = best * dt
        print(
            f"{name:58s} {best:12,.0f} {best / best_anchor:8.2f}x {best_anchor:9,.0f} {sim:12,.0f}"
        )
    print(f"(best Pendulum-v1 anchor over the run: {best_anchor_all:,.0f} steps/s)")
    try:
        print(f"numba threading layer: {numba.threading_layer()}")
    except ValueError:  # no parallel kernel ran
        pass


if __name__ == "__main__":
    main()
