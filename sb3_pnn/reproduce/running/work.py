"""The work of one run of the study: train (DiscreteSAC, SAC-Multi, PNN or SPNN) and evaluate.

:func:`run_work` is what :func:`sb3_pnn.reproduce.running.executor.run_one` calls in a worker
process.
It writes into the run's temporary folder:

* ``model.zip``: the final policy (SB3 format; PNN/SPNN models are self-contained, their prior
  weights are inside), for ``prior`` and ``transfer`` runs;
* ``validation.json``: when the run keeps its best policy (``spec.validation``), the
  validation checks and the training episode whose policy was kept (and saved as model.zip);
* ``model_by_<ranking>.zip``: with ``validation["also_rank_by"]``, the policy each further
  ranking keeps of the same training (:func:`also_rank_by`);
* ``episodes.json``: per training episode return, length, success and end reason
  (:class:`.recorder.EpisodeRecorder`), and ``trajectories.npz``: the positions of the recorded
  training episodes (key ``ep_<index>``, arrays (T, 2));
* ``selection.json`` (``select`` runs): each candidate's kept validation check (its success and
  the entry it was ranked by) and the one kept;
  the run's ``model.zip``, ``validation.json`` and ``eval.json`` are that candidate's;
* ``eval.json``: for every run with evaluation tasks (all of them in the study), one
  :class:`sb3_pnn.evaluation.EvaluationResult` dict per evaluation task (label -> dict), from
  ``eval_episodes`` episodes with seeds ``EVAL_SEED + i`` (the same episodes for every policy)
  and the evaluation library's default start-pose noise; a trained policy is played as
  ``spec.play`` names (:func:`played`: SPNN through a switch memory and / or without
  immediate turn reversals, or as trained).
"""

from __future__ import annotations

import dataclasses
import json
import math
import shutil
import time
from pathlib import Path
from typing import Any

import numpy as np

from sb3_pnn.reproduce.planning.plan import AGENT_LABELS, RunSpec
from sb3_pnn.reproduce.planning.setups import validation_env_kwargs

#: First evaluation seed (training seeds are 0..seeds-1; evaluation episodes are others).
EVAL_SEED = 10_000
#: ``learn()`` is stopped by the episode budget, never by this step count.
MAX_STEPS = 10**9


def build_model(spec: RunSpec, deps: dict[str, Path], device: str = "cpu") -> Any:
    """The DiscreteSAC model of ``spec`` on a fresh single environment.

    ``device``: the study trains on the CPU (its small networks gain nothing from a GPU, and
    its runs are compared bit for bit); another device is for checking that the same agents
    train there (tests/sb3_pnn/reproduce/test_cuda_agents.py).
    """
    import gymnasium as gym

    import rov_envs  # noqa: F401 - registers the tasks
    from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy, make_sac_multi

    if spec.env_id is None:
        raise ValueError(f"run {spec.run_id!r} has no environment")
    env = gym.make(spec.env_id, **spec.env_kwargs)
    priors = [str(deps[d] / "model.zip") for d in spec.deps]
    sac_kwargs = dict(spec.sac_kwargs)
    if "train_freq" in sac_kwargs:  # JSON holds the (frequency, unit) pair as a list
        sac_kwargs["train_freq"] = tuple(sac_kwargs["train_freq"])
    policy_kwargs = dict(sac_kwargs.pop("policy_kwargs", None) or {})
    common: dict[str, Any] = dict(seed=spec.seed, verbose=0, device=device, **sac_kwargs)
    if spec.agent in ("dsac", "sac_single"):
        return DiscreteSAC("MultiInputPolicy", env, policy_kwargs=policy_kwargs, **common)
    if spec.agent == "sac_multi":
        # the networks are the prior's (make_sac_multi refuses a net_arch of its own)
        policy_kwargs.pop("net_arch", None)
        return make_sac_multi(priors[0], env, policy_kwargs=policy_kwargs, **common)
    if spec.agent == "pnn":
        policy_kwargs["priors"] = priors
        return DiscreteSAC(ProgressivePolicy, env, policy_kwargs=policy_kwargs, **common)
    if spec.agent == "spnn":
        policy_kwargs.update(priors=priors, sonar_range=float(env.unwrapped.sonar_range))
        return DiscreteSAC(SelectivePolicy, env, policy_kwargs=policy_kwargs, **common)
    raise ValueError(f"agent {spec.agent!r} of run {spec.run_id!r} is unknown")


def also_rank_by(spec: RunSpec) -> tuple[str, ...]:
    """The further rankings whose policies the run keeps beside the kept one (the spec's
    ``validation["also_rank_by"]``, comma-separated; :attr:`TrainingSetup.keep_best_also`)."""
    text = str((spec.validation or {}).get("also_rank_by", ""))
    return tuple(name for name in text.split(",") if name)


