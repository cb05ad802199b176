"""How a study's kept policies do among obstacles drawn afresh around their training path: a
validation measure of generalization.

The study's agents train on the paper's fixed obstacles, where every kept policy succeeds on
every validation episode, so validation on the training task cannot tell a set-up that
generalizes from one that does not; Figure 20's new layouts and evaluation seeds may not be used
to choose a set-up. This replays each run's kept policy on its planning task with the obstacles
drawn afresh every episode by the ``scatter`` generator (``layout="scatter"``: 1-5 cylinders per
40 m of route, radius U(0.75, 2.5) m, moved U(-10, 10) m off the route; none of the uniform /
dense / sine_dense generators' parameters), on the validation seeds (20000+), with the run's env
keywords otherwise, and prints each run's success rate and how its episodes ended. A policy is
played as the study evaluated it (an SPNN run whose spec names a switch memory,
``spnn_play_memory``, through :class:`sb3_pnn.progressive.SwitchMemory`; one whose spec names
``no_reversal``, ``spnn_play_no_reversal``, through :class:`sb3_pnn.evaluation.NoReversal`);
``--kept-by RANKING`` replays the policies that ranking kept of the same training (runs trained
with ``--set keep_best_also=RANKING``; BASE's stay as kept).
``--no-reversal on|off`` replays every run with or without NoReversal instead (docs/ablation
section 50 was measured this way).

``--gate-corridor C`` (SPNN runs, a diagnosis at inference) replays the policies with their gate
bounded at abs(g) / d_L >= C (``none``: eq. 15's unbounded gate), whatever they trained with; the
bound of ``spnn_gate_corridor`` was chosen this way (docs/ablation section 25).
``--corridor-release R`` (with a bound, the run's or ``--gate-corridor``'s) keeps the bound's
cut until abs(g) / d_L < R (:mod:`sb3_pnn.reproduce.tools.corridor_release`; section 49).

``--return-by NAME`` (with ``--return-clear M``, ``--return-offset G``) lets a PID baseline
steer wherever the sonar is clear and the vehicle off its path, ``--return-column STUDY`` the
same seed's path-following column of STUDY (:mod:`sb3_pnn.reproduce.tools.return_controller`;
sections 93-94).

``--against BASE`` replays the same agent, path and seeds of a second study and prints the
difference of the two mean success rates with a 95 % Welch interval over runs: each training
run is one draw, and runs of one set-up can differ by tens of points among drawn obstacles, so a
difference of a few points between five-seed studies is no evidence of an effect (docs/ablation
section 30).

Usage: python -m sb3_pnn.reproduce.tools.drawn_layouts STUDY --agent pnn --path straight
    [--seeds 0 1 2] [--episodes 50] [--gate-corridor 0.9] [--against BASE_STUDY]
    [--no-reversal on|off] [--arrival-gate 5] [--return-by adaptive_pid]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np
import torch as th

from sb3_pnn.common.callbacks import DRAWN_VALIDATION_LAYOUT, VALIDATION_SEED
from sb3_pnn.common.checks import float_in
from sb3_pnn.evaluation.evaluate import evaluate_policy_on_task
from sb3_pnn.progressive.gates import checked_corridor
from sb3_pnn.reproduce.reporting.stats import difference_ci
from sb3_pnn.reproduce.tools.corridor_release import CorridorRelease
from sb3_pnn.reproduce.tools.replay import (
    add_arrival_gate_option,
    add_kept_by_option,
    add_no_reversal_option,
    gated,
    no_reversal_of,
    run_env_kwargs,
    run_folders,
    run_model,
    run_played,
    task_id,
    task_parser,
)
from sb3_pnn.reproduce.tools.return_controller import add_return_options, returned

#: The generator whose layouts the measure draws (rov_envs.sim.layouts): not an evaluation one;
#: the one ``KeepBestOnValidation(drawn_episodes=...)`` checks on, on other seeds.
LAYOUT = DRAWN_VALIDATION_LAYOUT


def corridor_value(text: str) -> float | str:
    """``--gate-corridor``'s value: a fraction of d_L in (0, 1], or ``"none"``."""
    if text == "none":
        return text
    try:
        return checked_corridor(float(text))  # the range the gate itself accepts
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not allowed: expected a fraction of d_L in (0, 1], or none"
        ) from None


def bound_gate(parser: argparse.ArgumentParser, model, corridor: float | str, run) -> None:
    """Set the SPNN policy's gate bound to ``corridor`` (``"none"``: unbounded) for predict."""
    gate = getattr(getattr(getattr(model, "policy", None), "actor", None), "gate", None)
    if not hasattr(gate, "corridor"):
        parser.error(f"--gate-corridor needs SPNN runs with a distance gate; {run} has none")
    gate.corridor = None if corridor == "none" else float(corridor)


def set_switch_distance(parser: argparse.ArgumentParser, model, d_th: float, run) -> None:
    """Set the SPNN policy's gate switch distance d_th (m) for predict (training unchanged)."""
    gate = getattr(getattr(getattr(model, "policy", None), "actor", None), "gate", None)
    if not hasattr(gate, "d_th"):
        parser.error(f"--d-th needs SPNN runs with a distance gate; {run} has none")
    gate.d_th = float(d_th)


