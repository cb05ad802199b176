"""How much of a PNN / SPNN training cycle the frozen prior columns cost: an upper bound of
what caching their activations could save.

The study's cycle at one update per 4 steps (one ``train(1)`` and 4 ``predict`` calls,
[64, 64] networks, batch 256, one torch thread) is timed as it is (the anchor) and with
``FrozenColumn.hidden`` answered from a dict of its first answers (shape-right stand-ins, so
the rest of the arithmetic is unchanged); rounds alternate, the median is kept. Priors are
untrained DiscreteSAC columns of the study's sizes (timing does not depend on their weights).

Usage: python bench/frozen_cache_bound.py [--cycles 300] [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
from collections.abc import Callable
from pathlib import Path

import gymnasium as gym
import torch as th
from dsac_update import _cycle_cost, positive_int, untrained_priors  # bench/ is the script's folder

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy
from sb3_pnn.progressive.columns import FrozenColumn
from sb3_pnn.reproduce.planning.setups import OURS

#: The study's environment and policy keywords on PlanningStraight, read from its set-up
ENV_KWARGS = OURS.env_kwargs()
SPNN_STUDY = OURS.sac_kwargs(agent="spnn", path="straight")["policy_kwargs"]
PNN_STUDY = OURS.sac_kwargs(agent="pnn", path="straight")["policy_kwargs"]


def cycle_bench_args(description: str) -> argparse.Namespace:
    """``--cycles`` / ``--repeats`` of the benches that time the study's cycle; one torch thread."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--cycles", type=positive_int, default=300)
    parser.add_argument("--repeats", type=positive_int, default=3)
    args = parser.parse_args()
    th.set_num_threads(1)
    return args


def study_model_makers(env: gym.Env, priors: list[str]) -> dict[str, Callable[[], DiscreteSAC]]:
    """{"SPNN", "PNN"}: functions that build the study's learner on ``env`` with ``priors``
    ([path following, obstacle avoidance]; the PNN reads the first), without learning starts or
    updates of its own (the benches call train() themselves). Call them while the prior files
    exist."""
    kw = dict(device="cpu", seed=0, learning_starts=0, gradient_steps=0, buffer_size=20_000)
    return {
        "SPNN": lambda: DiscreteSAC(
            SelectivePolicy, env, policy_kwargs={**SPNN_STUDY, "priors": priors}, **kw
        ),
        "PNN": lambda: DiscreteSAC(
            ProgressivePolicy, env, policy_kwargs={**PNN_STUDY, "priors": priors[:1]}, **kw
        ),
    }


def main() -> None:
    args = cycle_bench_args(__doc__.splitlines()[0])
    env = gym.make("rov_envs/PlanningStraight-v0", **ENV_KWARGS)
    with tempfile.TemporaryDirectory() as tmp:
        priors = untrained_priors(Path(tmp), SPNN_STUDY["net_arch"], ENV_KWARGS)
        models = {name: make() for name, make in study_model_makers(env, priors).items()}
    for model in models.values():
        model.learn(600)
    obs, _ = env.reset(seed=0)
    real = FrozenColumn.hidden
    answers: dict = {}

    def from_dict(column, x):
        key = (id(column), tuple(x.shape))
        if key not in answers:
            answers[key] = real(column, x)
        return answers[key]

    rounds: dict[tuple[str, str], list[float]] = {}
    try:
        for _ in range(args.repeats):
            for name, model in models.items():
                for mode, hidden in (("computed", real), ("from a dict", from_dict)):
                    FrozenColumn.hidden = hidden
                    rounds.setdefault((name, mode), []).append(
                        _cycle_cost(model, obs, args.cycles, 256)
                    )
    finally:
        FrozenColumn.hidden = real
    print("train(1) + 4 predicts, [64, 64], batch 256, one thread (median of rounds):")
    for name in models:
        anchor = statistics.median(rounds[(name, "computed")])
        bound = statistics.median(rounds[(name, "from a dict")])
        print(
            f"  {name}: {anchor:.3f} ms per cycle with the prior columns computed, "
            f"{bound:.3f} ms answered from a dict ({bound / anchor:.2f}x, "
            f"at most {1 - bound / anchor:.0%} to save)"
        )


if __name__ == "__main__":
    main()
