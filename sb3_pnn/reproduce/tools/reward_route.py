"""What the task's own reward pays for a route: the adaptive PID swept over how wide it goes round
obstacles, beside a study's learners, on the planning task.

The route marks of the planning tasks (mean abs(g) <= 2 m, mean abs(a_c) <= 20 deg) ask for
tight detours, while eq. 20 charges -2 per step within 8 m of an obstacle's surface and -4
within 5 m, so a wide detour may pay more than a tight one. This measures the trade on the
study's own planning task (the run's ``"original"`` evaluation task and its env keywords, the
reward as the learners were trained on it) and on the fresh validation seeds 40000+ of
``tools.fresh_route``:

* the adaptive PID (sb3_pnn.baselines.adaptive_pid) at each ``--clearances`` x ``--triggers``
  pair: ``clearance`` is how far it passes a sonar reading, ``trigger_distance`` how near a
  reading starts to push it; wider settings detour wider. Per setting: success, mean return
  (the sum of eq. 17-21 per episode, the env's success bonus included), mean discounted return
  at ``--gamma`` (the learners' discount: the return they maximize), mean abs(g) and abs(a_c),
  and whether the route is within the marks;
* each run of ``--agents`` (kept policy, played as the study evaluated it) on the same
  episodes, per seed and as a mean with its Student-t 95 % interval over seeds.

With ``--parts`` the same episodes are played again and each policy's mean return is split
into its terms per episode: r_c (eq. 18 / 19, the path), r_v (eq. 20, the charges near
obstacles), the terminal reward (eq. 21's -200 or the success bonus), with the episode's steps
and its steps within 8 m of an obstacle's surface (eq. 20's zone).

The summary names the PID setting with the highest return among those that succeed in at
least 98 % of the episodes, and the best one within the marks. If the best setting's route is
outside the marks, the reward pays for a route wider than the marks; if a learner's return is
below an in-mark setting's while its route is wider, its wide route is not what the reward
asks for.

Usage: python -m sb3_pnn.reproduce.tools.reward_route STUDY --path sine
    [--agents spnn pnn] [--seeds 0 1 2] [--clearances 2.5 4.5 8] [--triggers 12 18]
    [--episodes 50] [--gamma 0.99] [--parts]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import torch as th

from sb3_pnn.baselines.adaptive_pid import AdaptivePIDController
from sb3_pnn.common.checks import float_in, positive_int
from sb3_pnn.dsac.dsac import PAPER_GAMMA
from sb3_pnn.evaluation import evaluate_policy_on_task
from sb3_pnn.evaluation.evaluate import DEFAULT_START_NOISE
from sb3_pnn.reproduce.reporting.stats import mean_ci
from sb3_pnn.reproduce.tools.fresh_route import FRESH_SEED
from sb3_pnn.reproduce.tools.replay import run_eval_task, run_folders, run_model, run_played

#: The planning tasks' route marks: mean abs(g) (m) and mean abs(a_c) (deg).
ROUTE_MARK = (2.0, 20.0)
#: Success a PID setting needs to be named the return-best (a wide setting that fails often
#: would otherwise be named for the episodes it survives).
MIN_SUCCESS = 0.98
DEFAULT_CLEARANCES = (2.5, 3.5, 4.5, 6.0, 8.0, 10.0, 12.0)
DEFAULT_TRIGGERS = (12.0, 15.0, 18.0, 25.0)


def measure(policy: Any, env_id: str, env_kwargs: dict, episodes: int, gamma: float) -> dict:
    """Success, mean return, mean discounted return, mean abs(g) (m), mean abs(a_c) (deg) of
    ``policy`` over ``episodes`` greedy episodes on seeds 40000+."""
    result = evaluate_policy_on_task(
        policy,
        env_id,
        n_episodes=episodes,
        seed=FRESH_SEED,
        env_kwargs=env_kwargs,
        discount=gamma,
    )
    return {
        "success": result.success_rate,
        "return": float(np.mean([e.episode_return for e in result.episodes])),
        "discounted": float(np.mean([e.discounted_return for e in result.episodes])),
        "g": result.mean_abs_cross_track,
        "ac": math.degrees(result.mean_abs_heading_error),
    }


#: Eq. 20's outer zone: r_v charges within this distance (m) of an obstacle's surface.
CHARGED_WITHIN = 8.0


def reward_parts(policy: Any, env_id: str, env_kwargs: dict, episodes: int) -> dict:
    """Mean per episode of r_c, r_v and the terminal reward (``info``'s ``r_c``, ``r_v``,
    ``r_terminal``), of the steps and of the steps within :data:`CHARGED_WITHIN` of an
    obstacle's surface, over the greedy episodes :func:`measure` plays (seeds 40000+, the
    evaluation's start noise)."""
    env = gym.make(env_id, **{"start_noise": DEFAULT_START_NOISE, **env_kwargs})
    sums = {"r_c": [], "r_v": [], "terminal": [], "steps": [], "charged": []}
    for episode in range(episodes):
        obs, _ = env.reset(seed=FRESH_SEED + episode)
        state, start, done = None, np.array([True]), False
        totals = dict.fromkeys(sums, 0.0)
        while not done:
            action, state = policy.predict(
                obs, state=state, episode_start=start, deterministic=True
            )
            start = np.array([False])
            obs, _, terminated, truncated, info = env.step(action)
            totals["r_c"] += float(info["r_c"])
            totals["r_v"] += float(info["r_v"])
            totals["terminal"] += float(info["r_terminal"])
            totals["steps"] += 1
            totals["charged"] += float(info["obstacle_distance"] <= CHARGED_WITHIN)
            done = terminated or truncated
        for key, value in totals.items():
            sums[key].append(value)
    return {key: float(np.mean(values)) for key, values in sums.items()}


