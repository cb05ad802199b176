"""Cost of the study's own gradient steps, each with and without its prior-KL copy terms, beside
SB3 DQN's (the anchor).

The study's learners differ in what one gradient step computes: PNN and SPNN run their frozen
columns beside the new one, and some runs add the prior KL term over made-up copies of each
batch (``off_path_kl``, ``clear_kl``, ``obstacle_kl``; sb3_pnn.progressive's off_path and
obstacle_copies), each a further pass of the actor with its columns. This prints, for each run
kind of the default study (as ``python -m sb3_pnn.reproduce`` plans it, seed 0), milliseconds
per gradient step (CPU time, one torch thread) as planned and with those terms' weights set to
0, and the ratio to SB3's DQN on the same networks, so the figures carry over between machines.
The priors are untrained columns of the planned shapes: the cost does not depend on weights.

Usage: python bench/study_updates.py [--runs spnn-sine pnn-straight ...] [--updates 200]
[--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

import torch as th
from stable_baselines3 import DQN

from sb3_pnn.common.checks import positive_int
from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.running.work import build_model

#: The prior-KL terms over copies of each batch (policy attributes: their weights).
COPY_TERMS = ("off_path_kl", "clear_kl", "obstacle_kl")
#: Run kinds timed by default: every learner of the study and the avoidance column.
DEFAULT_RUNS = (
    "spnn-sine",
    "spnn-straight",
    "pnn-sine",
    "pnn-straight",
    "sac_multi-sine",
    "sac_single-sine",
    "prior-oa",
)


def planned_specs(kinds: list[str]) -> tuple[dict[str, Any], dict[str, Any]]:
    """Seed 0's run spec of each kind (``"<agent>-<path>"`` or ``"prior-<column>"``) of the
    default study, and every run spec of seed 0 by run id (the priors they read); a kind the
    study does not plan is refused by name."""
    by_id = {spec.run_id: spec for spec in build_plan(StudyConfig(seeds=1))}
    missing = [k for k in kinds if f"{k}-s0" not in by_id]
    if missing:
        known = sorted({run_id.rsplit("-s", 1)[0] for run_id in by_id if "-s" in run_id})
        raise SystemExit(
            f"run kinds {missing} are not in the default study; expected some of {known}"
        )
    return {kind: by_id[f"{kind}-s0"] for kind in kinds}, by_id


def untrained_deps(spec: Any, by_id: dict[str, Any], folder: Path) -> dict[str, Path]:
    """Each prior ``spec`` reads, untrained and saved where :func:`build_model` looks for it."""
    deps = {}
    for dep in spec.deps:
        run = folder / dep
        if not (run / "model.zip").is_file():
            run.mkdir(parents=True, exist_ok=True)
            build_model(by_id[dep], {}).save(run / "model.zip")
        deps[dep] = run
    return deps


def copy_weights(model: Any) -> dict[str, float]:
    """The copy terms the model's policy weighs above 0 (name -> weight)."""
    weights = {name: float(getattr(model.policy, name, 0.0)) for name in COPY_TERMS}
    return {name: weight for name, weight in weights.items() if weight > 0}


def step_ms(model: Any, updates: int, weights: dict[str, float] | None = None) -> float:
    """CPU milliseconds per gradient step of ``model.train``; ``weights`` set the copy terms'
    weights for the measurement (restored after)."""
    before = copy_weights(model)
    for name, value in (weights or {}).items():
        setattr(model.policy, name, value)
    start = time.process_time()
    model.train(updates, model.batch_size)
    elapsed = time.process_time() - start
    for name in weights or {}:
        setattr(model.policy, name, before.get(name, 0.0))
    return elapsed / updates * 1e3


def anchor(model: Any) -> DQN:
    """SB3's DQN on the same environment and hidden widths as ``model``, buffer filled."""
    arch = list(model.policy_kwargs.get("net_arch") or [64, 64])
    dqn = DQN(
        "MultiInputPolicy",
        model.get_env(),
        policy_kwargs={"net_arch": arch},
        learning_starts=0,
        gradient_steps=0,
        batch_size=model.batch_size,
        device="cpu",
        seed=0,
    )
    dqn.learn(2 * model.batch_size)
    return dqn


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", nargs="+", default=list(DEFAULT_RUNS))
    parser.add_argument("--updates", type=positive_int("--updates"), default=200)
    parser.add_argument("--repeats", type=positive_int("--repeats"), default=3)
    args = parser.parse_args()
    th.set_num_threads(1)
    specs, by_id = planned_specs(args.runs)
    print(f"the default study's gradient steps (seed 0's specs), median of {args.repeats} rounds")
    print(
        f"{'run':<16} {'copy terms':<44} {'ms/step':>8} {'x DQN':>6} {'no copies':>10} {'x DQN':>6}"
    )
    with tempfile.TemporaryDirectory() as tmp:
        for kind, spec in specs.items():
            model = build_model(spec, untrained_deps(spec, by_id, Path(tmp)))
            model.learn(model.learning_starts + 2 * model.batch_size)
            dqn = anchor(model)
            terms = copy_weights(model)
            off = {name: 0.0 for name in terms}
            rounds: dict[str, list[float]] = {"dqn": [], "as planned": [], "no copies": []}
            for _ in range(args.repeats):  # alternating, so that other load hits all alike
                start = time.process_time()
                dqn.train(args.updates, model.batch_size)
                rounds["dqn"].append((time.process_time() - start) / args.updates * 1e3)
                rounds["as planned"].append(step_ms(model, args.updates))
                rounds["no copies"].append(step_ms(model, args.updates, off))
            base = statistics.median(rounds["dqn"])
            planned = statistics.median(rounds["as planned"])
            bare = statistics.median(rounds["no copies"])
            names = ", ".join(f"{n}={w:g}" for n, w in terms.items()) or "none"
            print(
                f"{kind:<16} {names:<44} {planned:8.2f} {planned / base:6.2f} "
                f"{bare:10.2f} {bare / base:6.2f}"
            )
    print("x DQN: against SB3's DQN on the same environment, widths and batch, timed alternately")


if __name__ == "__main__":
    main()