def released(parser: argparse.ArgumentParser, policy, model, release: float, run):
    """``policy`` played with the corridor bound released only below ``release`` d_L."""
    gate = getattr(getattr(getattr(model, "policy", None), "actor", None), "gate", None)
    try:
        return CorridorRelease(policy, gate, release)
    except ValueError as exc:
        parser.error(f"--corridor-release {release} ({run}): {exc}")


def drawn_success(
    parser: argparse.ArgumentParser,
    args: argparse.Namespace,
    study: Path,
    env_id: str,
    kept_by: str | None = None,
) -> list[tuple[int, float, str]]:
    """(seed, success rate, how the episodes ended) of each of ``study``'s runs of the agent
    and path (the policies ``kept_by`` that ranking, :func:`run_model`), replayed among drawn
    obstacles on the validation seeds."""
    out = []
    for seed, run in run_folders(study, args.agent, args.path, args.seeds):
        env_kwargs = dict(gated(run_env_kwargs(parser, run), args.arrival_gate), layout=LAYOUT)
        model = run_model(parser, run, kept_by)
        if args.gate_corridor is not None:
            bound_gate(parser, model, args.gate_corridor, run)
        if args.d_th is not None:
            set_switch_distance(parser, model, args.d_th, run)
        no_reversal = no_reversal_of(args)
        policy = args.agent if model is None else run_played(parser, run, model, no_reversal)
        if args.corridor_release is not None:
            policy = released(parser, policy, model, args.corridor_release, run)
        policy = returned(parser, args, policy, env_id, env_kwargs, run)
        result = evaluate_policy_on_task(
            policy, env_id, args.episodes, VALIDATION_SEED, env_kwargs=env_kwargs
        )
        ends = ", ".join(f"{k} {v}" for k, v in sorted(result.end_reasons.items()))
        out.append((seed, result.success_rate, ends))
    return out


def print_difference(base: list[float], rates: list[float]) -> None:
    """The difference of the mean success rates (points) with its 95 % Welch interval."""
    diff, low, high = difference_ci(base, rates)
    spread = [float(np.std(x, ddof=1)) for x in (base, rates) if len(x) > 1]
    interval = (
        "no interval (one run per side)"
        if math.isnan(low)
        else f"95 % interval [{100 * low:+.1f}, {100 * high:+.1f}] (Welch, runs as the unit)"
    )
    print(f"difference {100 * diff:+.1f} points, {interval}")
    if spread:
        print(f"run-to-run standard deviation {100 * float(np.mean(spread)):.1f} points")


def main(argv: list[str] | None = None) -> int:
    parser = task_parser(__doc__, episodes=50)
    parser.add_argument(
        "--agent", default="spnn", help="the runs' agent (spnn, pnn, ..., pid, adaptive_pid)"
    )
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument(
        "--gate-corridor",
        type=corridor_value,
        metavar="C",
        help="SPNN runs: replay with the gate bounded at abs(g) / d_L >= C (0 < C <= 1), or "
        "'none' for eq. 15's unbounded gate (default: as trained)",
    )
    parser.add_argument(
        "--d-th",
        type=float_in("--d-th", 0.0, 100.0, "m"),
        metavar="D",
        help="SPNN runs: replay with the gate's switch distance d_th set to D m (default: as "
        "trained)",
    )
    parser.add_argument(
        "--against",
        type=Path,
        metavar="BASE",
        help="a second study: its runs of the same agent, path and seeds replayed alike, and "
        "the difference of the means printed with a 95 %% interval",
    )
    parser.add_argument(
        "--corridor-release",
        type=float,
        metavar="R",
        help="SPNN runs with a corridor bound: once abs(g) / d_L reaches the bound, keep the "
        "avoidance column cut until abs(g) / d_L < R (a diagnosis; default: no release)",
    )
    add_no_reversal_option(parser)
    add_arrival_gate_option(parser)
    add_return_options(parser)
    add_kept_by_option(parser)
    args = parser.parse_args(argv)
    env_id = task_id(parser, args)
    th.set_num_threads(1)
    bound = "" if args.gate_corridor is None else f", gate bound {args.gate_corridor}"
    print(
        f"{args.agent} on {env_id} with layout={LAYOUT!r}, {args.episodes} validation episodes"
        + bound
    )
    runs = drawn_success(parser, args, args.study, env_id, args.kept_by)
    rates = [rate for _, rate, _ in runs]
    if args.against is None:
        print("| seed | success | episodes ended by |\n|---|---|---|")
        for seed, rate, ends in runs:
            print(f"| {seed} | {100 * rate:.0f} % | {ends} |")
        print(f"mean success {100 * float(np.mean(rates)):.1f} % over {len(rates)} run(s)")
        return 0
    base = drawn_success(parser, args, args.against, env_id)
    arm = f"{args.study}" + (f" (kept by {args.kept_by})" if args.kept_by else "")
    print(f"| seed | {args.against} | {arm} |\n|---|---|---|")
    for (seed, b_rate, b_ends), (_, rate, ends) in zip(base, runs, strict=True):
        print(f"| {seed} | {100 * b_rate:.0f} % ({b_ends}) | {100 * rate:.0f} % ({ends}) |")
    b_rates = [rate for _, rate, _ in base]
    print(
        f"mean success {100 * float(np.mean(b_rates)):.1f} % against "
        f"{100 * float(np.mean(rates)):.1f} % over {len(rates)} run(s) each"
    )
    print_difference(b_rates, rates)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
