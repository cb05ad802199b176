"""Watch one DiscreteSAC run learn: every ``--every`` episodes, what the episodes ended in.

Prints, per block of episodes: mean return and length, end reasons (success, collision,
heading, off_path, time_limit), the entropy coefficient alpha, the policy's action probabilities
and the first critic's Q values at the task's start observation, and the elapsed time; at the
end, success over ``--eval-episodes`` evaluation episodes under the evaluation library's start
noise (seeds 10000+, apart from the training seeds; before 2026-11-23 the script used seeds
0+ here). With ``keep_best`` (on in ``ours``) it also validates every 25 episodes as the study
does and evaluates the policy kept. A diagnostic, not a statistic: the
ablation (``python -m sb3_pnn.reproduce --ablation``) measures across seeds.

Usage: python bench/learning_trace.py --env rov_envs/PlanningStraight-v0 --setup ours
                                      [--episodes 300] [--seed 0] [--set progress_weighted=false]
                                      [--eval-every 100]
"""

from __future__ import annotations

import argparse
import json
import time

import gymnasium as gym
import numpy as np
import torch as th
from stable_baselines3.common.callbacks import BaseCallback, CallbackList

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy
from sb3_pnn.common.callbacks import VALIDATION_SEED, KeepBestOnValidation
from sb3_pnn.evaluation import evaluate_policy_on_task
from sb3_pnn.reproduce.planning.setups import SETUPS, parse_setup_changes, path_of_env
from sb3_pnn.reproduce.running.work import EVAL_SEED


