"""The physics core alone, beside Gymnasium's Pendulum-v1 stepped in the same run.

Prints nanoseconds per vehicle-step (one 0.2 s step, the physics layer's default, in 4
exponential-RK4 substeps) and the ratio of vehicle-steps per second to Pendulum-v1 steps per
second, for each vehicle preset (``--vehicles``, default both), for:

* ``integrator.advance_blocks`` (parameters read at run time) and the preset kernel
  ``advance_block_vehicle`` that the environments run, on one thread;
* ``integrator.advance_blocks_parallel`` on numba's threads;
* the whole environment kernel ``kernel.step_batch_parallel`` (physics, guidance, sonar, rewards,
  autoresets), called directly without the Gymnasium layer;

and whether LLVM turned the per-block vehicle loop into SIMD code (packed ``v...pd``
instructions on ymm/zmm registers): without it every figure drops about 4x. Workload: random
Table 1 commands, vehicles spread over their own states. Timings are the best of ``--repeats``.

    python bench/physics_speed.py [--n-envs 1024] [--repeats 5] [--seconds 0.5]
        [--vehicles uuv_simulator wu2018]
"""

from __future__ import annotations

import argparse
import math
import re
import time
from collections.abc import Callable

import gymnasium as gym
import numba
import numpy as np
from numba import njit, types

from rov_envs.physics import ACTION_TABLE
from rov_envs.physics import integrator as I  # noqa: E741 (the module's short name)
from rov_envs.physics.params import VEHICLES, vehicle_code, vehicle_params
from rov_envs.sim import kernel as K
from rov_envs.sim.engine import RovBatch


def best_rate(step: Callable[[], None], seconds: float, repeats: int) -> float:
    """Best calls per second over ``repeats`` loops of about ``seconds`` each."""
    step()
    n = 4
    while True:  # calibrate
        t0 = time.perf_counter()
        for _ in range(n):
            step()
        el = time.perf_counter() - t0
        if el > 0.05:
            break
        n *= 4
    n = max(4, int(n * seconds / el))
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(n):
            step()
        best = min(best, time.perf_counter() - t0)
    return n / best


@njit(cache=True, _nrt=False)
def _advance_preset_serial(buf, vehicle, dt, n_substeps):
    coef = I.vehicle_coefficients(vehicle, dt, n_substeps)
    for b in range(buf.shape[0] // I.BLOCK):
        I.advance_block_vehicle(buf, b, vehicle, coef, dt, n_substeps)


def simd_report(vehicle: str) -> str:
    """Packed double-precision instructions in the compiled vehicle loop, by register width."""
    cached = getattr(I, f"_substep_{vehicle}")
    flags = {k: v for k, v in I._JIT_PRESET.items() if k != "cache"}
    fresh = njit(**flags)(cached.py_func)  # cached code cannot be inspected: compile anew
    f8 = types.float64
    coef = types.UniTuple(types.UniTuple(f8, 6), 6)
    fresh.compile((types.float64[::1], types.uint64, types.float64[::1], coef, f8, f8, f8, f8))
    asm = fresh.inspect_asm(fresh.signatures[0])
    ymm = len(re.findall(r"\tv\w+pd\t.*%ymm", asm))
    zmm = len(re.findall(r"\tv\w+pd\t.*%zmm", asm))
    scalar = len(re.findall(r"\tv\w+sd\t", asm))
    verdict = "SIMD" if ymm + zmm > scalar else "NOT vectorised"
    return f"{verdict}: {zmm} zmm + {ymm} ymm packed vs {scalar} scalar instructions"


def pendulum_rate(seconds: float, repeats: int) -> float:
    env = gym.make("Pendulum-v1")
    env.reset(seed=0)
    acts = list(np.random.default_rng(0).uniform(-2, 2, (4096, 1)).astype(np.float32))
    k = [0]

    def step() -> None:
        _, _, te, tr, _ = env.step(acts[k[0] % 4096])
        k[0] += 1
        if te or tr:
            env.reset()

    return best_rate(step, seconds, repeats)


def vehicle_rows(vehicle: str, n: int, dt: float, nsub: int) -> list[tuple[str, Callable]]:
    """The timed workloads of one preset."""
    p = vehicle_params(vehicle).to_array()
    code = vehicle_code(vehicle)
    rng = np.random.default_rng(0)
    buf = I.new_lanes(n)
    rows = buf.reshape(-1, I.ROWS, I.LANES)
    cmds = ACTION_TABLE[rng.integers(0, 5, (rows.shape[0], I.LANES))]  # (blocks, lanes, 6)
    rows[:, I.ROW_CMD : I.ROW_CMD + 6, :] = cmds.transpose(0, 2, 1)
    for _ in range(20):  # spread the vehicles over their own states
        I.advance_blocks(buf, p, dt, nsub)
    batch = RovBatch(n, "PlanningStraight", vehicle=vehicle)
    batch.reset_all(list(range(n)))
    actions = [rng.integers(0, 5, n) for _ in range(64)]
    k = [0]

    def env_kernel() -> None:
        k[0] += 1
        K.step_batch_parallel(
            K.MODE_NEXT_STEP, n, actions[k[0] % 64], batch._no_cont, False, *batch.step_arrays
        )

    return [
        (f"advance_blocks (run-time params), 1 thread [{vehicle}]",
         lambda: I.advance_blocks(buf, p, dt, nsub)),
        (f"advance_block_vehicle (env physics), 1 thread [{vehicle}]",
         lambda: _advance_preset_serial(buf, code, dt, nsub)),
        (f"advance_blocks_parallel (run-time params) [{vehicle}]",
         lambda: I.advance_blocks_parallel(buf, p, dt, nsub)),
        (f"env kernel step_batch_parallel, PlanningStraight [{vehicle}]", env_kernel),
    ]  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n-envs", type=int, default=1024, help="vehicles")
    ap.add_argument("--repeats", type=int, default=5, help="timed repeats (best is kept)")
    ap.add_argument("--seconds", type=float, default=0.5, help="length of one timed repeat")
    ap.add_argument("--vehicles", nargs="+", default=list(VEHICLES), choices=VEHICLES)
    args = ap.parse_args()
    if args.n_envs < 1 or args.repeats < 1 or not args.seconds > 0:
        raise SystemExit("--n-envs and --repeats must be >= 1 and --seconds > 0")
    n = args.n_envs
    dt, nsub = 0.2, 4
    work = [row for v in args.vehicles for row in vehicle_rows(v, n, dt, nsub)]
    for _, fn in work:
        fn()  # compile / load the numba cache before timing
    pend = pendulum_rate(args.seconds, args.repeats)
    print(
        f"{n} vehicles, control period {dt} s, {nsub} exponential-RK4 substeps, "
        f"{numba.get_num_threads()} numba threads"
    )
    for v in args.vehicles:
        print(f"vehicle loop [{v}]: {simd_report(v)}")
    print(f"{'workload':66s} {'ns/vehicle-step':>16s} {'vehicle-steps/s':>16s} {'x Pendulum':>11s}")
    print(
        f"{'Pendulum-v1 (gymnasium.make), anchor':66s} {1e9 / pend:16.1f} {pend:16,.0f} {1:11.2f}"
    )
    for name, fn in work:
        rate = best_rate(fn, args.seconds, args.repeats) * n
        print(f"{name:66s} {1e9 / rate:16.1f} {rate:16,.0f} {rate / pend:11.2f}")


if __name__ == "__main__":
    main()
