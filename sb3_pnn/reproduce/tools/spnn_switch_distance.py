"""A diagnostic: a study's SPNN policies with the gate's switch distance d_th changed after
training, on the training task and the new layouts of Figure 20.

Eq. 15's hard gate hands control to the obstacle-avoidance column when the nearest obstacle is
within d_th. Changing d_th in a trained policy asks whether the new layouts fail because the
gate switches too late or too early. Episodes run on the validation seeds (20000+, never the
study's evaluation seeds 10000+), 1 m / 5 deg start noise, deterministic actions; nothing is
chosen here. Prints, per task and d_th, the success rate over the seeds' episodes, per seed,
and how the episodes ended.

Usage: python -m sb3_pnn.reproduce.tools.spnn_switch_distance STUDY --path straight
    [--d-th 12.5 8 16 20] [--episodes 30] [--seeds 5]
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import torch as th

from sb3_pnn import DiscreteSAC
from sb3_pnn.common.callbacks import VALIDATION_SEED
from sb3_pnn.common.checks import is_finite_number
from sb3_pnn.evaluation import evaluate_policy_on_task
from sb3_pnn.reproduce.planning.plan import EVAL_TASKS
from sb3_pnn.reproduce.planning.setups import OURS


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("study", type=Path)
    parser.add_argument("--path", choices=["straight", "sine"], default="straight")
    parser.add_argument("--d-th", type=float, nargs="+", default=[12.5, 8.0, 16.0, 20.0])
    parser.add_argument("--episodes", type=int, default=30)
    parser.add_argument("--seeds", type=int, default=5)
    args = parser.parse_args()
    for name in ("episodes", "seeds"):
        if getattr(args, name) < 1:
            parser.error(f"--{name} {getattr(args, name)} is not allowed: expected an integer >= 1")
    for d_th in args.d_th:
        if not is_finite_number(d_th) or d_th < 0:
            parser.error(f"--d-th {d_th} is not allowed: expected finite distances >= 0 (m)")
    th.set_num_threads(1)
    tasks = [(label, env_id) for label, env_id, extra in EVAL_TASKS[args.path] if not extra]
    env_kwargs = OURS.env_kwargs()
    success: dict[tuple[str, float], list[int]] = {}
    ends: dict[tuple[str, float], Counter] = {}
    for seed in range(args.seeds):
        zip_path = args.study / "runs" / f"spnn-{args.path}-s{seed}" / "model.zip"
        if not zip_path.exists():
            parser.error(f"{zip_path} does not exist: expected a study folder with SPNN runs")
        model = DiscreteSAC.load(zip_path, device="cpu")
        for d_th in args.d_th:
            model.policy.actor.gate.d_th = d_th  # the actor's gate decides the actions
            for label, env_id in tasks:
                result = evaluate_policy_on_task(
                    model,
                    env_id,
                    n_episodes=args.episodes,
                    seed=VALIDATION_SEED,
                    env_kwargs=env_kwargs,
                )
                success.setdefault((label, d_th), []).append(round(100 * result.success_rate))
                ends.setdefault((label, d_th), Counter()).update(result.end_reasons)
    print(f"SPNN, {args.path} path, {args.episodes} validation episodes per seed and task")
    print("| task | d_th (m) | success | per seed | episodes ended by |")
    print("|---|---|---|---|---|")
    for (label, d_th), rates in success.items():
        ended = ", ".join(f"{k} {v}" for k, v in ends[(label, d_th)].most_common())
        mean = sum(rates) / len(rates)
        print(f"| {label} | {d_th:g} | {mean:.0f} % | {' '.join(map(str, rates))} | {ended} |")


if __name__ == "__main__":
    main()
