"""Should the study's learners train on a GPU? Wall time of the study's cycle on each device.

The cycle is the one ``bench/dsac_update.py`` times: one ``train(1)`` (batch 256) and 4
``predict`` calls on PlanningStraight-v0's observation, the study's one update per 4 steps,
without the environment. Here it is timed in wall-clock time (a GPU works asynchronously, so
CPU time would flatter it; the GPU is synchronized before each clock reading) for DiscreteSAC,
PNN and SPNN with [64, 64] columns, on the CPU with one torch thread and on CUDA, beside SB3's
DQN cycle on the CPU (the anchor of ``bench/``). Rounds alternate between the learners and the
median round is kept. On a machine without CUDA it times the CPU alone.

Usage: python bench/gpu_vs_cpu.py [--cycles 200] [--repeats 3] [--nets 64,64]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import gymnasium as gym
import torch as th
from dsac_update import (
    ENV,
    ENV_KWARGS,
    _cycle_cost,
    _print_rounds,
    _rounds,
    positive_int,
    untrained_priors,
)
from stable_baselines3 import DQN

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy


def _cycle_wall_ms(model, obs, cycles: int) -> float:
    """``bench/dsac_update.py``'s cycle in wall time, the GPU synchronized at each reading."""

    def clock() -> float:
        if model.device.type == "cuda":
            th.cuda.synchronize()
        return time.perf_counter()

    return _cycle_cost(model, obs, cycles, 256, clock=clock)


def _learners(env, arch: list[int], priors: list[str], devices: list[str]) -> dict[str, object]:
    kw = dict(learning_starts=0, gradient_steps=0, seed=0, buffer_size=20_000)
    learners: dict[str, object] = {
        "DQN (anchor)": DQN(
            "MultiInputPolicy",
            env,
            policy_kwargs={"net_arch": arch},
            train_freq=1,
            device="cpu",
            **kw,
        )
    }
    for device in devices:
        learners[f"DiscreteSAC, {device}"] = DiscreteSAC(
            "MultiInputPolicy", env, policy_kwargs={"net_arch": arch}, device=device, **kw
        )
        learners[f"PNN, {device}"] = DiscreteSAC(
            ProgressivePolicy,
            env,
            policy_kwargs={"net_arch": arch, "priors": priors[:1]},
            device=device,
            **kw,
        )
        learners[f"SPNN, {device}"] = DiscreteSAC(
            SelectivePolicy,
            env,
            policy_kwargs={"net_arch": arch, "priors": priors},
            device=device,
            **kw,
        )
    return learners


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=positive_int, default=200)
    parser.add_argument("--repeats", type=positive_int, default=3)
    parser.add_argument("--nets", default="64,64")
    args = parser.parse_args()
    th.set_num_threads(1)
    devices = ["cpu", "cuda"] if th.cuda.is_available() else ["cpu"]
    if len(devices) == 1:
        print("no CUDA device: timing the CPU alone")
    else:
        print(f"GPU: {th.cuda.get_device_name(0)}")
    arch = [int(w) for w in args.nets.split(",")]
    env = gym.make(ENV, **ENV_KWARGS)
    obs, _ = env.reset(seed=0)
    with tempfile.TemporaryDirectory() as tmp:
        priors = untrained_priors(Path(tmp), arch, ENV_KWARGS)
        learners = _learners(env, arch, priors, devices)
        for model in learners.values():
            model.learn(1_000)  # fills the buffer (no updates: gradient_steps=0)
            _cycle_wall_ms(model, obs, 5)  # warm-up
        rounds = _rounds(learners, args.repeats, lambda m: _cycle_wall_ms(m, obs, args.cycles))
    _print_rounds(
        f"networks {arch}, train(1) + 4 predicts, wall time (median of {args.repeats} rounds); "
        "DQN on the CPU:",
        rounds,
        "per cycle",
    )


if __name__ == "__main__":
    main()
