"""Transfer benchmark of the paper's section 4.3.1 on ``rov_envs/PlanningStraight-v0``.

1. Trains the priors with DiscreteSAC: path following on ``PathFollowingStraight-v0`` and obstacle
   avoidance on ``ObstacleAvoidance-v0`` (one prior pair per ``--prior-seed``), and reports each
   prior's success rate on its own task.
2. Trains, for the same number of episodes and for every seed, on ``PlanningStraight-v0``:
   SAC-Single (from scratch), SAC-Multi (all networks from the path-following prior), PNN (two
   columns: path-following prior + new) and SPNN (three columns, the paper's hard gate).
3. Prints, per run, the episode of the first success (``info["is_success"]`` on the final step
   of a training episode; "-" if none) and the success rate of the final policy (deterministic,
   ``--eval-episodes`` episodes), then per method the mean/median over seeds.

The paper (Figure 11) reports PNN and SPNN completing the task by episode 80 while SAC-Single and
SAC-Multi still fail at episode 150; this script prints whatever it measures.

Quick run:
    python bench/transfer.py --prior-episodes 30 --episodes 20 --seeds 0 1 2 --net-arch 64 64
Paper-size: python bench/transfer.py --prior-episodes 300 --episodes 150 --seeds 0 1 2
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import torch as th
from stable_baselines3.common.callbacks import BaseCallback

import rov_envs  # noqa: F401  (registers the tasks)
from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy, make_sac_multi

PF_ID = "rov_envs/PathFollowingStraight-v0"
OA_ID = "rov_envs/ObstacleAvoidance-v0"
TASK_ID = "rov_envs/PlanningStraight-v0"
METHODS = ("SAC-Single", "SAC-Multi", "PNN", "SPNN")


class EpisodeBudget(BaseCallback):
    """Stops learning after ``n_episodes`` episodes; records the first successful episode and
    each episode's return and length (from SB3's Monitor wrapper)."""

    def __init__(self, n_episodes: int):
        super().__init__()
        self.n_episodes = n_episodes
        self.episodes = 0
        self.first_success: int | None = None
        self.successes = 0
        self.returns: list[float] = []
        self.lengths: list[int] = []

    def last(self, k: int = 20) -> tuple[float, float]:
        """Mean return and mean length of the last ``k`` training episodes."""
        return float(np.mean(self.returns[-k:])), float(np.mean(self.lengths[-k:]))

    def _on_step(self) -> bool:
        for done, info in zip(self.locals["dones"], self.locals["infos"], strict=True):
            if done:
                self.episodes += 1
                if "episode" in info:
                    self.returns.append(float(info["episode"]["r"]))
                    self.lengths.append(int(info["episode"]["l"]))
                if info.get("is_success"):
                    self.successes += 1
                    if self.first_success is None:
                        self.first_success = self.episodes
        return self.episodes < self.n_episodes


def success_rate(
    model: DiscreteSAC, env_id: str, n_episodes: int, seed: int
) -> tuple[float, dict[str, int]]:
    """Share of ``n_episodes`` deterministic episodes ending with ``info["is_success"]``, and
    the count of each ``info["end_reason"]``."""
    env = gym.make(env_id)
    wins = 0
    reasons: dict[str, int] = {}
    for k in range(n_episodes):
        obs, _ = env.reset(seed=seed + k)
        done, info = False, {}
        while not done:
            action, _ = model.predict(obs, deterministic=True)
            obs, _, terminated, truncated, info = env.step(int(action))
            done = terminated or truncated
        wins += bool(info.get("is_success"))
        reason = str(info.get("end_reason", "?"))
        reasons[reason] = reasons.get(reason, 0) + 1
    env.close()
    return wins / n_episodes, reasons


def common_kwargs(args: argparse.Namespace, seed: int) -> dict[str, Any]:
    return dict(
        learning_starts=args.learning_starts,
        batch_size=args.batch_size,
        gradient_steps=args.gradient_steps,
        seed=seed,
        device=args.device,
        target_entropy_ratio=args.target_entropy_ratio,
        verbose=0,
    )


def train(model: DiscreteSAC, episodes: int) -> tuple[EpisodeBudget, float]:
    budget = EpisodeBudget(episodes)
    start = time.perf_counter()
    model.learn(total_timesteps=10**9, callback=budget)
    return budget, time.perf_counter() - start


def train_prior(job: dict[str, Any]) -> dict[str, Any]:
    args, env_id, path, seed = job["args"], job["env_id"], job["path"], job["seed"]
    th.set_num_threads(1)
    env = gym.make(env_id)
    model = DiscreteSAC(
        "MultiInputPolicy",
        env,
        policy_kwargs=dict(net_arch=args.net_arch),
        **common_kwargs(args, seed),
    )
    budget, wall = train(model, job["episodes"])
    model.save(path)
    rate, reasons = success_rate(model, env_id, args.eval_episodes, 10_000 + seed)
    return dict(
        env_id=env_id,
        path=str(path),
        seed=seed,
        episodes=budget.episodes,
        first_success=budget.first_success,
        train_successes=budget.successes,
        success_rate=rate,
        end_reasons=reasons,
        wall_s=wall,
    )


def run_transfer(job: dict[str, Any]) -> dict[str, Any]:
    args, method, seed, pf, oa = job["args"], job["method"], job["seed"], job["pf"], job["oa"]
    th.set_num_threads(1)
    env = gym.make(TASK_ID)
    kwargs = common_kwargs(args, seed)
    arch = dict(net_arch=args.net_arch)
    if method == "SAC-Single":
        model = DiscreteSAC("MultiInputPolicy", env, policy_kwargs=arch, **kwargs)
    elif method == "SAC-Multi":
        model = make_sac_multi(pf, env, **kwargs)
    elif method == "PNN":
        model = DiscreteSAC(
            ProgressivePolicy, env, policy_kwargs=dict(priors=[pf], **arch), **kwargs
        )
    elif method == "SPNN":
        spnn = dict(priors=[pf, oa], sonar_range=float(env.unwrapped.sonar_range), gate=args.gate)
        model = DiscreteSAC(SelectivePolicy, env, policy_kwargs=dict(**spnn, **arch), **kwargs)
    else:
        raise ValueError(f"unknown method {method!r}; expected one of {METHODS}")
    budget, wall = train(model, args.episodes)
    rate, reasons = success_rate(model, TASK_ID, args.eval_episodes, 20_000 + seed)
    ret20, len20 = budget.last(20)
    return dict(
        method=method,
        seed=seed,
        first_success=budget.first_success,
        train_successes=budget.successes,
        success_rate=rate,
        end_reasons=reasons,
        last20_return=ret20,
        last20_length=len20,
        wall_s=wall,
        steps=int(model.num_timesteps),
    )


def pool_map(fn, jobs: list[dict[str, Any]], workers: int) -> list[dict[str, Any]]:
    if workers <= 1:
        return [fn(j) for j in jobs]
    with ProcessPoolExecutor(max_workers=workers) as pool:
        return list(pool.map(fn, jobs))


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--episodes", type=int, default=150, help="transfer episodes per run")
    parser.add_argument(
        "--prior-episodes",
        type=int,
        nargs="+",
        default=[300],
        help="episodes of the path-following prior [and of the obstacle-avoidance prior]",
    )
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument(
        "--prior-seeds",
        type=int,
        nargs="+",
        default=[100],
        help="one prior pair per prior seed; run i uses prior pair i mod n",
    )
    parser.add_argument("--methods", nargs="+", default=list(METHODS), choices=METHODS)
    parser.add_argument("--net-arch", type=int, nargs="+", default=[255, 255])
    parser.add_argument(
        "--learning-starts",
        type=int,
        default=256,
        help="random-action steps before learning (episodes are short at first)",
    )
    parser.add_argument("--batch-size", type=int, default=256)
    parser.add_argument("--gradient-steps", type=int, default=10, help="per episode (paper: 10)")
    parser.add_argument("--eval-episodes", type=int, default=5)
    parser.add_argument("--target-entropy-ratio", type=float, default=0.98, help="paper: 0.98")
    parser.add_argument("--gate", default="hard", choices=("hard", "soft", "learned"))
    parser.add_argument("--workers", type=int, default=1, help="parallel processes")
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--out", type=Path, default=Path("results/transfer"))
    parser.add_argument("--reuse-priors", action="store_true", help="keep existing prior zips")
    args = parser.parse_args()
    if len(args.prior_episodes) not in (1, 2):
        parser.error("--prior-episodes takes one or two values (path following, avoidance)")
    if min(args.episodes, *args.prior_episodes, args.eval_episodes) < 1:
        parser.error("--episodes, --prior-episodes and --eval-episodes must be >= 1")
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()

    prior_jobs, pairs = [], []
    for ps in args.prior_seeds:
        pf, oa = args.out / f"prior_pf_s{ps}.zip", args.out / f"prior_oa_s{ps}.zip"
        pairs.append((str(pf), str(oa)))
        budgets = (args.prior_episodes[0], args.prior_episodes[-1])
        for env_id, path, n in zip((PF_ID, OA_ID), (pf, oa), budgets, strict=True):
            if not (args.reuse_priors and path.exists()):
                prior_jobs.append(dict(args=args, env_id=env_id, path=path, seed=ps, episodes=n))
    print(f"training {len(prior_jobs)} priors (episodes: {args.prior_episodes})...", flush=True)
    for r in pool_map(train_prior, prior_jobs, args.workers):
        print(
            f"  prior {r['env_id']:<34} seed {r['seed']}: first success episode "
            f"{r['first_success'] or '-'}, "
            f"wins in training {r['train_successes']}/{r['episodes']}, "
            f"final success rate {r['success_rate']:.2f} {r['end_reasons']} "
            f"({r['wall_s']:.0f} s)",
            flush=True,
        )

    jobs = [
        dict(args=args, method=m, seed=s, pf=pairs[i % len(pairs)][0], oa=pairs[i % len(pairs)][1])
        for i, s in enumerate(args.seeds)
        for m in args.methods
    ]
    print(f"transfer on {TASK_ID}: {len(jobs)} runs of {args.episodes} episodes", flush=True)
    results = pool_map(run_transfer, jobs, args.workers)
    print(
        f"\n{'method':<11} {'seed':>4} {'first success':>13} {'train wins':>10} "
        f"{'final success':>13} {'last-20 return':>14} {'last-20 length':>14} {'steps':>8} "
        f"{'wall s':>7}  final-policy end reasons"
    )
    for r in results:
        print(
            f"{r['method']:<11} {r['seed']:>4} {str(r['first_success'] or '-'):>13} "
            f"{r['train_successes']:>10} {r['success_rate']:>13.2f} {r['last20_return']:>14.1f} "
            f"{r['last20_length']:>14.0f} {r['steps']:>8} {r['wall_s']:>7.0f}  {r['end_reasons']}"
        )
    print(f"\nper method over seeds {args.seeds} ({args.episodes} episodes; '-' = no success):")
    for m in args.methods:
        rs = [r for r in results if r["method"] == m]
        firsts = [r["first_success"] for r in rs if r["first_success"] is not None]
        med = statistics.median(firsts) if len(firsts) == len(rs) else "-"
        print(
            f"  {m:<11} succeeded in {len(firsts)}/{len(rs)} runs, first-success episodes "
            f"{[r['first_success'] or '-' for r in rs]} (median {med}), final success rate "
            f"mean {np.mean([r['success_rate'] for r in rs]):.2f}"
        )
    (args.out / "transfer.json").write_text(
        json.dumps(
            dict(
                config={k: v for k, v in vars(args).items() if k != "out"} | {"out": str(args.out)},
                results=results,
            ),
            indent=2,
            default=str,
        )
    )
    print(
        f"\ntotal {time.perf_counter() - t0:.0f} s; "
        f"results in {os.fspath(args.out / 'transfer.json')}"
    )


if __name__ == "__main__":
    main()
