"""Micro-benchmark of the physics core beside Gymnasium's Pendulum-v1, stepped in the same run.

Prints steps per second of:
  * Pendulum-v1, two anchors: ``env.step`` with a fixed action (the bare step), and the usual
    random-agent loop ``env.step(env.action_space.sample())`` (the ~16k steps/s figure quoted in
    design.md and issue 2 matches this one on the project machine),
  * one vehicle: the fused kernel with N = 1 (dynamics + sonar + LOS, one Python call per step),
    and ``dynamics.advance`` alone,
  * N vehicles (default 64): ``fused.advance_observe_batch`` and ``dynamics.advance_batch``,
    counted in vehicle-steps per second,
each with its ratio to both Pendulum-v1 anchors. Workload: the PlanningSine layout (sine path,
4 obstacles incl. the paper's two, 9-sector sonar over 180 deg, 25 m range), random Table 1 actions,
default control period and substeps. Timings are the best of several repeats.

    python bench/physics_speed.py [--n-envs 64] [--repeats 5] [--seconds 0.5]
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable

import gymnasium as gym
import numpy as np

from rov_envs.physics import ACTION_TABLE, BlueROV2Params
from rov_envs.physics.dynamics import (
    DEFAULT_CONTROL_PERIOD,
    DEFAULT_SUBSTEPS,
    advance,
    advance_batch,
)
from rov_envs.physics.fused import advance_observe_batch
from rov_envs.physics.guidance import (
    DEFAULT_LOOKAHEAD,
    PATH_SINE,
    SINE_AMPLITUDE,
    SINE_WAVELENGTH,
)

SPAN = math.pi
RANGE = 25.0
Q = 9
OBSTACLES = np.array([[30.0, 17.5, 1.5], [90.0, -12.5, 1.5], [20.0, 8.0, 1.5], [60.0, 2.0, 1.5]])


def best_rate(step: Callable[[], None], calls: int, repeats: int) -> float:
    """Best calls-per-second over ``repeats`` timed loops of ``calls`` calls."""
    step()
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(calls):
            step()
        best = min(best, time.perf_counter() - t0)
    return calls / best


def calibrate(step: Callable[[], None], seconds: float) -> int:
    """Number of calls that take about ``seconds``."""
    step()
    n = 10
    while True:
        t0 = time.perf_counter()
        for _ in range(n):
            step()
        el = time.perf_counter() - t0
        if el > 0.05:
            return max(10, int(n * seconds / el))
        n *= 4


class Fleet:
    """Preallocated buffers for N vehicles on the PlanningSine layout."""

    def __init__(self, n: int, seed: int = 0):
        self.rng = np.random.default_rng(seed)
        self.p = BlueROV2Params().to_array()
        self.states = np.zeros((n, 18))
        self.states[:, 5] = math.atan(SINE_AMPLITUDE * 2 * math.pi / SINE_WAVELENGTH)
        self.currents = np.zeros((n, 3))
        self.obstacles = np.tile(OBSTACLES, (n, 1, 1))
        self.n_obs = np.full(n, OBSTACLES.shape[0], dtype=np.int64)
        self.sonar = np.empty((n, Q))
        self.nearest = np.empty(n)
        self.guide = np.full((n, 3), math.nan)
        self.actions = self.rng.integers(0, 5, (4096, n))
        self.cmds = np.empty((n, 6))
        self.t = 0

    def _next_cmds(self) -> None:
        self.cmds[:] = ACTION_TABLE[self.actions[self.t % 4096]]
        self.t += 1
        if self.t % 1500 == 0:  # restart the episode now and then, like an env would
            self.states[:] = 0.0
            self.guide[:, 2] = math.nan

    def fused(self) -> None:
        self._next_cmds()
        advance_observe_batch(
            self.states, self.cmds, self.p, self.currents, DEFAULT_CONTROL_PERIOD,
            DEFAULT_SUBSTEPS, self.obstacles, self.n_obs, SPAN, RANGE, self.sonar, self.nearest,
            PATH_SINE, SINE_AMPLITUDE, SINE_WAVELENGTH, DEFAULT_LOOKAHEAD, self.guide,
        )  # fmt: skip

    def dynamics(self) -> None:
        self._next_cmds()
        advance_batch(
            self.states, self.cmds, self.p, self.currents, DEFAULT_CONTROL_PERIOD, DEFAULT_SUBSTEPS
        )

    def single_advance(self) -> None:
        self._next_cmds()
        advance(
            self.states[0], self.cmds[0], self.p, self.currents[0], DEFAULT_CONTROL_PERIOD,
            DEFAULT_SUBSTEPS,
        )  # fmt: skip


def pendulum_rate(seconds: float, repeats: int, sample: bool) -> float:
    env = gym.make("Pendulum-v1")
    env.reset(seed=0)
    env.action_space.seed(0)
    fixed = np.array([0.5], dtype=np.float32)

    def step() -> None:
        action = env.action_space.sample() if sample else fixed
        _, _, term, trunc, _ = env.step(action)
        if term or trunc:
            env.reset()

    return best_rate(step, calibrate(step, seconds), repeats)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n-envs", type=int, default=64, help="vehicles in the batched runs")
    ap.add_argument("--repeats", type=int, default=5, help="timed repeats (best is kept)")
    ap.add_argument("--seconds", type=float, default=0.5, help="length of one timed repeat")
    args = ap.parse_args()
    if args.n_envs < 1 or args.repeats < 1 or not args.seconds > 0:
        raise SystemExit("--n-envs and --repeats must be >= 1 and --seconds > 0")

    one = Fleet(1)
    many = Fleet(args.n_envs)
    for f in (one.fused, one.single_advance, many.fused, many.dynamics):
        f()  # compile / load the numba cache before timing

    pend = pendulum_rate(args.seconds, args.repeats, sample=False)
    pend_s = pendulum_rate(args.seconds, args.repeats, sample=True)
    rows = [
        ("Pendulum-v1, fixed action (anchor A)", pend, 1),
        ("Pendulum-v1, action_space.sample() (anchor B)", pend_s, 1),
    ]
    for name, fn, n in (
        ("1 vehicle: fused dynamics+sonar+LOS", one.fused, 1),
        ("1 vehicle: dynamics.advance only", one.single_advance, 1),
        (f"{args.n_envs} vehicles: fused dynamics+sonar+LOS", many.fused, args.n_envs),
        (f"{args.n_envs} vehicles: dynamics.advance_batch only", many.dynamics, args.n_envs),
    ):
        rows.append((name, best_rate(fn, calibrate(fn, args.seconds), args.repeats) * n, n))
    print(
        f"control period {DEFAULT_CONTROL_PERIOD} s, {DEFAULT_SUBSTEPS} RK4 substeps, "
        f"sonar {Q} sectors / {math.degrees(SPAN):.0f} deg / {RANGE:.0f} m, "
        f"{OBSTACLES.shape[0]} obstacles, sine path"
    )
    print(f"{'workload':48s} {'steps/s':>12s} {'us/vehicle-step':>16s} {'x A':>7s} {'x B':>7s}")
    for name, rate, _ in rows:
        print(
            f"{name:48s} {rate:12,.0f} {1e6 / rate:16.3f} {rate / pend:7.1f} {rate / pend_s:7.1f}"
        )


if __name__ == "__main__":
    main()
