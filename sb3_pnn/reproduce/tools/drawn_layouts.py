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

import numpy as np
import torch as th

from sb3_pnn.common.callbacks import DRAWN_VALIDATION_LAYOUT, VALIDATION_SEED
from sb3_pnn.evaluation.evaluate import evaluate_policy_on_task
from sb3_pnn.reproduce.tools.replay import (
    run_env_kwargs,
    run_folders,
    run_model,
    task_id,
    task_parser,
)

#: The generator whose layouts the measure draws (rov_envs.sim.layouts): not an evaluation one;
#: the one ``KeepBestOnValidation(drawn_episodes=...)`` checks on, on other seeds.
LAYOUT = DRAWN_VALIDATION_LAYOUT


def main(argv: list[str] | None = None) -> int:
    parser = task_parser(__doc__, episodes=50)
    parser.add_argument(
        "--agent", default="spnn", help="the runs' agent (spnn, pnn, ..., pid, adaptive_pid)"
    )
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    args = parser.parse_args(argv)
    env_id = task_id(parser, args)
    th.set_num_threads(1)
    rates = []
    print(f"{args.agent} on {env_id} with layout={LAYOUT!r}, {args.episodes} validation episodes")
    print("| seed | success | episodes ended by |\n|---|---|---|")
    for seed, run in run_folders(args.study, args.agent, args.path, args.seeds):
        env_kwargs = dict(run_env_kwargs(parser, run), layout=LAYOUT)
        model = run_model(parser, run)
        policy = args.agent if model is None else model
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
