"""A diagnostic: how often a study's SPNN acts as its gate-selected frozen prior would.

Eq. 15's gate feeds the new column the path-following prior while the nearest obstacle is
beyond d_th and the obstacle-avoidance prior within it. Per step of deterministic episodes this
compares SPNN's greedy action with the greedy action of the selected prior's own policy (the
reference of ``prior_kl``), by gate regime (read from the policy's own gate, so soft and learned
gates count by their leading prior), and counts the actions each takes (Table 1's order: Turn
left 1, Turn left 2, Go straight, Turn right 1, Turn right 2). Episodes run on the validation
seeds (20000+, never the study's evaluation seeds 10000+) with the study's env keywords;
nothing is chosen here.

Usage: python -m sb3_pnn.reproduce.tools.prior_agreement STUDY --path straight
    [--env rov_envs/PlanningStraightDense-v0] [--episodes 10] [--seeds 3]
"""

from __future__ import annotations

from collections import Counter

import gymnasium as gym
import torch as th

import rov_envs  # noqa: F401  (registers the tasks)
from rov_envs.physics.thrusters import N_ACTIONS
from sb3_pnn import DiscreteSAC
from sb3_pnn.common.callbacks import VALIDATION_SEED
from sb3_pnn.common.checks import positive_int
from sb3_pnn.reproduce.tools.replay import ended, load_run, task_id, task_parser

REGIMES = ("path following", "avoidance")


def step_counts(
    model: DiscreteSAC, env: gym.Env, episodes: int, seed: int
) -> tuple[Counter, Counter]:
    """Per (regime, what) step counts over ``episodes`` episodes, and how the episodes ended.

    ``what`` is "steps", "agree", ("own", a) or ("prior", a)."""
    policy = model.policy
    counts: Counter = Counter()
    ends: Counter = Counter()
    for episode in range(episodes):
        obs, info = env.reset(seed=seed + episode)
        done = False
        while not done:
            batch = policy.obs_to_tensor(obs)[0]  # on the policy's device
            with th.no_grad():
                logits, prior_log_probs = policy.actor.logits_and_prior_log_probs(batch)
            own, prior = int(logits.argmax()), int(prior_log_probs.argmax())
            # the prior the policy's own gate leads with (the hard gate: by distance vs d_th)
            regime = REGIMES[int(policy.gate_weights(batch).argmax())]
            counts[(regime, "steps")] += 1
            counts[(regime, "agree")] += own == prior
            counts[(regime, ("own", own))] += 1
            counts[(regime, ("prior", prior))] += 1
            obs, _, terminated, truncated, info = env.step(own)
            done = terminated or truncated
        ends[info.get("end_reason", "none")] += 1
    return counts, ends


def table(rows: list[tuple[int, Counter, Counter]]) -> list[str]:
    """Markdown rows: per seed and regime, agreement and both action shares."""
    lines = [
        "| seed | regime | steps | agrees with the prior | SPNN's actions (shares) "
        "| prior's actions | episodes ended by |",
        "|---|---|---|---|---|---|---|",
    ]
    for seed, counts, ends in rows:
        for regime in REGIMES:
            steps = counts[(regime, "steps")]
            if not steps:
                continue
            own, prior = (
                " ".join(f"{counts[(regime, (who, a))] / steps:.2f}" for a in range(N_ACTIONS))
                for who in ("own", "prior")
            )
            agree = counts[(regime, "agree")] / steps
            lines.append(
                f"| {seed} | {regime} | {steps} | {100 * agree:.0f} % | {own} | {prior} "
                f"| {ended(ends)} |"
            )
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = task_parser(__doc__, episodes=10)
    parser.add_argument("--seeds", type=positive_int("--seeds"), default=3)
    args = parser.parse_args(argv)
    env_id = task_id(parser, args)
    th.set_num_threads(1)
    rows = []
    for seed in range(args.seeds):
        model, env = load_run(parser, args.study / "runs" / f"spnn-{args.path}-s{seed}", env_id)
        rows.append((seed, *step_counts(model, env, args.episodes, VALIDATION_SEED)))
        env.close()
    print(f"SPNN on {env_id}, {args.episodes} validation episodes per seed")
    print("\n".join(table(rows)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