class Trace(BaseCallback):
    """Prints a line per block of episodes; stops after ``episodes``."""

    def __init__(
        self, model_ref: list, obs0: dict, episodes: int, every: int, evaluate=None, eval_every=0
    ) -> None:
        super().__init__()
        self.model_ref, self.obs0, self.episodes, self.every = model_ref, obs0, episodes, every
        self.evaluate, self.eval_every = evaluate, eval_every
        self.ret, self.returns, self.lengths, self.ends, self.n = 0.0, [], [], [], 0
        self.t0 = time.time()

    def _on_step(self) -> bool:
        self.ret += float(self.locals["rewards"][0])
        self.n += 1
        if self.locals["dones"][0]:
            self.returns.append(self.ret)
            self.lengths.append(self.n)
            self.ends.append(self.locals["infos"][0].get("end_reason"))
            self.ret, self.n = 0.0, 0
            if len(self.returns) % self.every == 0:
                self._print()
            if self.eval_every and len(self.returns) % self.eval_every == 0:
                self.evaluate(f"after {len(self.returns)} episodes")
        return len(self.returns) < self.episodes

    def _print(self) -> None:
        model = self.model_ref[0]
        obs = {k: th.as_tensor(v[None]) for k, v in self.obs0.items()}
        with th.no_grad():
            q = model.critic(obs)[0][0].numpy().round(1).tolist()
            pi = th.softmax(model.actor(obs), 1)[0].numpy().round(2).tolist()
        alpha = model.ent_coef  # a fixed alpha, unless it is learned
        if model.log_ent_coef is not None:
            alpha = float(th.exp(model.log_ent_coef).item())
        ends = self.ends[-self.every :]
        counts = {e: ends.count(e) for e in sorted(set(ends))}
        print(
            f"episode {len(self.returns)} steps {self.num_timesteps} "
            f"return {np.mean(self.returns[-self.every :]):.0f} "
            f"length {np.mean(self.lengths[-self.every :]):.0f} ends {counts} alpha {alpha:.3f} "
            f"pi(s0) {pi} Q1(s0) {q} t {time.time() - self.t0:.0f} s",
            flush=True,
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--env", default="rov_envs/PlanningStraight-v0")
    parser.add_argument("--setup", choices=sorted(SETUPS), default="ours")
    parser.add_argument(
        "--set", nargs="*", default=[], help="factor=value, e.g. progress_weighted=false"
    )
    parser.add_argument(
        "--agent",
        choices=("sac", "pnn", "spnn"),
        default="sac",
        help="DiscreteSAC from scratch, or PNN / SPNN on the --priors",
    )
    parser.add_argument(
        "--priors", nargs="*", default=[], help="prior zips: PNN one (path following), SPNN two"
    )
    parser.add_argument("--episodes", type=int, default=300)
    parser.add_argument("--every", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--eval-episodes", type=int, default=50)
    parser.add_argument(
        "--eval-every", type=int, default=0, help="also evaluate every N training episodes"
    )
    parser.add_argument("--save", default="", help="save the model here at the end")
    parser.add_argument(
        "--policy-kwargs",
        default="{}",
        metavar="JSON",
        help="merged over the set-up's policy_kwargs, e.g. '{\"lateral_scale_init\": 0.1}'",
    )
    args = parser.parse_args()
    try:
        extra_policy_kwargs = json.loads(args.policy_kwargs)
    except json.JSONDecodeError as error:
        parser.error(f"--policy-kwargs {args.policy_kwargs!r} is not JSON: {error}")
    if not isinstance(extra_policy_kwargs, dict):
        parser.error(f"--policy-kwargs {args.policy_kwargs!r}: expected a JSON object")
    wanted = {"sac": 0, "pnn": 1, "spnn": 2}[args.agent]
    if len(args.priors) != wanted:
        parser.error(
            f"--agent {args.agent} takes {wanted} prior zip(s) in --priors, got {len(args.priors)}"
        )
    try:
        setup = SETUPS[args.setup].with_(**parse_setup_changes(args.set))
        path = path_of_env(args.env)
    except ValueError as error:
        parser.error(str(error))
    th.set_num_threads(1)
    print(f"set-up: {setup.to_dict()}", flush=True)
    sac = setup.sac_kwargs(agent=args.agent, path=path)
    sac["train_freq"] = tuple(sac["train_freq"])
    env = gym.make(args.env, **setup.train_env_kwargs())
    policy = {"sac": "MultiInputPolicy", "pnn": ProgressivePolicy, "spnn": SelectivePolicy}
    if args.agent != "sac":
        sac["policy_kwargs"]["priors"] = args.priors
    sac["policy_kwargs"].update(extra_policy_kwargs)
    if args.agent == "spnn":
        sac["policy_kwargs"]["sonar_range"] = float(env.unwrapped.sonar_range)
    model = DiscreteSAC(policy[args.agent], env, seed=args.seed, device="cpu", **sac)
    obs0, _ = gym.make(args.env, **setup.env_kwargs()).reset(seed=0)

    def evaluate(when: str) -> None:
        result = evaluate_policy_on_task(
            model,
            args.env,
            n_episodes=args.eval_episodes,
            seed=EVAL_SEED,
            env_kwargs=setup.env_kwargs(),
        )
        lo, hi = result.success_ci95
        print(
            f"evaluation {when}: {result.success_rate * 100:.0f} % [{lo * 100:.0f}, "
            f"{hi * 100:.0f}] of {result.n_episodes}; ends {result.end_reasons}",
            flush=True,
        )

    trace = Trace([model], obs0, args.episodes, args.every, evaluate, args.eval_every)
    callbacks = [trace]
    validation = setup.validation()
    if validation:  # keep_best: what the study does (sb3_pnn.reproduce.running.work.train)
        keeper = KeepBestOnValidation(
            args.env,
            validation["every"],
            validation["episodes"],
            setup.env_kwargs(),
            restore_at_end=False,  # the trace evaluates the last weights, then the kept ones
        )
        callbacks.append(keeper)
    model.learn(10**9, callback=CallbackList(callbacks))
    if not args.eval_every or args.episodes % args.eval_every:
        evaluate("at the end")
    if validation and keeper.history:
        checks = " ".join(f"{h['episode']}:{h['success_rate'] * 100:.0f}%" for h in keeper.history)
        print(f"validation (episode:success, seeds {VALIDATION_SEED}+): {checks}", flush=True)
        keeper.restore()
        evaluate(f"of the policy kept (episode {keeper.best_episode})")
    if args.save:
        model.save(args.save)


if __name__ == "__main__":
    main()
