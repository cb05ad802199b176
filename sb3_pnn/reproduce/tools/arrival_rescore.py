"""A study's evaluation replayed with an arrival gate: success only near the target point.

The study counts an episode as a success when the vehicle reaches the end of its path anywhere
inside the corridor (or comes within 2 m of the target point). The paper's vehicle must "avoid
the obstacle and return to the set path to complete the task" (section 4.2.1). This tool
replays every run's kept policy, as the study played it, on each of its evaluation tasks (the
same env keywords, evaluation seeds, episodes and start noise, read from the run's eval.json)
with rov_envs' ``arrival_gate=M``: an end of the path passed farther than M m from the target
point fails (``missed_target``). It prints, per agent, path and task, the mean success over the
runs as evaluated and with the gate, and the gated success per run.

It reads evaluation episodes: a report of measured results, to be run after every decision,
never to choose anything.

Usage: python -m sb3_pnn.reproduce.tools.arrival_rescore STUDY --arrival-gate 5
    [--agents spnn pnn sac_multi sac_single adaptive_pid] [--paths straight sine]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import torch as th

from sb3_pnn.common.checks import float_in
from sb3_pnn.evaluation import evaluate_policy_on_task
from sb3_pnn.reproduce.tools.replay import gated, run_folders, run_model, run_played

#: The agents of Figure 20, in its order, then the PID baselines.
AGENTS = ("spnn", "pnn", "sac_multi", "sac_single", "adaptive_pid", "pid")


def rescored(parser: argparse.ArgumentParser, run: Path, gate: float) -> dict[str, tuple]:
    """Per evaluation task of ``run``: (success as evaluated, success with the gate)."""
    eval_file = run / "eval.json"
    if not eval_file.is_file():
        parser.error(f"{eval_file} does not exist: expected a finished run of a study")
    tasks = json.loads(eval_file.read_text())
    model = run_model(parser, run)
    agent = json.loads((run / "manifest.json").read_text())["agent"]
    policy = agent if model is None else run_played(parser, run, model)
    out = {}
    for label, task in tasks.items():
        result = evaluate_policy_on_task(
            policy,
            task["env_id"],
            n_episodes=int(task["n_episodes"]),
            seed=int(task["seed"]),
            start_noise=tuple(task["start_noise"]),
            env_kwargs=gated(task["env_kwargs"], gate),
        )
        out[label] = (float(task["success_rate"]), result.success_rate)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("study", type=Path)
    parser.add_argument(
        "--arrival-gate",
        required=True,
        type=float_in("--arrival-gate", 2.0, 100.0, "m from the target point"),
        metavar="M",
        help="an end of the path farther than M m (2-100) from the target point fails",
    )
    parser.add_argument("--agents", nargs="+", choices=AGENTS, default=list(AGENTS))
    parser.add_argument(
        "--paths", nargs="+", choices=["straight", "sine"], default=["straight", "sine"]
    )
    args = parser.parse_args(argv)
    th.set_num_threads(1)
    print(f"{args.study}: evaluation replayed with arrival_gate={args.arrival_gate:g} m")
    print("| agent | path | task | success as evaluated | with the gate | per run, with the gate |")
    print("|---|---|---|---|---|---|")
    found = False
    for path in args.paths:
        for agent in args.agents:
            runs = [run for _, run in run_folders(args.study, agent, path, None) if run.is_dir()]
            if not runs:
                continue
            found = True
            scores = [rescored(parser, run, args.arrival_gate) for run in runs]
            for label in scores[0]:
                before = [s[label][0] for s in scores]
                after = [s[label][1] for s in scores]
                per_run = " ".join(f"{100 * a:.0f}" for a in after)
                print(
                    f"| {agent} | {path} | {label} | {100 * np.mean(before):.1f} % | "
                    f"{100 * np.mean(after):.1f} % | {per_run} |"
                )
    if not found:
        parser.error(f"{args.study / 'runs'} holds no run of {args.agents} on {args.paths}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
