"""Does deploying a study's kept policies by the median of pi(.|s) on Table 1's ordered turns,
or without immediate turn reversals, instead of its mode, stop them weaving? A validation
measurement; nothing here trains.

Table 1's five actions are ordered by the turn they command: Turn left 2, Turn left 1, Go
straight, Turn right 1, Turn right 2. A deterministic policy plays the argmax of pi(.|s) (the
mode); where the two opposite turns lead with nearly equal probability the mode flips between
them from step to step (docs/ablation section 14). The median on that order plays "Go straight"
whenever neither side holds half the probability. :class:`sb3_pnn.evaluation.NoReversal` plays
the mode except where it turns to the side opposite to the step before's, and then goes
straight (docs/ablation section 50). This replays each run's kept policy the three ways on the
validation seeds (20000+), 50 episodes each, on its planning task, on the same path without
obstacles, and among obstacles drawn afresh (the ``scatter`` generator of
``tools.drawn_layouts``), and prints success, return, mean abs(g) and mean abs(a_c) per run and
decoder, and their means. The mode is played as the study plays the run (a switch memory where
its spec names one), without NoReversal; the median reads the model's own logits.

Usage: python -m sb3_pnn.reproduce.tools.greedy_decoding STUDY --agent spnn --path straight
    [--seeds 0 1 2 3 4 (default: every run of that agent and path)] [--episodes 50]
"""

from __future__ import annotations

from typing import Any

import numpy as np
import torch as th

from rov_envs.physics.thrusters import ACTION_NAMES
from sb3_pnn.common.callbacks import VALIDATION_SEED
from sb3_pnn.evaluation import NoReversal
from sb3_pnn.evaluation.evaluate import evaluate_policy_on_task
from sb3_pnn.reproduce.tools.drawn_layouts import LAYOUT
from sb3_pnn.reproduce.tools.replay import (
    run_env_kwargs,
    run_folders,
    run_model,
    run_played,
    task_id,
    task_parser,
)

#: Table 1's action indices ordered by the turn they command, from hardest left to hardest right
TURN_ORDER = tuple(
    ACTION_NAMES.index(name)
    for name in ("Turn left 2", "Turn left 1", "Go straight", "Turn right 1", "Turn right 2")
)


def median_actions(logits: th.Tensor, order: tuple[int, ...] = TURN_ORDER) -> th.Tensor:
    """Per row of ``logits`` (B, n): the action at which pi's mass, summed along ``order``,
    first reaches one half (the lower median of the ordered distribution) -> (B,)."""
    index = th.as_tensor(order, device=logits.device)
    cumulative = th.softmax(logits, dim=1)[:, index].cumsum(dim=1)
    position = (cumulative < 0.5).sum(dim=1).clamp(max=len(order) - 1)
    return index[position]


class MedianDecoded:
    """A model whose deterministic ``predict`` plays :func:`median_actions` of its actor's
    logits (SB3's ``predict`` signature; stochastic calls are the model's own)."""

    def __init__(self, model: Any):
        self.model = model
        self.observation_space = model.observation_space
        self.action_space = model.action_space

    def predict(self, observation, state=None, episode_start=None, deterministic=False):
        if not deterministic:
            return self.model.predict(observation, state, episode_start, deterministic)
        policy = self.model.policy
        obs, vectorized = policy.obs_to_tensor(observation)
        with th.no_grad():
            actions = median_actions(policy.actor(obs)).cpu().numpy()
        return (actions if vectorized else actions[0]), state


#: (label, env keywords added to the run's) of the three validation tasks
TASKS = (("planning task", {}), ("no obstacles", {"obstacles": []}), ("drawn", {"layout": LAYOUT}))


#: The decoders compared, in the table's order.
DECODERS = ("mode", "median", "no reversal")


def measure(
    model: Any, env_id: str, env_kwargs: dict, episodes: int, played: Any = None
) -> dict[str, dict]:
    """{decoder: {task label: (success, return, abs(g), abs(a_c) in degrees)}}; ``played``:
    the model as the study plays it without NoReversal (default: the model itself)."""
    mode = model if played is None else played
    policies = (mode, MedianDecoded(model), NoReversal(mode))
    out: dict[str, dict] = {}
    for decoder, policy in zip(DECODERS, policies, strict=True):
        out[decoder] = {}
        for label, extra in TASKS:
            r = evaluate_policy_on_task(
                policy, env_id, episodes, VALIDATION_SEED, env_kwargs={**env_kwargs, **extra}
            )
            out[decoder][label] = (
                r.success_rate,
                r.mean_return,
                r.mean_abs_cross_track,
                float(np.degrees(r.mean_abs_heading_error)),
            )
    return out


def main(argv: list[str] | None = None) -> int:
    parser = task_parser(__doc__, episodes=50)
    parser.add_argument("--agent", default="spnn", help="the runs' agent (spnn, pnn, ...)")
    parser.add_argument(
        "--seeds", type=int, nargs="+", default=None, help="training seeds (default: every run)"
    )
    args = parser.parse_args(argv)
    env_id = task_id(parser, args)
    th.set_num_threads(1)
    print(f"{args.agent} on {env_id}, {args.episodes} validation episodes per task")
    print(
        "| seed | decoder | planning task: success, return, abs(g), abs(a_c) | no obstacles: "
        "success, abs(g), abs(a_c) | drawn obstacles: success |\n|---|---|---|---|---|"
    )
    rows: dict[str, list] = {decoder: [] for decoder in DECODERS}
    runs = run_folders(args.study, args.agent, args.path, args.seeds)
    if not runs:
        parser.error(f"{args.study / 'runs'} holds no run of {args.agent} on the {args.path} path")
    for seed, run in runs:
        model = run_model(parser, run)
        if model is None:
            parser.error(f"{run} is a PID baseline's run: expected a trained agent's")
        played = run_played(parser, run, model, no_reversal=False)
        result = measure(model, env_id, run_env_kwargs(parser, run), args.episodes, played)
        for decoder, tasks in result.items():
            plan, free, drawn = (tasks[label] for label, _ in TASKS)
            rows[decoder].append([*plan, *free[2:], drawn[0], free[0]])
            print(
                f"| {seed} | {decoder} | {100 * plan[0]:.0f} %, {plan[1]:.0f}, {plan[2]:.2f} m, "
                f"{plan[3]:.1f} deg | {100 * free[0]:.0f} %, {free[2]:.2f} m, {free[3]:.1f} deg | "
                f"{100 * drawn[0]:.0f} % |"
            )
    for decoder, values in rows.items():
        m = np.mean(values, axis=0)
        print(
            f"mean, {decoder}: planning task {100 * m[0]:.1f} %, return {m[1]:.1f}, "
            f"{m[2]:.2f} m, {m[3]:.1f} deg; no obstacles {100 * m[7]:.1f} %, {m[4]:.2f} m, "
            f"{m[5]:.1f} deg; "
            f"drawn {100 * m[6]:.1f} %"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
