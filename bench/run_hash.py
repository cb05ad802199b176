"""Train the study's run for a fixed number of steps; print its CPU time and a hash of its weights.

For checking that a speed change keeps every bit: run it with ``PYTHONPATH`` at a checkout of the
code before and after, and compare the hashes (the CPU times are a side figure; alternate the
two and repeat to compare them). The run is the study's (``ours`` with ``--set``, one update per
4 steps by default, keep-best validation), seed 0, one torch thread.

Usage: python bench/run_hash.py --agent spnn --steps 6000
           --priors runs/prior-pf_straight-s0/model.zip runs/prior-oa-s0/model.zip
       python bench/run_hash.py --agent sac --steps 4000 --env rov_envs/PlanningSine-v0
"""

from __future__ import annotations

import argparse
import hashlib
import time

import gymnasium as gym
import torch as th
from dsac_update import positive_int  # bench/ is the script's folder

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy
from sb3_pnn.common.callbacks import KeepBestOnValidation
from sb3_pnn.reproduce.planning.setups import (
    SETUPS,
    TrainingSetup,
    parse_setup_changes,
    path_of_env,
)

#: The study's policy class per bench agent name.
POLICIES = {"sac": "MultiInputPolicy", "pnn": ProgressivePolicy, "spnn": SelectivePolicy}


def study_learner(
    agent: str, env: gym.Env, priors: list[str], setup: TrainingSetup, path: str
) -> DiscreteSAC:
    """The study's DiscreteSAC (``agent`` "sac"), PNN or SPNN on ``env`` with ``setup``'s
    keyword arguments for planning path ``path``, seed 0, on the CPU; ``priors`` the prior zips
    (PNN one, SPNN two, SAC none)."""
    sac = setup.sac_kwargs(agent=agent, path=path)
    sac["train_freq"] = tuple(sac["train_freq"])
    if priors:
        sac["policy_kwargs"]["priors"] = priors
    if agent == "spnn":
        sac["policy_kwargs"]["sonar_range"] = float(env.unwrapped.sonar_range)
    return DiscreteSAC(POLICIES[agent], env, seed=0, device="cpu", **sac)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--agent", choices=("sac", "pnn", "spnn"), default="sac")
    parser.add_argument("--priors", nargs="*", default=[], help="PNN: one prior zip, SPNN: two")
    parser.add_argument("--env", default="rov_envs/PlanningStraight-v0")
    parser.add_argument("--steps", type=positive_int, default=4000)
    parser.add_argument("--set", nargs="*", default=["updates=step:4"], help="factor=value")
    args = parser.parse_args()
    wanted = {"sac": 0, "pnn": 1, "spnn": 2}[args.agent]
    if len(args.priors) != wanted:
        parser.error(f"--agent {args.agent} takes {wanted} prior zip(s), got {len(args.priors)}")
    try:
        setup = SETUPS["ours"].with_(**parse_setup_changes(args.set))
        path = path_of_env(args.env)
    except ValueError as error:
        parser.error(str(error))
    th.set_num_threads(1)
    env = gym.make(args.env, **setup.train_env_kwargs())
    model = study_learner(args.agent, env, args.priors, setup, path)
    callback = None
    validation = setup.validation()
    if validation:
        callback = KeepBestOnValidation(
            args.env,
            validation["every"],
            validation["episodes"],
            setup.env_kwargs(),
            restore_at_end=False,  # hash the weights the updates reached
        )
    start = time.process_time()
    model.learn(args.steps, callback=callback)
    cpu = time.process_time() - start
    digest = hashlib.sha256()
    for name, tensor in sorted(model.policy.state_dict().items()):
        digest.update(name.encode())
        digest.update(tensor.cpu().numpy().tobytes())
    weights = digest.hexdigest()[:16]
    print(f"{args.agent} {args.env} {args.steps} steps: CPU {cpu:.2f} s, weights {weights}")


if __name__ == "__main__":
    main()
