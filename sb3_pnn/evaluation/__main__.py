"""``python -m sb3_pnn.evaluate``: evaluate a saved model or a PID baseline on an rov_envs task.

Example::

    python -m sb3_pnn.evaluate --model adaptive_pid --env PlanningStraight-v0 --episodes 100
    python -m sb3_pnn.evaluate --model runs/spnn.zip --env rov_envs/PlanningSineDense-v0 \\
        --seed 1000 --out results.json
    python -m sb3_pnn.evaluate --model adaptive_pid --env PlanningSine-v0 --vehicle wu2018
    python -m sb3_pnn.evaluate --model runs/spnn.zip --env PlanningStraightDense-v0 \\
        --switch-memory 10

``--model`` is a baseline name (``pid``, ``adaptive_pid``) or the path of a model zip saved by
``DiscreteSAC.save`` (progressive policies included). Prints a table of the statistics of
:func:`sb3_pnn.evaluation.evaluate_policy_on_task`; ``--out`` also writes them as JSON. Bad input
(unknown env id, missing model file, ``--episodes < 1``, a model trained on another observation,
...) prints one line ``python -m sb3_pnn.evaluate: error: ...`` (with "did you mean" for a
mistyped env id or baseline name) and exits with code 2.
"""

from __future__ import annotations

import argparse
import ast
import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from rov_envs.sim.tasks import task_of_env
from sb3_pnn.baselines import BASELINE_NAMES
from sb3_pnn.common.atomic import check_writable
from sb3_pnn.evaluation import (
    DEFAULT_START_NOISE,
    evaluate_policy_on_task,
    resolve_env_id,
)
from sb3_pnn.evaluation.evaluate import trained_env_kwargs
from sb3_pnn.evaluation.played import played_through

PROG = "python -m sb3_pnn.evaluate"


class _UsageError(Exception):
    """Bad command-line input: reported as one line, exit code 2."""


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog=PROG,
        description="Evaluate a saved DiscreteSAC model or a PID baseline on an rov_envs task.",
    )
    p.add_argument(
        "--model",
        required=True,
        help=f"model zip path, or a baseline name: {', '.join(BASELINE_NAMES)}",
    )
    p.add_argument("--env", required=True, help="env id, e.g. PlanningStraight-v0")
    p.add_argument("--episodes", type=int, default=100, help="number of episodes (default 100)")
    p.add_argument("--seed", type=int, default=0, help="first seed; episode i uses seed + i")
    p.add_argument(
        "--start-noise",
        type=float,
        nargs=2,
        metavar=("POS_M", "HEAD_DEG"),
        default=(DEFAULT_START_NOISE[0], math.degrees(DEFAULT_START_NOISE[1])),
        help="std of the start position (m) and heading (deg) (default 1 5)",
    )
    p.add_argument(
        "--vehicle",
        default=None,
        help="the env's vehicle preset (uuv_simulator, the default, or wu2018)",
    )
    p.add_argument(
        "--env-kwargs",
        nargs="+",
        default=[],
        metavar="KEY:VALUE",
        help="env keyword arguments (Python literals, e.g. control_period:0.5), over those the "
        "model was trained with",
    )
    p.add_argument(
        "--switch-memory",
        type=float,
        default=None,
        metavar="H",
        help="play an SPNN whose gate is eq. 15's hard switch with a memory: the avoidance "
        "column keeps control until the nearest reading is beyond d_th + H metres "
        "(sb3_pnn.progressive.SwitchMemory; the study's spnn_play_memory)",
    )
    p.add_argument(
        "--no-reversal",
        action="store_true",
        help="play Go straight where the policy's turn reverses the step before's "
        "(sb3_pnn.evaluation.NoReversal; the study's spnn_play_no_reversal)",
    )
    p.add_argument("--record", type=int, default=0, help="keep the first K trajectories")
    p.add_argument("--stochastic", action="store_true", help="sample actions (default: greedy)")
    p.add_argument("--out", default=None, help="write the result as JSON to this path")
    p.add_argument(
        "--num-threads",
        type=int,
        default=1,
        help="torch threads (default 1: on few cores small networks run slower on more)",
    )
    return p