def kept_model_name(ranking: str | None) -> str:
    """The file in a run folder that holds the policy kept by ``ranking`` (None: the run's own
    ranking, ``model.zip``)."""
    return "model.zip" if ranking is None else f"model_by_{ranking}.zip"


def train(spec: RunSpec, tmp: Path, deps: dict[str, Path]) -> tuple[Any, dict[str, Any]]:
    """Train for ``spec.episodes`` episodes; save model, episode records and trajectories."""
    from stable_baselines3.common.callbacks import CallbackList

    from sb3_pnn.common.callbacks import KeepBestOnValidation
    from sb3_pnn.reproduce.running.recorder import EpisodeRecorder

    model = build_model(spec, deps)
    recorder = EpisodeRecorder(spec.episodes, spec.record_episodes)
    callbacks: list[Any] = [recorder]
    keeper = None
    if spec.validation:
        env_kwargs = validation_env_kwargs(spec.env_kwargs)  # the training task as evaluated
        keeper = KeepBestOnValidation(
            str(spec.env_id),
            every=int(spec.validation["every"]),
            n_episodes=int(spec.validation["episodes"]),
            env_kwargs=env_kwargs,
            drawn_episodes=int(spec.validation.get("drawn_episodes", 0)),
            rank_by=str(spec.validation.get("rank_by", "return")),
            route_bound=spec.validation.get("route_bound"),
            also_rank_by=also_rank_by(spec),
        )
        callbacks.append(keeper)
    start = time.time()
    model.learn(total_timesteps=MAX_STEPS, callback=CallbackList(callbacks), progress_bar=False)
    train_s = time.time() - start
    if keeper is not None:  # the kept weights are back in the model (restore_at_end)
        (tmp / "validation.json").write_text(json.dumps(keeper.to_dict()))
    if keeper is not None and keeper.also_rank_by:  # each further ranking's policy, then back
        for ranking in keeper.also_rank_by:
            if keeper.restore(ranking):
                model.save(tmp / kept_model_name(ranking))
        keeper.restore()
    model.save(tmp / "model.zip")
    (tmp / "episodes.json").write_text(json.dumps(recorder.to_dict()))
    np.savez_compressed(
        tmp / "trajectories.npz", **{f"ep_{i}": t for i, t in recorder.trajectories.items()}
    )
    successes = recorder.successes
    info = {
        "train_s": train_s,
        "timesteps": int(model.num_timesteps),
        "episodes": len(recorder.returns),
        "train_successes": int(sum(successes)),
        "first_success": successes.index(True) if True in successes else None,
    }
    if keeper is not None:
        info["kept_episode"] = keeper.best_episode
    return model, info


#: A retried source column trains from seed ``seed + RETRY_SEED_STEP * attempt``: apart from
#: every study's training seeds (0.., and k * set + j for candidates).
RETRY_SEED_STEP = 1000


def train_with_retries(
    spec: RunSpec, tmp: Path, deps: dict[str, Path]
) -> tuple[Any, dict[str, Any]]:
    """:func:`train`, and for a source column with ``spec.validation["retries"]`` = r > 0, train
    it again from seed ``spec.seed + RETRY_SEED_STEP * i`` (i = 1..r) while no validation check
    of the last attempt passed a single episode. A column can collapse early to a policy that
    turns away within seconds, every episode ending by the heading rule, and never reach its
    target; it then gives every learner that reads it a prior that does not do its task. A
    column that passed a check is kept as it is, so only failed draws change. The run
    keeps the attempt of the best kept check (the first of equals); the manifest lists every
    attempt's seed and kept success."""
    retries = int(spec.validation.get("retries", 0)) if spec.validation else 0
    if not retries:
        return train(spec, tmp, deps)
    from sb3_pnn.common.callbacks import validation_rank

    attempts: list[dict[str, Any]] = []
    for attempt in range(retries + 1):
        seed = spec.seed + RETRY_SEED_STEP * attempt
        folder = tmp / f"attempt-{attempt}"
        folder.mkdir()
        model, info = train(dataclasses.replace(spec, seed=seed), folder, deps)
        kept = kept_check(folder)
        attempts.append(dict(folder=folder, model=model, info=info, kept=kept, seed=seed))
        if kept and kept[0]["success_rate"] > 0:
            break
    unranked = (-math.inf,)
    best = max(  # max keeps the first of equals
        attempts, key=lambda a: validation_rank(*a["kept"]) if a["kept"] else unranked
    )
    for path in best["folder"].iterdir():  # the kept attempt's records become the run's
        shutil.move(path, tmp / path.name)
    for a in attempts:
        shutil.rmtree(a["folder"])
    tried = [
        {"seed": a["seed"], "kept_success": a["kept"][0]["success_rate"] if a["kept"] else None}
        for a in attempts
    ]
    return best["model"], dict(best["info"], attempts=tried)


