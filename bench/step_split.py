"""Where a training step of the study's learners goes, and what half the batch would save.

For the study's DiscreteSAC (SAC-Single), PNN and SPNN on PlanningStraight (set-up ``ours`` with
one update per 4 steps, as ``--set updates=step:4``), one torch thread, CPU time per environment
step of ``learn()``:

* the whole step, updates included (the anchor: every share below is of this figure, measured
  in the same run);
* the same ``learn()`` with ``train`` replaced by a no-op (rollout: ``predict``, the
  environment, SB3's buffer and callbacks), hence the updates' share;
* one ``predict`` on one observation, and one step of the vectorized environment.

Then one ``train(1)`` at ``--batch`` and at half of it, alternating, median of ``--repeats``
rounds: the ratio is what a smaller batch would save per update.

Usage: python bench/step_split.py [--priors PF.zip OA.zip] [--steps 4000] [--repeats 3]
(without --priors: untrained columns of the study's widths; the timing does not depend on
their weights, though episode lengths, and so resets, do a little)
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import gymnasium as gym
import numpy as np
import torch as th
from dsac_update import _cost, positive_int, untrained_priors  # bench/ is the script's folder
from run_hash import study_learner

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC
from sb3_pnn.reproduce.planning.setups import OURS

ENV = "rov_envs/PlanningStraight-v0"
SETUP = OURS.with_(updates="step:4")
#: Printed name -> (run_hash.study_learner's agent name, how many of the priors it reads).
LEARNERS = {"SAC-Single": ("sac", 0), "PNN": ("pnn", 1), "SPNN": ("spnn", 2)}


def _per_step_us(model: DiscreteSAC, steps: int) -> float:
    start = time.process_time()
    model.learn(steps, reset_num_timesteps=False)
    return (time.process_time() - start) / steps * 1e6


def _split(model: DiscreteSAC, steps: int) -> dict[str, float]:
    """Microseconds per environment step: whole, rollout only, predict, environment."""
    whole = _per_step_us(model, steps)
    model.train = lambda *args, **kwargs: None  # type: ignore[method-assign]
    try:
        rollout = _per_step_us(model, steps)
    finally:
        del model.train  # the class's method again
    obs = model.env.reset()
    start = time.process_time()
    for _ in range(steps):
        model.predict(obs, deterministic=False)
    predict = (time.process_time() - start) / steps * 1e6
    actions = np.zeros(model.env.num_envs, dtype=np.int64)
    start = time.process_time()
    for _ in range(steps):
        model.env.step(actions)
    env_step = (time.process_time() - start) / steps * 1e6
    return {"whole": whole, "rollout": rollout, "predict": predict, "env": env_step}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--priors", nargs="*", default=[], help="[path following, avoidance]")
    parser.add_argument("--steps", type=positive_int, default=4000)
    parser.add_argument("--repeats", type=positive_int, default=3)
    parser.add_argument("--batch", type=positive_int, default=256)
    args = parser.parse_args()
    if args.priors and len(args.priors) != 2:
        parser.error(f"--priors takes two zips (path following, avoidance), got {args.priors}")
    if args.batch < 2:
        parser.error(f"--batch {args.batch} is not allowed: expected >= 2 (it is halved)")
    th.set_num_threads(1)
    env = gym.make(ENV, **SETUP.train_env_kwargs())
    with tempfile.TemporaryDirectory() as tmp:
        arch = list(SETUP.net_arch)
        priors = args.priors or untrained_priors(Path(tmp), arch, SETUP.env_kwargs())
        learners = {
            name: study_learner(agent, env, priors[:n_priors], SETUP, "straight")
            for name, (agent, n_priors) in LEARNERS.items()
        }
    for model in learners.values():
        model.learn(1000)  # past learning_starts: every 4th step updates
    print(f"per environment step (us, CPU, one thread; {args.steps} steps of learn())")
    print(f"  {'learner':<11} {'step':>7} {'updates':>14} {'predict':>13} {'env':>11} {'rest':>11}")
    for name, model in learners.items():
        s = _split(model, args.steps)
        rest = s["rollout"] - s["predict"] - s["env"]
        share = {k: 100 * v / s["whole"] for k, v in s.items()}
        updates = s["whole"] - s["rollout"]
        print(
            f"  {name:<11} {s['whole']:7.0f} {updates:7.0f} ({100 - share['rollout']:3.0f} %)"
            f" {s['predict']:6.0f} ({share['predict']:3.0f} %)"
            f" {s['env']:4.0f} ({share['env']:3.0f} %)"
            f" {rest:4.0f} ({100 * rest / s['whole']:3.0f} %)"
        )
    half = args.batch // 2
    rounds: dict[tuple[str, int], list[float]] = {}
    for _ in range(args.repeats):
        for name, model in learners.items():
            for batch in (args.batch, half):
                rounds.setdefault((name, batch), []).append(_cost(model, 200, batch))
    print(f"train(1), ms (median of {args.repeats} alternating rounds of 200 updates)")
    for name in learners:
        full = statistics.median(rounds[(name, args.batch)])
        small = statistics.median(rounds[(name, half)])
        print(
            f"  {name:<11} batch {args.batch} {full:5.2f}  batch {half} {small:5.2f}  "
            f"({small / full:4.2f}x)"
        )


if __name__ == "__main__":
    main()
