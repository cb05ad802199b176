"""A diagnostic of weaving: how often a trained agent turns left on one step and right on the next,
by how near the nearest obstacle reads on its sonar.

Per step of deterministic episodes this records the action (Table 1's order: Turn left 1, Turn
left 2, Go straight, Turn right 1, Turn right 2) and the nearest sonar reading the policy
observed, min over sectors times the sonar range (eq. 15's d as the policy sees it). Per band of
that reading it prints the share of steps that reverse the turn of the step before (left after
right or right after left), the share of "Go straight" steps, and the share of steps whose
reading jumps by more than ``--jump`` metres from the step before: with a sonar span under 360
degrees an obstacle beside the vehicle leaves the view when it turns away and comes back when it
turns toward it, so the reading (and SPNN's gate, which switches at d_th) flips with the turns.
It also prints the mean surge speed the steps leave the vehicle at: Table 1's turns drive two of
the four horizontal thrusters, so an agent that alternates turns where "Go straight" would do
crosses a field slower, and a task's time limit (2 x the route at 1 m/s) ends it. Last, per
seed, the share of each action over all steps.
Episodes run on the validation seeds (20000+, never the study's evaluation seeds 10000+) with
the run's env keywords; nothing is chosen here.

A PID baseline (``--agent adaptive_pid``) runs the same episodes, for reference.

Usage: python -m sb3_pnn.reproduce.tools.action_reversals STUDY --agent spnn --path sine
    [--env rov_envs/PlanningSineDense-v0] [--episodes 20] [--seeds 0 1 2] [--jump 3]
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import Any

import gymnasium as gym
import numpy as np
import torch as th

from rov_envs.physics.thrusters import ACTION_NAMES
from sb3_pnn.common.callbacks import VALIDATION_SEED
from sb3_pnn.reproduce.tools.replay import ended, load_run, run_folders, task_id, task_parser

#: Bands of the nearest reading (m): eq. 20's penalty bands (d <= 5, 5 < d <= 8), then up to
#: and beyond eq. 15's d_th = 12.5 m, and the sonar's range (nothing in view).
BAND_EDGES = (5.0, 8.0, 12.5, 17.0)
LEFT, RIGHT = (0, 1), (3, 4)
STRAIGHT = 2


def band_names(sonar_range: float) -> list[str]:
    """Labels of the bands of :data:`BAND_EDGES`, the last one "nothing in view"."""
    edges = (0.0, *BAND_EDGES)
    names = [f"{lo:g}-{hi:g} m" for lo, hi in zip(edges[:-1], edges[1:], strict=True)]
    return [*names, f"{BAND_EDGES[-1]:g}-{sonar_range:g} m", "nothing in view"]


def step_counts(
    actions: Sequence[int],
    nearest: Sequence[float],
    sonar_range: float,
    jump: float,
    surge: Sequence[float] | None = None,
) -> Counter:
    """Per (band, what) step counts of one episode: "steps", "reversals" (the turn's side is the
    opposite of the step before), "straight" and "jumps" (the reading moved by more than
    ``jump`` m since the step before); the first step has no step before (no reversal or jump).
    ``nearest[t]`` is the reading the policy observed before choosing ``actions[t]``; with
    ``surge`` (m/s after each step) also "surge", the band's sum of it. ``("action", a)``
    counts the steps of action ``a`` over all bands."""
    actions, nearest = np.asarray(actions), np.asarray(nearest, dtype=float)
    if actions.shape != nearest.shape:
        raise ValueError(f"{actions.shape} actions but {nearest.shape} readings")
    if surge is not None and np.shape(surge) != actions.shape:
        raise ValueError(f"{actions.shape} actions but {np.shape(surge)} surge speeds")
    side = np.where(np.isin(actions, LEFT), -1, np.where(np.isin(actions, RIGHT), 1, 0))
    reversal = np.r_[False, side[1:] * side[:-1] < 0]
    jumped = np.r_[False, np.abs(np.diff(nearest)) > jump]
    names = band_names(sonar_range)
    band = np.digitize(nearest, BAND_EDGES)
    band[nearest >= sonar_range - 1e-6] = len(names) - 1
    counts: Counter = Counter(("action", int(a)) for a in actions)
    for index, name in enumerate(names):
        here = band == index
        counts[(name, "steps")] += int(here.sum())
        counts[(name, "reversals")] += int(reversal[here].sum())
        counts[(name, "straight")] += int((actions[here] == STRAIGHT).sum())
        counts[(name, "jumps")] += int(jumped[here].sum())
        if surge is not None:
            counts[(name, "surge")] += float(np.asarray(surge, dtype=float)[here].sum())
    return counts


def run_episodes(
    model: Any, env: gym.Env, episodes: int, seed: int, sonar_range: float, jump: float
) -> tuple[Counter, Counter]:
    """Step counts (:func:`step_counts`) over ``episodes`` deterministic episodes from
    ``seed`` of ``model`` (a trained agent or a PID baseline, whose memory is reset at each
    start; sonar readings are distance / ``sonar_range``), and how the episodes ended. The
    surge speed is read from the env's ``info["velocity"]`` where it gives one (rov_envs do)."""
    counts: Counter = Counter()
    ends: Counter = Counter()
    for episode in range(episodes):
        obs, info = env.reset(seed=seed + episode)
        if hasattr(model, "reset"):
            model.reset()
        actions, nearest, surge, done = [], [], [], False
        while not done:
            action, _ = model.predict(obs, deterministic=True)
            actions.append(int(action))
            nearest.append(float(np.min(obs["sonar"])) * sonar_range)
            obs, _, terminated, truncated, info = env.step(action)
            surge.append(float(info["velocity"][0]) if "velocity" in info else np.nan)
            done = terminated or truncated
        counts += step_counts(actions, nearest, sonar_range, jump, surge)
        ends[info.get("end_reason", "none")] += 1
    return counts, ends


