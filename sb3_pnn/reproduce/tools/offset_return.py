"""Does a study's kept policy come back to its path from a parallel offset, or hold it?

Each run's kept policy is put at rest beside its path without obstacles (the run's
``"path_following"`` evaluation task, a path-following column's ``"own"`` task, with their env
keywords), ``g0`` metres off along the path's normal, heading along the path's tangent, and
played greedily, as the study played it, for ``--steps`` steps. The table gives abs(g) after
half and all of the steps for each offset of ``--offsets``. A policy that holds an offset
("straight" chosen where a_c = atan(g / Delta)) keeps abs(g) at g0: nothing brings it back after
an avoidance detour has left it there, whatever its mean route from the usual start noise
(``tools.fresh_route``) shows. The start is the validation-free seed 40000 (only the sonar noise
and nothing else of the episode reads it; there are no obstacles).

``--agent pf_column`` measures the path's path-following source column (runs
``prior-pf_PATH-sN``) on its own task; a PID baseline's run replays the baseline.

Usage: python -m sb3_pnn.reproduce.tools.offset_return STUDY --agent pnn --path straight
    [--seeds 0 1 2] [--offsets 3 6 9 12 15] [--steps 40]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import gymnasium as gym
import numpy as np
import torch as th

from sb3_pnn.common.checks import positive_int
from sb3_pnn.reproduce.tools.fresh_route import (
    FRESH_SEED,
    PF_COLUMN,
    add_run_arguments,
    chosen_runs,
)
from sb3_pnn.reproduce.tools.replay import run_baseline, run_eval_task, run_model, run_played

#: Where along x the vehicle is put: on the straight path, and at the sinusoid's first crest.
START_X = {"straight": 20.0, "sine": 30.0}
DEFAULT_OFFSETS = (3.0, 6.0, 9.0, 12.0, 15.0)


def start_pose(env: gym.Env, path: str, offset: float) -> tuple[float, float, float]:
    """(x, y, heading): ``offset`` metres to the path's left of its point at :data:`START_X`,
    heading along its tangent there (``env``'s own sine amplitude and wavelength)."""
    x0 = START_X[path]
    if path == "straight":
        return x0, offset, 0.0
    config = env.unwrapped.config
    k = 2.0 * math.pi / config.wavelength
    y0 = config.amplitude * math.sin(k * x0)
    tangent = math.atan(config.amplitude * k * math.cos(k * x0))
    return x0 - offset * math.sin(tangent), y0 + offset * math.cos(tangent), tangent


def offset_after(policy, env: gym.Env, path: str, offset: float, steps: int) -> list[float]:
    """abs(g) after every step of ``policy`` played greedily from :func:`start_pose` (the
    episode's end, if it ends earlier, repeats its last abs(g))."""
    env.reset(seed=FRESH_SEED)
    obs = env.unwrapped.set_pose(*start_pose(env, path, offset))
    state, start = None, np.array([True])
    out: list[float] = []
    for _ in range(steps):
        action, state = policy.predict(obs, state=state, episode_start=start, deterministic=True)
        start = np.array([False])
        obs, _, terminated, truncated, info = env.step(action)
        out.append(abs(float(info["cross_track"])))
        if terminated or truncated:
            out += [out[-1]] * (steps - len(out))
            break
    return out


def run_offsets(
    parser: argparse.ArgumentParser, run: Path, path: str, offsets, steps: int, task: str
) -> list[list[float]]:
    """:func:`offset_after` of the run's kept policy (or its PID baseline) per offset."""
    env_id, env_kwargs = run_eval_task(parser, run, task)
    env = gym.make(env_id, **{**env_kwargs, "start_noise": (0.0, 0.0)})
    model = run_model(parser, run)
    policy = run_baseline(run, env) if model is None else run_played(parser, run, model)
    return [offset_after(policy, env, path, g0, steps) for g0 in offsets]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_run_arguments(parser)
    parser.add_argument("--offsets", type=float, nargs="+", default=list(DEFAULT_OFFSETS))
    parser.add_argument("--steps", type=positive_int("--steps"), default=40)
    args = parser.parse_args(argv)
    if any(not (math.isfinite(g) and g > 0) for g in args.offsets):
        parser.error(f"--offsets {args.offsets} is not allowed: expected distances > 0 (m)")
    th.set_num_threads(1)
    runs = chosen_runs(parser, args)
    task = "own" if args.agent == PF_COLUMN else "path_following"
    half = args.steps // 2
    print(
        f"abs(g) (m) after {half} / {args.steps} steps from a parallel offset, "
        f"{args.agent} on the {args.path} path without obstacles"
    )
    print("| seed | " + " | ".join(f"{g:g} m" for g in args.offsets) + " |")
    print("|---|" + "---|" * len(args.offsets))
    for seed, run in runs:
        traces = run_offsets(parser, run, args.path, args.offsets, args.steps, task)
        cells = [f"{t[max(half - 1, 0)]:.1f} / {t[-1]:.1f}" for t in traces]
        print(f"| {seed} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
