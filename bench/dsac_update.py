"""Cost of one DiscreteSAC gradient step, beside SB3 DQN's on the same networks (the anchor).

Prints milliseconds per gradient step (CPU time, one torch thread) for DiscreteSAC with plain
columns (with its default fused Adam and with PyTorch's default for-each Adam) and with the SPNN's
three columns (also with half of each batch mirrored, ``mirror=rov_envs.LEFT_RIGHT_MIRROR``,
and with the prior KL term over off-path copies of each batch, ``off_path_kl=1``, the study's
sine SPNN), and for SB3's DQN (one Q-network and its target, the
cheapest off-policy update SB3 ships), on PlanningStraight-v0's observation, batch 256, and the
ratio DiscreteSAC / DQN. Timings alternate between the learners, ``--repeats`` rounds, and the
median round is kept, so that other load on the machine affects all of them alike.

A second table gives the cost of ``predict`` on one observation, what every environment step of
a training run pays beside the updates (SB3 switches the policy to eval mode, converts the
observation, runs the actor), with the same anchor.

A third gives the cost of the study's cycle at one update per 4 environment steps: one
``train(1)`` call (which switches the policy to train mode) and 4 ``predict`` calls (each
switching it back to eval mode), without the environment; the study's transfer runs are about
35 000 such cycles each.

Usage: python bench/dsac_update.py [--nets 64,64 255,255] [--updates 200] [--repeats 5]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import gymnasium as gym
import torch as th
from stable_baselines3 import DQN

import rov_envs  # registers the tasks
from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy

ENV = "rov_envs/PlanningStraight-v0"
ENV_KWARGS = {"motion_obs": True}


def positive_int(text: str) -> int:
    """argparse type: an integer >= 1 (counts of rounds, updates, cycles)."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not allowed: expected an integer >= 1")
    return value


def untrained_priors(folder: Path, arch: list[int], env_kwargs: dict) -> list[str]:
    """Saved, untrained DiscreteSAC path-following and obstacle-avoidance columns of hidden
    widths ``arch`` (timing does not depend on their weights): [pf.zip, oa.zip]."""
    paths = []
    for task in ("PathFollowingStraight", "ObstacleAvoidance"):
        prior = DiscreteSAC(
            "MultiInputPolicy",
            gym.make(f"rov_envs/{task}-v0", **env_kwargs),
            policy_kwargs={"net_arch": arch},
            device="cpu",
        )
        paths.append(str(folder / f"{task}.zip"))
        prior.save(paths[-1])
    return paths


def _filled(model, steps: int):
    model.learn(steps)
    return model


def _cost(model, updates: int, batch: int) -> float:
    start = time.process_time()
    model.train(updates, batch)
    return (time.process_time() - start) / updates * 1e3


def _rounds(learners: dict, repeats: int, measure) -> dict[str, list[float]]:
    """``repeats`` rounds of ``measure(model)``, alternating between the learners."""
    rounds: dict[str, list[float]] = {name: [] for name in learners}
    for _ in range(repeats):
        for name, model in learners.items():
            rounds[name].append(measure(model))
    return rounds


def _predict_cost(model, obs, calls: int) -> float:
    start = time.process_time()
    for _ in range(calls):
        model.predict(obs, deterministic=False)
    return (time.process_time() - start) / calls * 1e3


def _cycle_cost(
    model, obs, cycles: int, batch: int, steps_per_update: int = 4, clock=time.process_time
) -> float:
    """Milliseconds per cycle by ``clock`` (CPU time by default; ``bench/gpu_vs_cpu.py`` passes
    a wall clock that first waits for the model's GPU)."""
    start = clock()
    for _ in range(cycles):
        model.train(1, batch)
        for _ in range(steps_per_update):
            model.predict(obs, deterministic=False)
    return (clock() - start) / cycles * 1e3


def _print_rounds(title: str, rounds: dict[str, list[float]], unit: str) -> None:
    anchor = statistics.median(rounds["DQN (anchor)"])
    print(title)
    for name, values in rounds.items():
        ms = statistics.median(values)
        print(f"  {name:<27} {ms:7.3f} ms {unit}  ({ms / anchor:4.2f}x DQN)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nets", nargs="+", default=["64,64", "255,255"])
    parser.add_argument("--updates", type=positive_int, default=200)
    parser.add_argument("--repeats", type=positive_int, default=5)
    parser.add_argument("--batch", type=positive_int, default=256)
    args = parser.parse_args()
    th.set_num_threads(1)
    env = gym.make(ENV, **ENV_KWARGS)
    sac_kw = dict(learning_starts=0, gradient_steps=0, device="cpu", seed=0, buffer_size=20_000)
    with tempfile.TemporaryDirectory() as tmp:
        for net in args.nets:
            arch = [int(w) for w in net.split(",")]
            prior_paths = untrained_priors(Path(tmp), arch, ENV_KWARGS)
            learners = {
                "DQN (anchor)": DQN(
                    "MultiInputPolicy",
                    env,
                    policy_kwargs={"net_arch": arch},
                    learning_starts=0,
                    train_freq=1,
                    gradient_steps=0,
                    device="cpu",
                    seed=0,
                    buffer_size=20_000,
                ),
                "DiscreteSAC": DiscreteSAC(
                    "MultiInputPolicy", env, policy_kwargs={"net_arch": arch}, **sac_kw
                ),
                "DiscreteSAC, for-each Adam": DiscreteSAC(
                    "MultiInputPolicy",
                    env,
                    policy_kwargs={"net_arch": arch, "optimizer_kwargs": {"fused": False}},
                    **sac_kw,
                ),
                "DiscreteSAC + PNN": DiscreteSAC(
                    ProgressivePolicy,
                    env,
                    policy_kwargs={"net_arch": arch, "priors": prior_paths[:1]},
                    **sac_kw,
                ),
                "DiscreteSAC + SPNN": DiscreteSAC(
                    SelectivePolicy,
                    env,
                    policy_kwargs={"net_arch": arch, "priors": prior_paths},
                    **sac_kw,
                ),
                "DiscreteSAC + SPNN, off-path KL": DiscreteSAC(
                    SelectivePolicy,
                    env,
                    policy_kwargs={"net_arch": arch, "priors": prior_paths, "off_path_kl": 1.0},
                    **sac_kw,
                ),
                "DiscreteSAC + SPNN, mirror": DiscreteSAC(
                    SelectivePolicy,
                    env,
                    policy_kwargs={"net_arch": arch, "priors": prior_paths},
                    mirror=rov_envs.LEFT_RIGHT_MIRROR,
                    **sac_kw,
                ),
            }
            for model in learners.values():
                _filled(model, 2 * args.batch)
                _cost(model, 10, args.batch)  # warm-up
            rounds = _rounds(learners, args.repeats, lambda m: _cost(m, args.updates, args.batch))
            title = f"networks {arch}, batch {args.batch}, one torch thread (median of rounds):"
            _print_rounds(title, rounds, "per gradient step")
            obs, _ = env.reset(seed=0)
            predicts = _rounds(
                learners, args.repeats, lambda m, obs=obs: _predict_cost(m, obs, 10 * args.updates)
            )
            _print_rounds(f"networks {arch}, predict on one observation:", predicts, "per call")
            cycles = _rounds(
                learners,
                args.repeats,
                lambda m, obs=obs: _cycle_cost(m, obs, args.updates, args.batch),
            )
            title = f"networks {arch}, train(1) + 4 predicts (the study's 1 update per 4 steps):"
            _print_rounds(title, cycles, "per cycle")


if __name__ == "__main__":
    main()