def table(rows: list[tuple[int, Counter, Counter]], sonar_range: float) -> list[str]:
    """Markdown rows: per seed and band, the step shares."""
    lines = [
        "| seed | nearest reading | steps | reversals | Go straight | reading jumps "
        "| mean surge | episodes ended by |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for seed, counts, ends in rows:
        for name in band_names(sonar_range):
            steps = counts[(name, "steps")]
            if steps:
                share = {w: counts[(name, w)] / steps for w in ("reversals", "straight", "jumps")}
                lines.append(
                    f"| {seed} | {name} | {steps} | {100 * share['reversals']:.0f} % "
                    f"| {100 * share['straight']:.0f} % | {100 * share['jumps']:.0f} % "
                    f"| {counts[(name, 'surge')] / steps:.2f} m/s | {ended(ends)} |"
                )
    return lines


def action_shares(rows: list[tuple[int, Counter, Counter]]) -> str:
    """Per seed, the share of each of Table 1's actions over all steps: a run that weaves with
    a pair of unequal opposite turns (Turn left 2 and Turn right 1) shows it here."""
    lines = ["actions per seed (" + ", ".join(ACTION_NAMES) + "):"]
    for seed, counts, _ in rows:
        steps = sum(counts[("action", a)] for a in range(len(ACTION_NAMES)))
        shares = " / ".join(
            f"{100 * counts[('action', a)] / max(steps, 1):.0f}" for a in range(len(ACTION_NAMES))
        )
        lines.append(f"  seed {seed}: {shares} %")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = task_parser(__doc__, episodes=20)
    parser.add_argument(
        "--agent", default="spnn", help="the runs' agent (spnn, pnn, ..., pid, adaptive_pid)"
    )
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--jump", type=float, default=3.0, help="metres (default 3)")
    args = parser.parse_args(argv)
    env_id = task_id(parser, args)
    if not args.jump > 0:
        parser.error(f"--jump {args.jump!r} is not allowed: expected a distance > 0 (m)")
    th.set_num_threads(1)
    rows, sonar_range = [], 0.0
    for seed, run in run_folders(args.study, args.agent, args.path, args.seeds):
        model, env = load_run(parser, run, env_id)
        if "sonar" not in env.observation_space.spaces:
            parser.error(f"{env_id} has no sonar: expected a task with obstacles")
        sonar_range = float(env.unwrapped.config.sonar_range)
        episodes = run_episodes(model, env, args.episodes, VALIDATION_SEED, sonar_range, args.jump)
        rows.append((seed, *episodes))
        env.close()
    print(f"{args.agent} on {env_id}, {args.episodes} validation episodes per seed")
    print("\n".join(table(rows, sonar_range)))
    print(action_shares(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
