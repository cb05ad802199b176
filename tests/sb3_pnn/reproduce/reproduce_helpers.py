"""Stand-in run functions for the study runner's tests (picklable: spawn workers import them).

They write the same files as :func:`sb3_pnn.reproduce.running.work.run_work` (episodes.json,
trajectories.npz, eval.json in the evaluation library's dict format, model.zip for priors) with
synthetic content, in well under a second, and check that their dependencies are finished.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import Any

import numpy as np

from sb3_pnn.reproduce.planning.plan import RunSpec


def _fake_eval(spec: RunSpec, label: str, rate: float) -> dict[str, Any]:
    n = spec.eval_episodes
    k = int(round(rate * n))
    t = np.arange(0, 20.0, 0.2)
    trace = {
        "index": 0,
        "seed": 10_000,
        "success": True,
        "end_reason": "success",
        "t": t.tolist(),
        "x": t.tolist(),
        "y": (np.sin(t) * (1 + spec.seed)).tolist(),
        "heading_error": (0.1 * np.cos(t)).tolist(),
        "cross_track": (np.sin(t)).tolist(),
        "actions": [2] * t.size,
        "obstacles": [[10.0, 1.0, 1.5]],
    }
    return {
        "n_episodes": n,
        "successes": k,
        "success_rate": k / n,
        "collisions": n - k,
        "mean_abs_cross_track": 1.0 + spec.seed,
        "max_abs_cross_track": 3.0,
        "mean_abs_heading_error": 0.1,
        "mean_time_to_target": 200.0 if k else None,
        "mean_return": 500.0,
        "trajectories": [trace] * spec.trace_episodes,
    }


def fake_work(spec: RunSpec, tmp: Path, deps: dict[str, Path]) -> dict[str, Any]:
    """Synthetic training/evaluation outputs; fails if a dependency is not finished."""
    for dep, folder in deps.items():
        if not (folder / "manifest.json").is_file():
            raise RuntimeError(f"dependency {dep} of {spec.run_id} is not finished")
    time.sleep(float(os.environ.get("REPRODUCE_STANDIN_SLEEP", "0.05")))
    rng = np.random.default_rng(spec.seed)
    if spec.kind != "baseline":
        n = spec.episodes
        returns = np.linspace(-200, 600, n) + rng.normal(0, 20, n)
        successes = [bool(r > 300) for r in returns]
        (tmp / "episodes.json").write_text(
            json.dumps(
                {
                    "returns": returns.tolist(),
                    "lengths": [100] * n,
                    "successes": successes,
                    "end_reasons": ["x"] * n,
                    "recorded_episodes": list(spec.record_episodes),
                }
            )
        )
        trajs = {
            f"ep_{e}": np.c_[np.arange(10.0), rng.normal(0, 1, 10)] for e in spec.record_episodes
        }
        np.savez_compressed(tmp / "trajectories.npz", **trajs)
        (tmp / "model.zip").write_bytes(b"stand-in")
    if spec.validation and spec.kind == "transfer":  # checks rise to 100 %, the last is 50 %
        every = int(spec.validation["every"])
        checks = list(range(every, spec.episodes + 1, every)) or list(range(1, spec.episodes + 1))
        rates = [min(1.0, 0.5 * (i + 1)) for i in range(len(checks))]
        rates[-1] = 0.5
        history = [
            {"episode": e, "success_rate": r, "mean_return": 0.0} for e, r in zip(checks, rates)
        ]
        (tmp / "validation.json").write_text(
            json.dumps(
                {
                    "every": every,
                    "n_episodes": int(spec.validation["episodes"]),
                    "seed": 20000,
                    "history": history,
                    "best_episode": checks[rates.index(max(rates))],
                }
            )
        )
    if spec.eval_tasks:
        rate = 0.9 if spec.agent == "spnn" else 0.6
        evals = {label: _fake_eval(spec, label, rate) for label, _, _ in spec.eval_tasks}
        (tmp / "eval.json").write_text(json.dumps(evals))
    info: dict[str, Any] = {"kind": spec.kind, "agent": spec.agent, "pid_of_worker": os.getpid()}
    if spec.kind != "baseline":
        info["train_s"] = 60.0 * (1 + spec.seed)  # what run_work reports, in seconds
        info["first_success"] = successes.index(True) if True in successes else None
    return info


def failing_prior_work(spec: RunSpec, tmp: Path, deps: dict[str, Path]) -> dict[str, Any]:
    """As :func:`fake_work`, but the straight path-following prior fails."""
    if spec.run_id.startswith("prior-pf_straight"):
        raise RuntimeError("stand-in failure")
    return fake_work(spec, tmp, deps)


def pid_baseline_run(study: Path, task: str = "original", env: str = "PlanningStraight-v0") -> None:
    """A study folder's ``adaptive_pid-straight`` run as the replay tools read it: a manifest
    naming the baseline and its evaluation ``task`` on ``env`` with the env's own keywords."""
    run = study / "runs" / "adaptive_pid-straight"
    run.mkdir(parents=True)
    (run / "manifest.json").write_text(json.dumps({"agent": "adaptive_pid"}))
    tasks = {task: {"env_id": f"rov_envs/{env}", "env_kwargs": {}}}
    (run / "eval.json").write_text(json.dumps(tasks))
