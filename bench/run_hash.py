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
from sb3_pnn.reproduce.setups import SETUPS, parse_setup_changes, path_of_env
from sb3_pnn.validation import KeepBestOnValidation


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
    sac = setup.sac_kwargs(agent=args.agent, path=path)
    sac["train_freq"] = tuple(sac["train_freq"])
    env = gym.make(args.env, **setup.train_env_kwargs())
    if args.priors:
        sac["policy_kwargs"]["priors"] = args.priors
    if args.agent == "spnn":
        sac["policy_kwargs"]["sonar_range"] = float(env.unwrapped.sonar_range)
    policy = {"sac": "MultiInputPolicy", "pnn": ProgressivePolicy, "spnn": SelectivePolicy}
    model = DiscreteSAC(policy[args.agent], env, seed=0, device="cpu", **sac)
    callback = None
    validation = setup.validation()
    if validation:
        callback = KeepBestOnValidation(
            args.env, validation["every"], validation["episodes"], setup.env_kwargs()
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