def evaluate(spec: RunSpec, policy: Any, tmp: Path) -> dict[str, Any]:
    """Evaluate ``policy`` (a model or a baseline name) on ``spec.eval_tasks``; save eval.json."""
    from sb3_pnn.evaluation import evaluate_policy_on_task

    results: dict[str, Any] = {}
    start = time.time()
    for label, env_id, env_kwargs in spec.eval_tasks:
        result = evaluate_policy_on_task(
            policy,
            env_id,
            n_episodes=spec.eval_episodes,
            seed=EVAL_SEED,
            env_kwargs=dict(env_kwargs) or None,
            record_trajectories=spec.trace_episodes,
            policy_name=AGENT_LABELS.get(spec.agent, spec.agent),
        )
        results[label] = result.to_dict()
    (tmp / "eval.json").write_text(json.dumps(results))
    return {
        "eval_s": time.time() - start,
        "success_rates": {label: r["success_rate"] for label, r in results.items()},
    }


def kept_check(run: Path) -> tuple[dict[str, Any], str] | None:
    """The validation check whose policy ``run`` kept (the ``best_episode`` that
    :class:`sb3_pnn.common.callbacks.KeepBestOnValidation` recorded) and the ranking it was kept
    by, so the ranking rule lives in one place; None when its budget ended before the first
    check (it kept its last policy)."""
    path = run / "validation.json"
    if not path.is_file():
        raise ValueError(
            f"{str(run)!r} has no validation.json: a source column can only be selected among "
            "candidates that validated (keep_best on)"
        )
    record = json.loads(path.read_text())
    kept = [c for c in record["history"] if c["episode"] == record.get("best_episode")]
    if not kept:
        return None
    return kept[0], str(record.get("rank_by", "return"))


def _ranked_figures(check: dict[str, Any], rank_by: str) -> dict[str, Any]:
    """What a candidate was ranked by: its kept check's success (and drawn success when it
    ran them) and the entry its ranking reads, under that entry's own name."""
    from sb3_pnn.common.callbacks import ranked_entry

    names = ("success_rate", "drawn_success_rate", ranked_entry(rank_by))
    return {name: check[name] for name in names if name in check}


def select(spec: RunSpec, tmp: Path, deps: dict[str, Path]) -> dict[str, Any]:
    """Keep the candidate source column that did best on validation episodes of its own task
    (success rate, then the ranking its checks were kept by; a tie goes to the first candidate,
    and so does the choice when no candidate's budget reached a check); copy its model and
    records into ``tmp``."""
    from sb3_pnn.common.callbacks import validation_rank

    kept = {dep: kept_check(deps[dep]) for dep in spec.deps}
    unranked = (-math.inf, -math.inf)
    # max keeps the first of equals
    chosen = max(spec.deps, key=lambda dep: validation_rank(*kept[dep]) if kept[dep] else unranked)
    for name in ("model.zip", "validation.json", "eval.json"):
        shutil.copyfile(deps[chosen] / name, tmp / name)
    table = {dep: None if k is None else _ranked_figures(*k) for dep, k in kept.items()}
    (tmp / "selection.json").write_text(json.dumps({"candidates": table, "chosen": chosen}))
    return {"chosen": chosen}


def run_work(spec: RunSpec, tmp: Path, deps: dict[str, Path]) -> dict[str, Any]:
    """Train and/or evaluate one run (see the module docstring); returns manifest fields."""
    info: dict[str, Any] = {"kind": spec.kind, "agent": spec.agent}
    if spec.kind == "select":
        info.update(select(spec, tmp, deps))
        return info
    if spec.kind == "baseline":
        info.update(evaluate(spec, spec.agent, tmp))
        return info
    model, train_info = train_with_retries(spec, tmp, deps)
    info.update(train_info)
    if spec.eval_tasks:
        info.update(evaluate(spec, played(spec.play, model), tmp))
    return info


def played(play: dict[str, Any], model: Any) -> Any:
    """The trained ``model`` as the study evaluates it (a run spec's ``play``): through
    :class:`sb3_pnn.progressive.SwitchMemory` where a switch memory is named, then through
    :class:`sb3_pnn.evaluation.NoReversal` where ``no_reversal`` is; else itself."""
    from sb3_pnn.evaluation.played import played_through

    return played_through(model, play.get("switch_memory"), bool(play.get("no_reversal")))
