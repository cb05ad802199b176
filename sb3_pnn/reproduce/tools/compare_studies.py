"""Two study folders that differ in one factor, compared run by run: validation first.

For one agent, each (task, seed) run found in both folders: the best validation success rate
(what ``keep_best`` kept: 30 episodes on seeds 20000+, every 25 training episodes) and the
evaluation success on the original task and the new layouts (50 episodes each, seeds 10000+).
A default is to be chosen from the validation columns; the evaluation columns are reported, not
tuned on. Used for docs/ablation/spnn_d_th:

    python -m sb3_pnn.reproduce.tools.compare_studies results/study results/study_d_th8 --agent spnn
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from sb3_pnn.reproduce.planning.plan import AGENTS
from sb3_pnn.reproduce.reporting.stats import mean_ci

LABELS = ("original", "uniform", "dense")


def best_validation(run: Path) -> float | None:
    path = run / "validation.json"
    if not path.is_file():
        return None
    history = json.loads(path.read_text())["history"]
    return max((h["success_rate"] for h in history), default=None)


def evaluation(run: Path) -> dict[str, float]:
    evals = json.loads((run / "eval.json").read_text())
    return {label: evals[label]["success_rate"] for label in LABELS if label in evals}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("a", type=Path, help="study folder A")
    parser.add_argument("b", type=Path, help="study folder B")
    parser.add_argument("--agent", default="spnn", choices=AGENTS)
    args = parser.parse_args()
    for folder in (args.a, args.b):
        if not (folder / "runs").is_dir():
            parser.error(f"{str(folder)!r} has no runs/ folder: expected a study folder")
    print(f"agent {args.agent}: best validation success | evaluation {' / '.join(LABELS)}")
    for task in ("straight", "sine"):
        per_folder: dict[Path, list[float]] = {args.a: [], args.b: []}
        prefix = f"{args.agent}-{task}-s"
        seeds = sorted(int(r.name[len(prefix) :]) for r in (args.a / "runs").glob(prefix + "*"))
        for seed in seeds:
            name = f"{prefix}{seed}"
            runs = [f / "runs" / name for f in (args.a, args.b)]
            if not all((r / "eval.json").is_file() for r in runs):
                continue
            cells = []
            for folder, run in zip((args.a, args.b), runs, strict=True):
                val = best_validation(run)
                ev = evaluation(run)
                if val is not None:
                    per_folder[folder].append(val)
                ev_text = " / ".join(f"{100 * ev[lb]:.0f}" if lb in ev else "-" for lb in LABELS)
                val_text = "-" if val is None else f"{100 * val:.0f}"
                cells.append(f"{folder.name}: val {val_text:>3} | eval {ev_text}")
            print(f"{task:8s} seed {seed}: " + "   ".join(cells))
        for folder, vals in per_folder.items():
            if vals:
                mean, lo, hi = mean_ci(vals)
                lo, hi = max(0.0, lo), min(1.0, hi)
                print(
                    f"{task:8s} {folder.name}: best validation mean {100 * mean:.0f} % "
                    f"[{100 * lo:.0f}, {100 * hi:.0f}] over {len(vals)} seeds"
                )


if __name__ == "__main__":
    main()