def parse_env_kwargs(items: Sequence[str]) -> dict[str, Any]:
    """``["key:value", ...]`` as a dict; each value a Python literal (``ast.literal_eval``: no
    code runs), or else the text itself."""
    out: dict[str, Any] = {}
    for item in items:
        key, sep, text = item.partition(":")
        if not sep or not key:
            raise _UsageError(f"--env-kwargs {item!r}: expected key:value")
        try:
            out[key] = ast.literal_eval(text)
        except (ValueError, SyntaxError):
            out[key] = text
    return out


def load_policy(model: str) -> tuple[Any, str]:
    """A baseline name, or a DiscreteSAC zip (``.zip`` may be left out) -> (policy, name)."""
    if model in BASELINE_NAMES:
        return model, model
    path = Path(model)
    if not path.is_file() and Path(model + ".zip").is_file():
        path = Path(model + ".zip")
    if not path.is_file():
        from sb3_pnn.common.checks import did_you_mean

        raise _UsageError(
            f"--model {model!r}: no such file; {did_you_mean(model, BASELINE_NAMES)}expected a "
            f"model zip or one of {', '.join(BASELINE_NAMES)}"
        )
    from sb3_pnn.dsac.dsac import DiscreteSAC

    try:
        return DiscreteSAC.load(path, device="cpu"), path.stem
    except Exception as exc:  # noqa: BLE001 - any failure to load is a bad --model
        raise _UsageError(f"--model {model!r}: cannot load as a DiscreteSAC model ({exc})") from exc


def run(argv: Sequence[str] | None = None) -> int:
    """Parse ``argv``, evaluate, print the table; return the exit code."""
    args = build_parser().parse_args(argv)
    try:
        if args.episodes < 1:
            raise _UsageError(f"--episodes {args.episodes}: expected an int >= 1")
        if args.seed < 0:
            raise _UsageError(f"--seed {args.seed}: expected an int >= 0")
        if not 0 <= args.record <= args.episodes:
            raise _UsageError(f"--record {args.record}: expected an int in [0, --episodes]")
        if args.num_threads < 1:
            raise _UsageError(f"--num-threads {args.num_threads}: expected an int >= 1")
        import torch

        torch.set_num_threads(args.num_threads)
        pos, head = args.start_noise
        if not (math.isfinite(pos) and math.isfinite(head) and pos >= 0 and head >= 0):
            raise _UsageError(f"--start-noise {pos} {head}: expected two finite floats >= 0")
        try:
            env_id = resolve_env_id(args.env)
            task_of_env(env_id)
        except ValueError as exc:
            raise _UsageError(f"--env {args.env!r}: {exc}") from exc
        if args.out:
            try:
                check_writable(args.out)
            except ValueError as exc:
                raise _UsageError(f"--out {exc}") from exc
        given = parse_env_kwargs(args.env_kwargs)
        if args.vehicle is not None:
            given["vehicle"] = args.vehicle
        policy, name = load_policy(args.model)
        env_kwargs = {**trained_env_kwargs(policy, env_id), **given}
        try:
            policy = played_through(policy, args.switch_memory, args.no_reversal)
        except ValueError as exc:
            raise _UsageError(str(exc)) from exc
        try:
            result = evaluate_policy_on_task(
                policy,
                env_id,
                n_episodes=args.episodes,
                seed=args.seed,
                start_noise=(pos, math.radians(head)),
                env_kwargs=env_kwargs,
                record_trajectories=args.record,
                deterministic=not args.stochastic,
                policy_name=name,
            )
        except ValueError as exc:
            raise _UsageError(str(exc)) from exc
    except _UsageError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    print(result.format_table())
    if args.out:
        print(f"written: {result.save_json(args.out)}")
    return 0


def main() -> None:
    sys.exit(run())


if __name__ == "__main__":
    main()
