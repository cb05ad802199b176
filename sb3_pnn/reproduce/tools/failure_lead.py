"""Which of SPNN's frozen columns led when its episodes among drawn obstacles ended.

Eq. 15's gate hands the vehicle to the obstacle-avoidance column near obstacles and to the
path-following column elsewhere. This replays each SPNN run's kept policy on its planning task
among obstacles drawn afresh (the ``scatter`` generator on the validation seeds 20000+, as
``tools.drawn_layouts``; ``--own-task``: the task's own obstacles), records at every decision
which prior the gate weighs most (:meth:`SelectivePolicy.gate_weights`), and attributes each
episode's ending to the column that led on most of its last ``--last`` decisions. It tells a
failure of the avoidance skill (a collision with the avoidance column leading) from one of the
hand-over (a collision or a crawl with the path column leading), which call for different fixes.
The actions are played as the study played the run (``--no-reversal on|off`` overrides
NoReversal); with a switch memory the leader is still read from the gate without memory.

Prints per run the endings by leading column and the share of decisions each column led, then
over all runs the share of each action while each column leads.

Usage: python -m sb3_pnn.reproduce.tools.failure_lead STUDY --path sine
    [--seeds 0 1 2 3 4] [--episodes 50] [--last 9] [--own-task]
"""

from __future__ import annotations

from collections import Counter
from typing import Any

import gymnasium as gym
import numpy as np
import torch as th

from rov_envs.physics.thrusters import ACTION_NAMES
from sb3_pnn.common.callbacks import DRAWN_VALIDATION_LAYOUT, VALIDATION_SEED
from sb3_pnn.evaluation import DEFAULT_START_NOISE
from sb3_pnn.progressive.selective_policy import PRIOR_NAMES
from sb3_pnn.reproduce.tools.replay import (
    add_no_reversal_option,
    no_reversal_of,
    run_env_kwargs,
    run_folders,
    run_model,
    run_played,
    task_id,
    task_parser,
)

#: Short names of eq. 15's two priors in the tables (the order of ``PRIOR_NAMES``).
SHORT = ("path", "avoid")


def leads(model: Any, env: gym.Env, episodes: int, last: int, policy: Any = None) -> dict[str, Any]:
    """Replay ``model`` (an SPNN model: ``predict`` and ``policy.gate_weights``), or the
    ``policy`` that plays it (its actions; the leader is read from the model's gate), for
    ``episodes`` episodes from the validation seed. Returns ``endings`` (a Counter of
    (end reason, leading prior index) over the episodes, the leader being the prior with the
    largest gate weight on most of the last ``last`` decisions, ties to the avoidance column),
    ``decisions`` (a Counter of decisions per leading prior) and ``actions`` (per leading prior a
    Counter of the actions played)."""
    endings: Counter = Counter()
    decisions: Counter = Counter()
    actions: dict[int, Counter] = {j: Counter() for j in range(len(PRIOR_NAMES))}
    player = model if policy is None else policy
    for episode in range(episodes):
        obs, info = env.reset(seed=VALIDATION_SEED + episode)
        leaders: list[int] = []
        done = False
        while not done:
            batch = {key: np.asarray(value)[None] for key, value in obs.items()}
            leader = int(np.argmax(model.policy.gate_weights(batch)[0].numpy()))
            start = np.array([not leaders])
            action, _ = player.predict(obs, episode_start=start, deterministic=True)
            leaders.append(leader)
            decisions[leader] += 1
            actions[leader][int(action)] += 1
            obs, _, terminated, truncated, info = env.step(action)
            done = terminated or truncated
        tail = leaders[-last:]
        endings[(info["end_reason"], int(2 * sum(tail) >= len(tail)))] += 1
    return {"endings": endings, "decisions": decisions, "actions": actions}


def ending_cells(endings: Counter) -> str:
    """``collision: path 0, avoid 24; success: ...`` for one run's endings by leader."""
    reasons = sorted({reason for reason, _ in endings})
    return "; ".join(
        f"{reason}: " + ", ".join(f"{SHORT[j]} {endings[(reason, j)]}" for j in range(len(SHORT)))
        for reason in reasons
    )


def main(argv: list[str] | None = None) -> int:
    parser = task_parser(__doc__, episodes=50)
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument(
        "--last",
        type=int,
        default=9,
        help="decisions before an ending that decide which column led it (default 9, odd so "
        "that the hard switch has no ties)",
    )
    parser.add_argument(
        "--own-task", action="store_true", help="the task's own obstacles, not drawn ones"
    )
    add_no_reversal_option(parser)
    args = parser.parse_args(argv)
    if args.last < 1:
        parser.error(f"--last {args.last} is not allowed: expected a number of decisions >= 1")
    env_id = task_id(parser, args)
    runs = run_folders(args.study, "spnn", args.path, args.seeds)
    if not runs:
        parser.error(f"{args.study / 'runs'} holds no SPNN run on the {args.path} path")
    th.set_num_threads(1)
    where = "its own obstacles" if args.own_task else f"layout={DRAWN_VALIDATION_LAYOUT!r}"
    print(f"SPNN on {env_id} with {where}, {args.episodes} validation episodes per run")
    print(
        "| seed | endings by the column leading the last decisions | decisions led by the "
        "avoidance column |\n|---|---|---|"
    )
    total_actions = {j: Counter() for j in range(len(PRIOR_NAMES))}
    for seed, run in runs:
        model = run_model(parser, run)
        if model is None or not hasattr(model.policy, "gate_weights"):
            parser.error(f"{run} is not an SPNN run (its policy has no gate)")
        kwargs = dict(run_env_kwargs(parser, run))
        if not args.own_task:
            kwargs["layout"] = DRAWN_VALIDATION_LAYOUT
        kwargs.setdefault("start_noise", DEFAULT_START_NOISE)
        policy = run_played(parser, run, model, no_reversal_of(args))
        result = leads(model, gym.make(env_id, **kwargs), args.episodes, args.last, policy)
        share = result["decisions"][1] / max(1, sum(result["decisions"].values()))
        print(f"| {seed} | {ending_cells(result['endings'])} | {100 * share:.0f} % |")
        for j, counts in result["actions"].items():
            total_actions[j].update(counts)
    print("\n| leading column | " + " | ".join(ACTION_NAMES) + " |")
    print("|---" * (1 + len(ACTION_NAMES)) + "|")
    for j, counts in total_actions.items():
        n = max(1, sum(counts.values()))
        cells = [f"{100 * counts[a] / n:.0f} %" for a in range(len(ACTION_NAMES))]
        print(f"| {PRIOR_NAMES[j]} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
