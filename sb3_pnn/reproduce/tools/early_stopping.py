"""What stopping a run early on its validation checks would have kept and saved, from a study.

Every run that keeps its best policy (:class:`sb3_pnn.common.callbacks.KeepBestOnValidation`)
records its validation checks (``validation.json``) and its training episodes' lengths
(``episodes.json``). A patience-P early stop ends training at the first check that is P checks
past the best one so far (the RL Zoo's ``StopTrainingOnNoModelImprovement``, counted in checks),
and keeps that best check. Up to its stopping point a stopped run is the same run (same seed,
same updates), so its outcome can be read off the full run's record without training again:

* whether the kept check is the one the full run kept (same episode);
* the kept check's validation success and mean return, against the full run's;
* the share of the full run's training steps it ran (a proxy for its training time: the
  update cost per step does not change along a run).

Usage::

    python -m sb3_pnn.reproduce.tools.early_stopping results/study [--patience 2 4 8]
"""

from __future__ import annotations

import argparse
import json
from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sb3_pnn.common.callbacks import validation_rank

#: A validation check's rank (:func:`sb3_pnn.common.callbacks.validation_rank`).
Key = tuple[float, float]


def stop_point(keys: Sequence[Key], patience: int) -> tuple[int, int]:
    """(index of the check at which a patience-``patience`` stop ends the run, index of the
    check it keeps). Without a stop the run ends at its last check and keeps the best of all,
    ties going to the earlier check, as :class:`KeepBestOnValidation` does."""
    if not keys:
        raise ValueError("a run without validation checks has no stopping point")
    if isinstance(patience, bool) or not isinstance(patience, int) or patience < 1:
        raise ValueError(f"patience={patience!r} is not allowed: expected an integer >= 1 (checks)")
    best = 0
    for i in range(1, len(keys)):
        if keys[i] > keys[best]:
            best = i
        elif i - best >= patience:
            return i, best
    return len(keys) - 1, best


def run_group(run_dir: Path) -> str:
    """A run's agent and task without its seed: ``spnn-sine-s3`` -> ``spnn-sine``."""
    head, sep, tail = run_dir.name.rpartition("-s")
    return head if sep and tail.isdigit() else run_dir.name


def _read_json(path: Path) -> Any:
    try:
        return json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as error:
        raise ValueError(f"{str(path)!r} is not a readable JSON record: {error}") from None


def stopped_run(run_dir: Path, patience: int) -> dict[str, Any] | None:
    """One run's outcome under a patience stop (None: the run kept no validation record)."""
    validation, episodes = run_dir / "validation.json", run_dir / "episodes.json"
    if not (validation.is_file() and episodes.is_file()):
        return None
    record, lengths = _read_json(validation), _read_json(episodes)
    try:
        history, lengths = record["history"], lengths["lengths"]
        rank_by, bound = record.get("rank_by", "return"), record.get("route_bound")
        keys = [validation_rank(check, rank_by, bound) for check in history]
        episodes_of = [int(check["episode"]) for check in history]
        full = episodes_of.index(record["best_episode"]) if history else None
    except (KeyError, TypeError, ValueError) as error:
        raise ValueError(
            f"{str(run_dir)!r} holds a validation or episode record of another shape "
            f"({type(error).__name__}: {error}): expected the study's validation.json and "
            "episodes.json"
        ) from None
    if not history or not lengths:
        return None
    stop, kept = stop_point(keys, patience)
    return {
        "same_check": kept == full,
        "success_change": keys[kept][0] - keys[full][0],
        "return_change": history[kept]["mean_return"] - history[full]["mean_return"],
        "steps_run": sum(lengths[: episodes_of[stop]]),
        "steps": sum(lengths),
    }


def summarize(study: Path, patiences: Sequence[int]) -> list[dict[str, Any]]:
    """One row per (agent and task, patience): runs, runs keeping the same check, mean changes
    of the kept check's success (points) and return, mean share of training steps run; then a
    row ``all`` per patience: every run together, its steps share the study's (steps run over
    steps of the full runs)."""
    runs = sorted(p for p in (study / "runs").iterdir() if p.is_dir())
    rows = []
    for patience in patiences:
        groups: dict[str, list[dict[str, Any]]] = defaultdict(list)
        for run in runs:
            outcome = stopped_run(run, patience)
            if outcome is not None:
                groups[run_group(run)].append(outcome)
        groups["all"] = [o for outcomes in list(groups.values()) for o in outcomes]
        for group, outcomes in sorted(groups.items(), key=lambda item: item[0] == "all"):
            n = len(outcomes)
            if not n:
                continue
            share = [o["steps_run"] / o["steps"] for o in outcomes]
            if group == "all":  # the study's share: long runs weigh more
                share = [sum(o["steps_run"] for o in outcomes) / sum(o["steps"] for o in outcomes)]
            rows.append(
                {
                    "runs": group,
                    "patience": patience,
                    "n": n,
                    "same_check": sum(o["same_check"] for o in outcomes),
                    "success_change_points": 100 * sum(o["success_change"] for o in outcomes) / n,
                    "return_change": sum(o["return_change"] for o in outcomes) / n,
                    "steps_share": sum(share) / len(share),
                }
            )
    return rows


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("study", type=Path, help="a study's output folder (with runs/)")
    parser.add_argument(
        "--patience",
        type=int,
        nargs="+",
        default=[2, 4, 8],
        help="checks without a better one (integers >= 1)",
    )
    args = parser.parse_args(argv)
    if not (args.study / "runs").is_dir():
        parser.error(f"{str(args.study)!r} has no runs/ folder: expected a study's --out folder")
    bad = [p for p in args.patience if p < 1]
    if bad:
        parser.error(f"--patience {bad[0]} is not allowed: expected integers >= 1 (checks)")
    print(
        "| runs | patience (checks) | runs | same kept check | kept success (points) "
        "| kept mean return | training steps run |"
    )
    print("|---|---|---|---|---|---|---|")
    try:
        rows = summarize(args.study, args.patience)
    except ValueError as error:
        parser.error(str(error))
    for r in rows:
        print(
            f"| {r['runs']} | {r['patience']} | {r['n']} | {r['same_check']} of {r['n']} | "
            f"{r['success_change_points']:+.1f} | {r['return_change']:+.1f} | "
            f"{100 * r['steps_share']:.0f} % |"
        )


if __name__ == "__main__":
    main()
