"""The script behind docs/ablation/README.md's ObstacleAvoidance heading-reference rows (section 4).

A DiscreteSAC (or PNN / SPNN) run on the ``ours`` set-up (``--setup`` JSON changes it), with
DiscreteSAC keyword arguments (``--sac``, e.g. a fixed ``{"ent_coef": 0.05}``) and environment
keyword arguments (``--envkw``) on top; every ``--val-every`` training episodes it validates on
``--val-episodes`` episodes (seeds 20000+) and keeps the best weights; at the end it evaluates
the last and the kept policy on ``--eval-episodes`` episodes (seeds 10000+). Superseded by
``bench/learning_trace.py`` with ``keep_best`` (the study's schedule); kept so that the rows it
made can be rerun exactly:

    python -m sb3_pnn.reproduce.tools.validation_trace --seed 0 [--sac '{"ent_coef": 0.05}']
"""

import argparse
import copy
import json
import time

import gymnasium as gym
import torch as th
from stable_baselines3.common.callbacks import BaseCallback

import rov_envs  # noqa
from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy
from sb3_pnn.evaluation import evaluate_policy_on_task
from sb3_pnn.reproduce.planning.setups import OURS

p = argparse.ArgumentParser()
p.add_argument("--env", default="rov_envs/ObstacleAvoidance-v0")
p.add_argument("--episodes", type=int, default=400)
p.add_argument("--seed", type=int, default=0)
p.add_argument("--setup", default="{}")
p.add_argument("--sac", default="{}")
p.add_argument("--envkw", default="{}")
p.add_argument("--agent", default="sac")
p.add_argument("--priors", nargs="*", default=[])
p.add_argument("--val-every", type=int, default=50)
p.add_argument("--val-episodes", type=int, default=30)
p.add_argument("--eval-episodes", type=int, default=100)
p.add_argument("--save", default="")
a = p.parse_args()
th.set_num_threads(1)
ch = json.loads(a.setup)
if "net_arch" in ch:
    ch["net_arch"] = tuple(ch["net_arch"])
setup = OURS.with_(**ch)
sac = setup.sac_kwargs()
sac["train_freq"] = tuple(sac["train_freq"])
sac.update(json.loads(a.sac))
envkw = {**setup.env_kwargs(), **json.loads(a.envkw)}
env = gym.make(a.env, **{**setup.train_env_kwargs(), **json.loads(a.envkw)})
pol = {"sac": "MultiInputPolicy", "pnn": ProgressivePolicy, "spnn": SelectivePolicy}[a.agent]
if a.agent != "sac":
    sac["policy_kwargs"]["priors"] = a.priors
if a.agent == "spnn":
    sac["policy_kwargs"]["sonar_range"] = float(env.unwrapped.sonar_range)
model = DiscreteSAC(pol, env, seed=a.seed, device="cpu", **sac)
print("setup", setup.to_dict(), "sac", json.loads(a.sac), "envkw", json.loads(a.envkw), flush=True)
t0 = time.time()


def ev(n, seed):
    return evaluate_policy_on_task(model, a.env, n_episodes=n, seed=seed, env_kwargs=envkw)


class CB(BaseCallback):
    def __init__(s):
        super().__init__()
        s.eps = 0
        s.ends = []
        s.best = -1
        s.best_state = None
        s.best_ep = 0

    def _on_step(s):
        if s.locals["dones"][0]:
            s.eps += 1
            s.ends.append(s.locals["infos"][0].get("end_reason"))
            if s.eps % a.val_every == 0:
                r = ev(a.val_episodes, 20000)
                last = s.ends[-a.val_every :]
                alpha = (
                    float(th.exp(model.log_ent_coef).item())
                    if model.log_ent_coef is not None
                    else model.ent_coef
                )
                print(
                    f"ep {s.eps} train_succ {last.count('success')}/{len(last)} "
                    f"val {r.success_rate * 100:.0f}% {r.end_reasons} alpha {alpha:.3f} "
                    f"t {time.time() - t0:.0f}s",
                    flush=True,
                )
                if r.success_rate > s.best:
                    s.best = r.success_rate
                    s.best_ep = s.eps
                    s.best_state = copy.deepcopy(model.policy.state_dict())
        return s.eps < a.episodes


cb = CB()
model.learn(10**9, callback=cb)
r = ev(a.eval_episodes, 10000)
lo, hi = r.success_ci95
print(
    f"FINAL last: {r.success_rate * 100:.0f}% [{lo * 100:.0f},{hi * 100:.0f}] {r.end_reasons}",
    flush=True,
)
model.policy.load_state_dict(cb.best_state)
r = ev(a.eval_episodes, 10000)
lo, hi = r.success_ci95
print(
    f"FINAL best(ep {cb.best_ep}, val {cb.best * 100:.0f}%): {r.success_rate * 100:.0f}% "
    f"[{lo * 100:.0f},{hi * 100:.0f}] {r.end_reasons} wall {time.time() - t0:.0f}s",
    flush=True,
)
if a.save:
    model.save(a.save)
