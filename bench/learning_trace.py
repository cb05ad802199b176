"""Watch one DiscreteSAC run learn: every ``--every`` episodes, what the episodes ended in.

Prints, per block of episodes: mean return and length, end reasons (success, collision,
heading, off_path, time_limit), the entropy coefficient alpha, the policy's action probabilities
and the first critic's Q values at the task's start observation, and the elapsed time; at the
end, success over ``--eval-episodes`` evaluation episodes under the evaluation library's start
noise (seeds 10000+, apart from the training seeds; before 2026-11-23 the script used seeds
0+ here). With ``keep_best`` (on in ``ours``) it also validates every 25 episodes as the study
does and evaluates the policy kept. A diagnostic, not a statistic: the
ablation (``python -m sb3_pnn.reproduce --ablation``) measures across seeds.

Diagnostics of how the learner moves (not factors of the study, so never a default):
``--sac-kwargs`` overrides DiscreteSAC's keyword arguments (e.g. ``'{"gamma": 0.995}'``),
``--actor-lr-scale`` multiplies the actor's learning rate and ``--actor-frozen-updates N`` holds
the actor (learning rate 0) for the first N updates while the critics and alpha learn;
``--critic-mean`` reads the mean of the twin critics where discrete SAC reads their minimum
(Zhou et al. 2022, "Revisiting Discrete Soft Actor-Critic").

Usage: python bench/learning_trace.py --env rov_envs/PlanningStraight-v0 --setup ours
                                      [--episodes 300] [--seed 0] [--set progress_weighted=false]
                                      [--eval-every 100] [--actor-frozen-updates 5000]
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
import sb3_pnn.dsac.dsac as dsac_module
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


class PrintedChecks(KeepBestOnValidation):
    """The study's validation, with each check printed as it is made (success and return)."""

    def check(self) -> None:
        super().check()
        entry = self.history[-1]
        print(
            f"validation check at episode {entry['episode']}: success "
            f"{entry['success_rate'] * 100:.0f} %, mean return {entry['mean_return']:.0f}",
            flush=True,
        )


def hold_actor(model: DiscreteSAC, lr_scale: float, frozen_updates: int) -> None:
    """Scale the actor's learning rate by ``lr_scale``, and set it to 0 while fewer than
    ``frozen_updates`` updates have run (the critics and alpha learn meanwhile)."""
    update_learning_rate = model._update_learning_rate

    def scaled(optimizers) -> None:
        update_learning_rate(optimizers)
        factor = 0.0 if model._n_updates < frozen_updates else lr_scale
        for group in model.actor.optimizer.param_groups:
            group["lr"] = group["lr"] * factor

    model._update_learning_rate = scaled  # type: ignore[method-assign]


def average_critics() -> None:
    """In this process, the target and the actor loss read the critics' mean, not their min."""

    def mean(q_values: tuple[th.Tensor, ...]) -> th.Tensor:
        return th.stack(q_values, dim=0).mean(dim=0)

    dsac_module.reduce_critics = mean


def json_object(parser: argparse.ArgumentParser, flag: str, text: str) -> dict:
    """``text`` parsed as a JSON object, or a parser error that names ``flag`` and the text."""
    try:
        value = json.loads(text)
    except json.JSONDecodeError as error:
        parser.error(f"{flag} {text!r} is not JSON: {error}")
    if not isinstance(value, dict):
        parser.error(f"{flag} {text!r}: expected a JSON object")
    return value


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
    parser.add_argument(
        "--sac-kwargs",
        default="{}",
        metavar="JSON",
        help="merged over the set-up's DiscreteSAC keyword arguments, e.g. '{\"gamma\": 0.995}'",
    )
    parser.add_argument(
        "--actor-lr-scale", type=float, default=1.0, help="the actor's learning rate times this"
    )
    parser.add_argument(
        "--actor-frozen-updates",
        type=int,
        default=0,
        help="the actor does not learn during the first N updates (critics and alpha do)",
    )
    parser.add_argument(
        "--critic-mean",
        action="store_true",
        help="the target and the actor read the critics' mean instead of their min",
    )
    args = parser.parse_args()
    extra_policy_kwargs = json_object(parser, "--policy-kwargs", args.policy_kwargs)
    extra_sac_kwargs = json_object(parser, "--sac-kwargs", args.sac_kwargs)
    if not args.actor_lr_scale >= 0.0:
        parser.error(f"--actor-lr-scale {args.actor_lr_scale!r}: expected a number >= 0")
    if args.actor_frozen_updates < 0:
        parser.error(f"--actor-frozen-updates {args.actor_frozen_updates!r}: expected an int >= 0")
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
    if args.critic_mean:
        average_critics()
    print(f"set-up: {setup.to_dict()}", flush=True)
    sac = setup.sac_kwargs(agent=args.agent, path=path)
    sac["train_freq"] = tuple(sac["train_freq"])
    env = gym.make(args.env, **setup.train_env_kwargs())
    policy = {"sac": "MultiInputPolicy", "pnn": ProgressivePolicy, "spnn": SelectivePolicy}
    if args.agent != "sac":
        sac["policy_kwargs"]["priors"] = args.priors
    sac["policy_kwargs"].update(extra_policy_kwargs)
    sac.update(extra_sac_kwargs)
    if args.agent == "spnn":
        sac["policy_kwargs"]["sonar_range"] = float(env.unwrapped.sonar_range)
    model = DiscreteSAC(policy[args.agent], env, seed=args.seed, device="cpu", **sac)
    if args.actor_lr_scale != 1.0 or args.actor_frozen_updates:
        hold_actor(model, args.actor_lr_scale, args.actor_frozen_updates)
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
        keeper = PrintedChecks(
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
