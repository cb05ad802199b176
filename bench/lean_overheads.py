"""The lean ``predict``, fused-Adam step and deferred gate counting against SB3's ``predict``,
PyTorch's ``Adam.step`` and a gate count per prediction.

Both lean paths give the same bits as the ones they replace (tests/dsac/test_lean_*.py); this
times what they save. For the study's SPNN and PNN on PlanningStraight-v0 ([64, 64], batch 256,
one torch thread, untrained priors of the study's sizes) it prints, per learner, the cost of

* ``predict`` of one observation: SB3's ``BasePolicy.predict`` with SPNN's gate-lead counts
  added up on every call (``PENDING_LEADS = 1``; the anchor) vs the package's (counted when
  read);
* one critic optimizer step (gradients in place): ``torch.optim.Adam(fused=True)`` (anchor) vs
  :class:`sb3_pnn.dsac.lean_adam.LeanFusedAdam`, on the same parameters;
* the study's cycle at one update per 4 steps (``train(1)`` + 4 ``predict``, no environment):
  the same model with SB3's predict and PyTorch's Adam put back (anchor) vs as built.

and, for SPNN alone, ``predict`` with the gate-lead count added up on every call (anchor) vs
counted when read, on the same lean model. Rounds alternate between anchor and lean, the
median of ``--repeats`` rounds is kept.

Usage: python bench/lean_overheads.py [--cycles 300] [--repeats 3]
"""

from __future__ import annotations

import statistics
import tempfile
import time
import types
from pathlib import Path

import gymnasium as gym
import torch as th
from dsac_update import _cycle_cost, untrained_priors  # bench/ is the script's folder
from frozen_cache_bound import ENV_KWARGS, SPNN_STUDY, cycle_bench_args, study_model_makers
from stable_baselines3.common.policies import BasePolicy

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC


def _with_sb3_paths(model: DiscreteSAC) -> DiscreteSAC:
    """The model with SB3's ``predict``, PyTorch's fused ``Adam`` (same state) and a gate-lead
    count on every prediction put back."""
    model.policy.predict = types.MethodType(BasePolicy.predict, model.policy)  # type: ignore[method-assign]
    model.actor.PENDING_LEADS = 1  # type: ignore[union-attr]
    for net in (model.actor, model.critic):
        lean = net.optimizer
        plain = th.optim.Adam(lean.param_groups[0]["params"], **lean.defaults)
        plain.load_state_dict(lean.state_dict())
        net.optimizer = plain
    return model


def _us_per_call(function, calls: int) -> float:
    start = time.process_time()
    for _ in range(calls):
        function()
    return (time.process_time() - start) / calls * 1e6


def main() -> None:
    args = cycle_bench_args(__doc__.splitlines()[0])
    env = gym.make("rov_envs/PlanningStraight-v0", **ENV_KWARGS)
    with tempfile.TemporaryDirectory() as tmp:
        priors = untrained_priors(Path(tmp), SPNN_STUDY["net_arch"], ENV_KWARGS)
        pairs = {}
        for name, make in study_model_makers(env, priors).items():
            built = [make(), make()]
            for model in built:
                model.learn(600)
                model.train(2, 256)  # optimizer state exists, gradients in place
            pairs[name] = {"anchor": _with_sb3_paths(built[0]), "lean": built[1]}
    obs = pairs["SPNN"]["lean"].env.reset()
    print(f"[64, 64], batch 256, one thread, median of {args.repeats} alternating rounds")
    for name, pair in pairs.items():
        measures = {
            "predict (us)": lambda m: _us_per_call(lambda: m.predict(obs), 20 * args.cycles),
            "critic Adam step (us)": lambda m: _us_per_call(m.critic.optimizer.step, args.cycles),
            "cycle train(1) + 4 predict (ms)": lambda m: _cycle_cost(m, obs, args.cycles, 256),
        }
        for label, measure in measures.items():
            rounds: dict[str, list[float]] = {"anchor": [], "lean": []}
            for _ in range(args.repeats):
                for which, model in pair.items():
                    rounds[which].append(measure(model))
            anchor, lean = (statistics.median(rounds[k]) for k in ("anchor", "lean"))
            print(
                f"  {name:<5} {label:<32} SB3 / PyTorch (anchor) {anchor:8.2f}   "
                f"lean {lean:8.2f}   {lean / anchor:4.2f}x"
            )
    actor = pairs["SPNN"]["lean"].actor
    counted: dict[str, list[float]] = {"per call": [], "when read": []}
    for _ in range(args.repeats):
        for which in counted:
            actor.PENDING_LEADS = 1 if which == "per call" else type(actor).PENDING_LEADS
            counted[which].append(
                _us_per_call(lambda: pairs["SPNN"]["lean"].predict(obs), 20 * args.cycles)
            )
    per_call, when_read = (statistics.median(counted[k]) for k in counted)
    print(
        f"  SPNN  predict, gate leads (us)         per call (anchor) {per_call:8.2f}   "
        f"when read {when_read:8.2f}   {when_read / per_call:4.2f}x"
    )


if __name__ == "__main__":
    main()
