"""The README's Python example, run as written: its SPNN's success on PlanningStraight.

Reads the example out of README.md (the first ``python`` block of the "Use it" section, the
same code the test runs with small budgets), runs it at the README's budgets in a temporary
folder, then evaluates the SPNN it saved on PlanningStraight and on the three new layouts (50
episodes each, seeds 10000+), beside the adaptive PID on the same episodes (the anchor). The
README's goal: at least 90 % on PlanningStraight.

Usage: python bench/readme_example.py [--episodes 50]
"""

from __future__ import annotations

import re
from pathlib import Path

#: The line of the example that sets its budgets.
BUDGET_LINE = re.compile(r"^PRIOR_STEPS, SPNN_STEPS = .*$", re.M)


def readme_example(readme: str | Path) -> str:
    """The source of the README's "Use it" example."""
    text = Path(readme).read_text(encoding="utf-8")
    section = text.split("\n## Use it", 1)
    if len(section) != 2:
        raise ValueError(f"{readme}: no '## Use it' section")
    match = re.search(r"```python\n(.*?)```", section[1], re.S)
    if match is None:
        raise ValueError(f"{readme}: no python block in 'Use it'")
    source = match.group(1)
    if not BUDGET_LINE.search(source):
        raise ValueError(f"{readme}: the example has no line 'PRIOR_STEPS, SPNN_STEPS = ...'")
    return source


def with_budgets(source: str, prior_steps: int, spnn_steps: int) -> str:
    """The example with other budgets (the test's small ones)."""
    return BUDGET_LINE.sub(f"PRIOR_STEPS, SPNN_STEPS = {prior_steps}, {spnn_steps}", source)


def main() -> None:
    import argparse
    import os
    import runpy
    import tempfile
    import time

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=50)
    args = parser.parse_args()
    source = readme_example(Path(__file__).resolve().parents[1] / "README.md")
    here = os.getcwd()
    with tempfile.TemporaryDirectory() as scratch:
        os.chdir(scratch)
        started, cpu = time.time(), time.process_time()
        try:
            runpy.run_path(_write(source, scratch), run_name="__main__")
        finally:
            os.chdir(here)
        wall, cpu = (time.time() - started) / 60, (time.process_time() - cpu) / 60
        took = f"{wall:.1f} min wall, {cpu:.1f} CPU-min"
        from sb3_pnn import DiscreteSAC, evaluate_policy_on_task
        from sb3_pnn.progressive import SwitchMemory

        # played as the example plays it (a 10 m memory in its switch)
        model = SwitchMemory(DiscreteSAC.load(Path(scratch) / "spnn.zip"), hysteresis=10.0)
        print(f"README example trained in {took}")
        for task in (
            "rov_envs/PlanningStraight-v0",
            "rov_envs/PlanningStraightUniform-v0",
            "rov_envs/PlanningStraightDense-v0",
        ):
            rows = []
            for policy in (model, "adaptive_pid"):
                r = evaluate_policy_on_task(policy, task, n_episodes=args.episodes, seed=10_000)
                lo, hi = r.success_ci95
                rows.append(
                    f"{r.policy_name} {100 * r.success_rate:.0f} % [{100 * lo:.0f}, {100 * hi:.0f}]"
                )
            print(f"{task}: " + "; ".join(rows) + " (anchor: the adaptive PID)")


def _write(source: str, folder: str) -> str:
    path = Path(folder) / "example.py"
    path.write_text(source)
    return str(path)


if __name__ == "__main__":
    main()
