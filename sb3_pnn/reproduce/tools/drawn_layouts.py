"""How a study's kept policies do among obstacles drawn afresh around their training path: a
validation measure of generalization.

The study's agents train on the paper's fixed obstacles, where every kept policy succeeds on
every validation episode, so validation on the training task cannot tell a set-up that
generalizes from one that does not; Figure 20's new layouts and evaluation seeds may not be used
to choose a set-up. This replays each run's kept policy on its planning task with the obstacles
drawn afresh every episode by the ``scatter`` generator (``layout="scatter"``: 1-5 cylinders per
40 m of route, radius U(0.75, 2.5) m, moved U(-10, 10) m off the route; none of the uniform /
dense / sine_dense generators' parameters), on the validation seeds (20000+), with the run's env
keywords otherwise, and prints each run's success rate and how its episodes ended.

Usage: python -m sb3_pnn.reproduce.tools.drawn_layouts STUDY --agent pnn --path straight
    [--seeds 0 1 2] [--episodes 50]
"""

from __future__ import annotations

import json

import numpy as np
import torch as th

from sb3_pnn import DiscreteSAC
from sb3_pnn.baselines import BASELINE_NAMES
from sb3_pnn.common.callbacks import VALIDATION_SEED
from sb3_pnn.evaluation.evaluate import evaluate_policy_on_task
from sb3_pnn.reproduce.tools.replay import task_id, task_parser

#: The generator whose layouts the measure draws (rov_envs.sim.layouts): not an evaluation one.
LAYOUT = "scatter"


def main(argv: list[str] | None = None) -> int:
    parser = task_parser(__doc__, episodes=50)
    parser.add_argument(
        "--agent", default="spnn", help="the runs' agent (spnn, pnn, ..., pid, adaptive_pid)"
    )
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    args = parser.parse_args(argv)
    env_id = task_id(parser, args)
    th.set_num_threads(1)
    baseline = args.agent in BASELINE_NAMES  # one run per path, no training seed
    rates = []
    print(f"{args.agent} on {env_id} with layout={LAYOUT!r}, {args.episodes} validation episodes")
    print("| seed | success | episodes ended by |\n|---|---|---|")
    for seed in [0] if baseline else args.seeds:
        run = (
            args.study / "runs" / (f"{args.agent}-{args.path}" + ("" if baseline else f"-s{seed}"))
        )
        eval_file = run / "eval.json"
        if not eval_file.is_file():
            parser.error(f"{eval_file} does not exist: expected a finished run of a study")
        env_kwargs = dict(json.loads(eval_file.read_text())["original"]["env_kwargs"])
        env_kwargs["layout"] = LAYOUT
        if not baseline and not (run / "model.zip").is_file():
            parser.error(f"{run / 'model.zip'} does not exist: expected a study's run folder")
        policy = args.agent if baseline else DiscreteSAC.load(run / "model.zip", device="cpu")
        result = evaluate_policy_on_task(
            policy, env_id, args.episodes, VALIDATION_SEED, env_kwargs=env_kwargs
        )
        rates.append(result.success_rate)
        ends = ", ".join(f"{k} {v}" for k, v in sorted(result.end_reasons.items()))
        print(f"| {seed} | {100 * result.success_rate:.0f} % | {ends} |")
    print(f"mean success {100 * float(np.mean(rates)):.1f} % over {len(rates)} run(s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