def parts_cells(m: dict) -> str:
    """Table cells of one :func:`reward_parts`."""
    return (
        f"{m['r_c']:.1f} | {m['r_v']:.1f} | {m['terminal']:.1f} | {m['steps']:.0f} | "
        f"{m['charged']:.1f}"
    )


def within_mark(m: dict) -> bool:
    """Whether a measured route keeps both :data:`ROUTE_MARK` marks."""
    return m["g"] <= ROUTE_MARK[0] and m["ac"] <= ROUTE_MARK[1]


def pid_settings(
    env_id: str, env_kwargs: dict, clearances: list[float], triggers: list[float]
) -> list[tuple[float, float, AdaptivePIDController]]:
    """The adaptive PID (its other gains the env's vehicle's) per (clearance, trigger distance)
    pair, as ``(clearance, trigger, controller)``."""
    env = gym.make(env_id, **env_kwargs)
    return [
        (c, t, AdaptivePIDController.for_env(env, clearance=c, trigger_distance=t))
        for c in clearances
        for t in triggers
    ]


def best(rows: list[dict], in_mark: bool) -> dict | None:
    """The row of highest return among those succeeding in >= :data:`MIN_SUCCESS` of the
    episodes (and within the marks when ``in_mark``); None if there is none."""
    fit = [r for r in rows if r["success"] >= MIN_SUCCESS and (within_mark(r) or not in_mark)]
    return max(fit, key=lambda r: r["return"]) if fit else None


def cells(m: dict) -> str:
    """Table cells of one :func:`measure`."""
    mark = "yes" if within_mark(m) else "no"
    return (
        f"{100 * m['success']:.0f} % | {m['return']:.1f} | {m['discounted']:.1f} | "
        f"{m['g']:.2f} | {m['ac']:.1f} | {mark}"
    )


