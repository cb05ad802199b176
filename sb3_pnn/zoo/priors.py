"""Resolving the prior checkpoints that PNN, SPNN and SAC-Multi configurations name.

A configuration entry lists its priors under ``priors:`` in the order the policy expects them
(SPNN: path following, then obstacle avoidance; PNN and SAC-Multi: path following). Each item is
either

* a mapping ``{algo: dsac, env: rov_envs/PathFollowingStraight-v0}``, optionally with
  ``exp_id: N`` (default 0 = the latest run that holds the model) and ``model: final | best``: a
  model trained with ``python -m sb3_pnn.train``, looked up in the zoo's layout under the current
  ``--log-folder`` (``<log-folder>/<algo>/<env>_<N>/<env>.zip``, or ``best_model.zip``); or
* a path to an SB3 ``.zip`` (``~`` and ``$VARS`` expanded, relative paths from the current
  directory).

``python -m sb3_pnn.train ... --priors A.zip [B.zip]`` replaces the configured list with explicit
paths (same count and order). A prior that cannot be found is an error naming the file and the
``train`` command that makes it.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from huggingface_sb3 import EnvironmentName

from sb3_pnn.zoo.errors import ZooUsageError
from sb3_pnn.zoo.runs import latest_run_with, runs_summary

# What each prior is for, per algo, in the order the policy takes them (for messages).
PRIOR_ROLES: dict[str, tuple[str, ...]] = {
    "pnn": ("path-following", "obstacle-avoidance"),  # the second where a config names it
    "spnn": ("path-following", "obstacle-avoidance"),
    "sac_multi": ("path-following",),
}
MODEL_KINDS = ("final", "best")


@dataclass(frozen=True)
class PriorRef:
    """A prior trained with ``train``: ``algo`` on ``env`` (run ``exp_id``, 0 = the latest run
    that holds the model)."""

    algo: str
    env: str
    exp_id: int = 0
    model: str = "final"

    def train_command(self, log_folder: str) -> str:
        return f"python -m sb3_pnn.train --algo {self.algo} --env {self.env} -f {log_folder}"

    def resolve(self, log_folder: str) -> Path:
        """The checkpoint of run ``exp_id``, or of the latest run that holds one (exp_id 0)."""
        env_name = EnvironmentName(self.env)
        algo_folder = os.path.join(log_folder, self.algo)
        file_name = f"{env_name}.zip" if self.model == "final" else "best_model.zip"

        def has_model(run: Path) -> bool:
            return (run / file_name).is_file()

        exp_id = self.exp_id or latest_run_with(algo_folder, env_name, has_model)
        runs = runs_summary(algo_folder, env_name, has_model)
        if exp_id <= 0:
            expected = os.path.join(algo_folder, f"{env_name}_<N>", file_name)
            raise FileNotFoundError(
                f"no run of {self.algo} on {self.env} holds a model (expected {expected}; {runs})"
            )
        path = Path(algo_folder) / f"{env_name}_{exp_id}" / file_name
        if not path.is_file():
            raise FileNotFoundError(f"{path} does not exist ({runs}; set exp_id: N)")
        return path


def parse_prior(item: Any, where: str) -> PriorRef | Path:
    """One ``priors:`` item as a :class:`PriorRef` or a path."""
    if isinstance(item, str):
        return Path(os.path.expandvars(os.path.expanduser(item)))
    if isinstance(item, dict):
        unknown = set(item) - {"algo", "env", "exp_id", "model"}
        if unknown or "algo" not in item or "env" not in item:
            raise ZooUsageError(
                f"{where}: a prior must be a path or a mapping with keys algo, env "
                f"(optional exp_id, model), got {item!r}"
            )
        exp_id = item.get("exp_id", 0)
        if isinstance(exp_id, bool) or not isinstance(exp_id, int) or exp_id < 0:
            raise ZooUsageError(f"{where}: prior exp_id must be an integer >= 0, got {exp_id!r}")
        model = item.get("model", "final")
        if model not in MODEL_KINDS:
            raise ZooUsageError(f"{where}: prior model must be one of {MODEL_KINDS}, got {model!r}")
        return PriorRef(str(item["algo"]), str(item["env"]), exp_id, model)
    raise ZooUsageError(f"{where}: a prior must be a path or a mapping, got {item!r}")


def resolve_priors(
    items: list[Any],
    *,
    algo: str,
    env_id: str,
    log_folder: str,
    where: str,
    override: list[str] | None = None,
) -> list[str]:
    """Paths of the prior checkpoints (as strings), checking that every file exists."""
    roles = PRIOR_ROLES.get(algo, ())
    if override:
        if items and len(override) != len(items):
            raise ZooUsageError(
                f"--priors got {len(override)} path(s) but {algo} on {env_id} takes "
                f"{len(items)} ({', '.join(roles[: len(items)]) or 'see the config'}), in that "
                "order"
            )
        items = list(override)
    paths: list[str] = []
    for index, item in enumerate(items):
        role = roles[index] if index < len(roles) else f"#{index + 1}"
        ref = parse_prior(item, where)
        if isinstance(ref, PriorRef):
            try:
                path = ref.resolve(log_folder)
            except FileNotFoundError as error:
                raise ZooUsageError(
                    f"missing {role} prior for {algo} on {env_id}: {error}; "
                    f"make it with: {ref.train_command(log_folder)} "
                    f"(or pass the checkpoints with --priors, in the order "
                    f"{', '.join(roles[: len(items)]) or 'of the config'})"
                ) from None
        else:
            path = ref
            if not path.is_file():
                raise ZooUsageError(
                    f"missing {role} prior for {algo} on {env_id}: {path} does not exist; "
                    f"train it with: python -m sb3_pnn.train --algo dsac --env <prior task> "
                    f"and pass <log-folder>/dsac/<env>_<N>/<env>.zip"
                )
            if path.suffix != ".zip":
                raise ZooUsageError(
                    f"{role} prior for {algo} on {env_id}: {path} is not an SB3 .zip checkpoint"
                )
        check_prior_role(path, role, algo, env_id)
        paths.append(str(path))
    return paths


def check_prior_role(path: Path, role: str, algo: str, env_id: str) -> None:
    """Refuse a prior that cannot play its role: a path-following column must not observe the
    sonar (an obstacle-avoidance column given to PNN or SAC-Multi; SPNN names swapped priors
    itself), and a
    checkpoint that names the task it was trained on must have been trained on the planning
    task's kind of path (a sine-path prior for the straight task, or the other way round)."""
    from rov_envs.sim.tasks import TASKS, task_of_env
    from sb3_pnn.progressive.prior_loading import load_prior, trained_env_id

    try:
        spec = load_prior(path).spec
        trained_id = trained_env_id(path)
    except (ValueError, FileNotFoundError) as error:
        raise ZooUsageError(f"{role} prior for {algo} on {env_id}: {error}") from None
    if role == "path-following" and algo != "spnn" and "sonar" in spec.obs.keys:
        raise ZooUsageError(
            f"{role} prior for {algo} on {env_id}: {path} observes the sonar (an "
            "obstacle-avoidance column); expected a model of a path-following task"
        )
    try:
        target, trained = task_of_env(env_id), task_of_env(trained_id) if trained_id else None
    except ValueError:
        return  # not an rov_envs task: nothing to compare
    if trained is None or role != "path-following" or trained.name not in TASKS:
        return
    if trained.path_kind != target.path_kind:
        raise ZooUsageError(
            f"{role} prior for {algo} on {env_id}: {path} was trained on {trained_id}, whose path "
            f"is not {env_id}'s; expected a model of the same kind of path"
        )
