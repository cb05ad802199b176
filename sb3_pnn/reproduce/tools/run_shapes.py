"""How runs of one task learn, per seed: best and last validation check, checks at 90 % or more.

Reads study runs (``<study>/runs/<agent>-<path>-s<seed>``) and single runs of
``bench/learning_trace.py`` (their printed ``validation`` and ``evaluation of the policy kept``
lines), so that a study's seeds 0-4 and fresh seeds checked with the script sit in one table.
The best check is what ``keep_best`` keeps (and what a default is chosen on); the last check is
the policy a run without ``keep_best`` would report; the count of checks at 90 % or more says
whether a run keeps what it learned. Used for docs/ablation/README.md, section 6 (SPNN's
weights):

    python -m sb3_pnn.reproduce.tools.run_shapes --label "0.5" --study results/study \
        --logs paper-s5.log ... --label "1" --study results/study_unit --logs unit-s5.log ...
"""

from __future__ import annotations

import argparse
import json
import re
from pathlib import Path

from sb3_pnn.reproduce.tools.compare_studies import evaluation

HIGH = 90  # a check at this success rate (%) or more counts as "learned"


def from_study(study: Path, agent: str, path: str, seed: int) -> tuple[list[int], int]:
    """(validation checks in %, evaluation on the original task in %) of one study run."""
    run = study / "runs" / f"{agent}-{path}-s{seed}"
    history = json.loads((run / "validation.json").read_text())["history"]
    checks = [round(100 * h["success_rate"]) for h in history]
    return checks, round(100 * evaluation(run)["original"])


def from_log(log: Path) -> tuple[list[int], int]:
    """The same from a ``bench/learning_trace.py`` log."""
    text = log.read_text()
    validation = re.search(r"^validation .*$", text, flags=re.MULTILINE)
    evaluation = re.search(r"^evaluation of the policy kept .*?\): (\d+) %", text, re.MULTILINE)
    if validation is None or evaluation is None:
        raise SystemExit(f"{log}: no validation / evaluation line (did the run finish?)")
    checks = [int(v) for v in re.findall(r"\d+:(\d+)%", validation.group(0))]
    return checks, int(evaluation.group(1))


def describe(label: str, runs: list[tuple[list[int], int]]) -> None:
    def row(name: str, values: list[int]) -> None:
        mean = sum(values) / len(values)
        print(f"| {label} | {name} | {' '.join(map(str, values))}: {mean:.0f} % |")

    row("best validation check", [max(c) for c, _ in runs])
    row("evaluation of the kept policy", [e for _, e in runs])
    row("last validation check", [c[-1] for c, _ in runs])
    high = sum(sum(v >= HIGH for v in c) for c, _ in runs)
    print(f"| {label} | checks at {HIGH} % or more | {high} of {sum(len(c) for c, _ in runs)} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--agent", default="spnn")
    parser.add_argument("--path", default="straight", choices=["straight", "sine"])
    parser.add_argument("--seeds", type=int, default=5, help="study seeds 0..N-1")
    parser.add_argument("--label", action="append", required=True, help="one per arm")
    parser.add_argument("--study", action="append", type=Path, required=True)
    parser.add_argument("--logs", action="append", nargs="*", type=Path, default=[])
    args = parser.parse_args()
    if not len(args.label) == len(args.study) >= len(args.logs):
        raise SystemExit("give one --label and one --study per arm (and at most one --logs)")
    print("| arm | measure | per run (study seeds, then the logs in order): mean |")
    print("|---|---|---|")
    for i, (label, study) in enumerate(zip(args.label, args.study, strict=True)):
        runs = [from_study(study, args.agent, args.path, s) for s in range(args.seeds)]
        runs += [from_log(log) for log in (args.logs[i] if i < len(args.logs) else [])]
        describe(label, runs)


if __name__ == "__main__":
    main()