def positive_floats(parser: argparse.ArgumentParser, name: str, values: list[float]) -> None:
    """Stop the command if any of ``values`` (option ``name``) is not a finite number > 0."""
    if any(not (math.isfinite(v) and v > 0) for v in values):
        parser.error(f"{name} {values} is not allowed: expected distances > 0 (m)")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("study", type=Path)
    parser.add_argument("--path", choices=["straight", "sine"], default="straight")
    parser.add_argument("--agents", nargs="*", default=["spnn", "pnn"])
    parser.add_argument("--seeds", type=int, nargs="*", default=None)
    parser.add_argument("--clearances", type=float, nargs="+", default=list(DEFAULT_CLEARANCES))
    parser.add_argument("--triggers", type=float, nargs="+", default=list(DEFAULT_TRIGGERS))
    parser.add_argument("--episodes", type=positive_int("--episodes"), default=50)
    parser.add_argument(
        "--gamma", type=float_in("--gamma", 0.0, 1.0, "a discount"), default=PAPER_GAMMA
    )
    parser.add_argument(
        "--parts", action="store_true", help="also split each return into its reward terms"
    )
    args = parser.parse_args(argv)
    positive_floats(parser, "--clearances", args.clearances)
    positive_floats(parser, "--triggers", args.triggers)
    th.set_num_threads(1)
    base = args.study / "runs" / f"adaptive_pid-{args.path}"
    if not base.is_dir():
        parser.error(
            f"{base} does not exist: expected a study folder with the adaptive PID's run on the "
            f"{args.path} path (its planning task and env keywords are the ones measured)"
        )
    env_id, env_kwargs = run_eval_task(parser, base, "original")
    print(
        f"{env_id}, {args.episodes} episodes from seed {FRESH_SEED}; return: eq. 17-21 as the "
        f"study trained on it; discounted at gamma {args.gamma:g}; marks: mean abs(g) <= "
        f"{ROUTE_MARK[0]:g} m, mean abs(a_c) <= {ROUTE_MARK[1]:g} deg"
    )
    header = "success | return | discounted | abs(g) (m) | abs(a_c) (deg) | within the marks"
    print(f"| policy | {header} |\n|---|---|---|---|---|---|---|")
    played: list[tuple[str, Any, str, dict]] = []  # (label, policy, env id, env keywords)
    rows = []
    for clearance, trigger, pid in pid_settings(env_id, env_kwargs, args.clearances, args.triggers):
        label = f"adaptive PID, clearance {clearance:g} m, trigger {trigger:g} m"
        row = measure(pid, env_id, env_kwargs, args.episodes, args.gamma)
        rows.append({"clearance": clearance, "trigger": trigger, **row})
        played.append((label, pid, env_id, env_kwargs))
        print(f"| {label} | {cells(row)} |")
    for agent in args.agents:
        measured = []
        for seed, run in run_folders(args.study, agent, args.path, args.seeds):
            if not run.is_dir():
                parser.error(f"{run} does not exist: expected the study's {agent} run")
            policy = run_played(parser, run, run_model(parser, run))
            task_id, task_kwargs = run_eval_task(parser, run, "original")
            m = measure(policy, task_id, task_kwargs, args.episodes, args.gamma)
            measured.append(m)
            played.append((f"{agent}, seed {seed}", policy, task_id, task_kwargs))
            print(f"| {agent}, seed {seed} | {cells(m)} |")
        if measured:
            mean = {k: float(np.mean([m[k] for m in measured])) for k in measured[0]}
            _, lo, hi = mean_ci([m["return"] for m in measured])
            interval = f"return [{lo:.0f}, {hi:.0f}]"
            print(f"| {agent}, mean of {len(measured)} | {cells(mean)} ({interval}) |")
    if args.parts:
        print(
            f"\nthe return's terms, mean per episode (charged steps: within "
            f"{CHARGED_WITHIN:g} m of an obstacle's surface)"
        )
        print(
            "| policy | r_c | r_v | terminal | steps | charged steps |\n|---|---|---|---|---|---|"
        )
        for label, policy, task_id, task_kwargs in played:
            parts = reward_parts(policy, task_id, task_kwargs, args.episodes)
            print(f"| {label} | {parts_cells(parts)} |")
    for label, row in (
        ("highest return", best(rows, False)),
        ("within the marks", best(rows, True)),
    ):
        if row is None:
            print(f"{label}: no PID setting succeeds in {100 * MIN_SUCCESS:.0f} % of episodes")
        else:
            print(
                f"{label}: clearance {row['clearance']:g} m, trigger {row['trigger']:g} m: "
                f"return {row['return']:.1f}, {row['g']:.2f} m, {row['ac']:.1f} deg"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
