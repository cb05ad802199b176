"""Do the frozen priors alone solve the planning tasks? Switch between them by obstacle distance.

A diagnostic for the SPNN's generalization (Figure 20). The policy here has no new column and
learns nothing: it plays the path-following prior's greedy action while the nearest obstacle is
farther than ``d_th`` and the obstacle-avoidance prior's greedy action when it is nearer, the
hard gate of eq. 15 applied to the priors' own outputs instead of to lateral inputs. Each prior
gets the observation keys it was trained on (``match_prior_obs``, as inside SPNN). If this
switch succeeds on the new layouts, the skills the transfer needs are in the priors and a
trained SPNN that fails there lost them; if it fails too, the priors do not compose.

Evaluated as the study evaluates (50 episodes per task on seeds 10000+, the evaluation
library's start noise); the environment keywords are those of the study's ``ours`` set-up.

Usage: python bench/prior_switch.py --pf-straight P.zip --pf-sine P.zip --oa P.zip [--d-th 12.5]
       [--hysteresis 0 10]  (a switch that keeps the avoidance prior until d_th + H)
       [--seed 20000 --training-tasks-only]  (validation seeds, no new layout: to choose on)
       [--seed 20000 --drawn-layouts]  (validation seeds: the planning tasks as they are and
       among obstacles drawn afresh by the ``scatter`` generator, none of the new layouts'; the
       validation measure of generalization of ``sb3_pnn.reproduce.tools.drawn_layouts``)
       (the 5-seed study's priors: STUDY/runs/prior-{pf_straight,pf_sine,oa}-s0/model.zip)
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np
import torch as th

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC
from sb3_pnn.evaluation import evaluate_policy_on_task
from sb3_pnn.evaluation.evaluate import trained_env_kwargs
from sb3_pnn.progressive.switch_memory import remembered_switch
from sb3_pnn.reproduce.planning.setups import OURS
from sb3_pnn.reproduce.running.work import EVAL_SEED
from sb3_pnn.reproduce.tools.drawn_layouts import LAYOUT
from sb3_pnn.reproduce.tools.spnn_switch_distance import add_hysteresis_argument

#: (label, env id, extra env keywords): the study's evaluation tasks, by path.
TASKS = {
    "straight": [
        ("original", "rov_envs/PlanningStraight-v0", {}),
        ("path following, no obstacles", "rov_envs/PlanningStraight-v0", {"obstacles": []}),
        ("new: uniform obstacles", "rov_envs/PlanningStraightUniform-v0", {}),
        ("new: dense obstacles", "rov_envs/PlanningStraightDense-v0", {}),
    ],
    "sine": [
        ("original", "rov_envs/PlanningSine-v0", {}),
        ("path following, no obstacles", "rov_envs/PlanningSine-v0", {"obstacles": []}),
        ("new: dense obstacles", "rov_envs/PlanningSineDense-v0", {}),
    ],
}


class PriorSwitch:
    """Greedy action of the path-following prior, or of the avoidance prior within ``d_th``.

    With ``hysteresis`` h > 0 the switch remembers: once the avoidance prior has control it
    keeps it until the nearest reading is beyond ``d_th + h`` (eq. 15's selector is memoryless,
    h = 0). The 180-degree sonar loses an obstacle when the vehicle turns its back to it, so
    the memoryless switch can hand control back while the obstacle is still beside the route.
    """

    def __init__(
        self,
        pf: DiscreteSAC,
        oa: DiscreteSAC,
        d_th: float,
        sonar_range: float,
        hysteresis: float = 0.0,
    ):
        self.pf, self.oa, self.d_th, self.sonar_range = pf, oa, d_th, sonar_range
        self.hysteresis = hysteresis
        self.oa_share: list[float] = []
        self.handovers = 0  # changes of the column in control within an episode
        self.decisions = 0
        self._near: np.ndarray | None = None

    @staticmethod
    def _greedy(model: DiscreteSAC, obs: dict[str, np.ndarray]) -> np.ndarray:
        keys = model.observation_space.spaces.keys()
        action, _ = model.predict({k: obs[k] for k in keys}, deterministic=True)
        return np.asarray(action)

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        nearest = obs["sonar"].min(axis=-1) * self.sonar_range
        near = remembered_switch(nearest, self._near, self.d_th, self.hysteresis, episode_start)
        if self._near is not None and self._near.shape == near.shape:
            starting = np.zeros_like(near) if episode_start is None else episode_start
            self.handovers += int(np.sum((near != self._near) & ~starting))
        self._near = near
        self.decisions += near.size
        self.oa_share.append(float(np.mean(near)))
        action = np.where(near, self._greedy(self.oa, obs), self._greedy(self.pf, obs))
        return action, state


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pf-straight", required=True)
    parser.add_argument("--pf-sine", required=True)
    parser.add_argument("--oa", required=True)
    parser.add_argument("--d-th", type=float, default=12.5, help="switch distance (m), paper 12.5")
    add_hysteresis_argument(parser, default=[0.0])
    parser.add_argument("--episodes", type=int, default=50)
    parser.add_argument(
        "--seed", type=int, default=EVAL_SEED, help="first episode seed (study evaluation: 10000)"
    )
    parser.add_argument(
        "--training-tasks-only",
        action="store_true",
        help="only the planning tasks the agents train on, with and without their obstacles "
        "(what a choice may be made on), not the new layouts",
    )
    parser.add_argument(
        "--drawn-layouts",
        action="store_true",
        help="the planning tasks as they are and with obstacles drawn afresh every episode "
        "(layout='scatter'; a validation measure of generalization), not the new layouts",
    )
    args = parser.parse_args()
    if not args.d_th > 0:
        parser.error(f"--d-th {args.d_th} is not allowed: expected a distance > 0 (m)")
    if args.episodes < 1 or args.seed < 0:
        parser.error(f"--episodes {args.episodes} / --seed {args.seed}: expected >= 1 / >= 0")
    th.set_num_threads(1)
    env_kwargs = OURS.env_kwargs()
    oa = DiscreteSAC.load(args.oa, device="cpu")
    if oa.observation_space["goal"].shape == (2,):  # a column that reads its offset (oa_offset_obs)
        env_kwargs["goal_offset"] = True
    # the goal part the avoidance column reads is the goal it was trained with
    oa_kwargs = trained_env_kwargs(oa, "rov_envs/ObstacleAvoidance-v0")
    if "goal_distance" in oa_kwargs:
        env_kwargs["goal_distance"] = oa_kwargs["goal_distance"]
    print(
        f"d_th {args.d_th} m; env keywords {env_kwargs}; {args.episodes} episodes per task "
        f"on seeds {args.seed}+"
    )
    for path, prior in (("straight", args.pf_straight), ("sine", args.pf_sine)):
        pf = DiscreteSAC.load(prior, device="cpu")
        tasks = TASKS[path]
        if args.drawn_layouts:
            env_id = tasks[0][1]
            tasks = [tasks[0], (f"drawn obstacles ({LAYOUT})", env_id, {"layout": LAYOUT})]
        for label, env_id, extra in tasks:
            if args.training_tasks_only and label.startswith("new"):
                continue
            kwargs = {**env_kwargs, **extra}
            probe = gym.make(env_id, **kwargs)
            sonar_range = probe.unwrapped.sonar_range
            probe.close()
            for hysteresis in args.hysteresis:
                policy = PriorSwitch(pf, oa, args.d_th, sonar_range, hysteresis)
                start = time.time()
                result = evaluate_policy_on_task(
                    policy,
                    env_id,
                    n_episodes=args.episodes,
                    seed=args.seed,
                    env_kwargs=kwargs,
                )
                low, high = result.success_ci95
                ends = ", ".join(f"{k} {v}" for k, v in sorted(result.end_reasons.items()))
                print(
                    f"{path:8} {label:30} h {hysteresis:g} m: success {result.success_rate:4.0%}"
                    f" [{low:.0%}, {high:.0%}]  mean |g| {result.mean_abs_cross_track:4.2f} m"
                    f", |a_c| {np.degrees(result.mean_abs_heading_error):4.1f} deg"
                    f"  avoidance prior in {np.mean(policy.oa_share):4.0%} of decisions"
                    f", handovers per 100 decisions "
                    f"{100 * policy.handovers / max(policy.decisions, 1):.1f}"
                    f"  ({ends}; {time.time() - start:.0f} s)",
                    flush=True,
                )


if __name__ == "__main__":
    main()
