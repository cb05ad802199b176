"""rl_zoo3's ExperimentManager, extended for this package (no fork: a subclass).

What it adds to the zoo:

* the config is read and checked by :mod:`sb3_pnn.zoo.configs` (clear errors for a malformed
  entry), ``priors:`` are resolved to checkpoint paths in ``policy_kwargs["priors"]``
  (:mod:`sb3_pnn.zoo.priors`), and ``policy_kwargs`` from ``-params`` or an Optuna trial are
  merged key by key over the config's instead of replacing it;
* SPNN gets the env's ``sonar_range`` in ``policy_kwargs`` unless the entry sets it, so that the
  gate's d (eq. 15) is in the env's metres;
* ``--trial-id 0`` loads trial 0 (the zoo treats 0 as "not given");
* ``learn(tb_log_name=...)`` per algo, and :class:`RovMetricsCallback` for TensorBoard;
* ``-optimize``: our search space (:mod:`sb3_pnn.zoo.tuning`) registered as the algo's sampler,
  a journal-file study by default, RDB storage with heartbeat, and a report of the best switch.
"""

from __future__ import annotations

import copy
import json
import os
import sys
import time
import warnings
from collections import OrderedDict
from dataclasses import dataclass, field
from pathlib import Path
from pprint import pprint
from typing import Any

import gymnasium as gym
import optuna
import rl_zoo3.exp_manager as zoo_exp_manager
from optuna.study import MaxTrialsCallback
from optuna.trial import TrialState
from rl_zoo3.exp_manager import ExperimentManager
from rl_zoo3.hyperparams_opt import HYPERPARAMS_CONVERTER, HYPERPARAMS_SAMPLER
from stable_baselines3.common.base_class import BaseAlgorithm

from sb3_pnn.common.atomic import write_text_atomic
from sb3_pnn.zoo.callbacks import RovMetricsCallback
from sb3_pnn.zoo.configs import load_config_file, select_entry, validate_entry
from sb3_pnn.zoo.errors import ZooUsageError
from sb3_pnn.zoo.priors import resolve_priors
from sb3_pnn.zoo.registry import OUR_ALGOS, TB_LOG_NAMES
from sb3_pnn.zoo.tuning import (
    PAPER_VALUES,
    SPNN_PARAMETERS,
    TuningSpace,
    build_space,
    convert_params,
    create_storage,
    default_journal_path,
    hide_password,
    make_converter,
    make_sampler,
)


@dataclass
class ZooOptions:
    """Command-line options of ours (beside the zoo's own flags)."""

    priors: list[str] | None = None
    tune: dict[str, Any] = field(default_factory=dict)
    tune_sac: bool = False
    heartbeat_interval: int = 60
    grace_period: int | None = None


def policy_kwargs_dict(value: Any, where: str) -> dict[str, Any]:
    """A ``policy_kwargs`` value as a dict (the zoo also accepts a Python dict expression)."""
    if value is None:
        return {}
    if isinstance(value, dict):
        return dict(value)
    if isinstance(value, str):
        try:
            # Same namespace as the zoo's own eval of this string (exp_manager's globals).
            result = eval(value, vars(zoo_exp_manager))  # noqa: S307 - the user's own config
        except Exception as error:
            message = f"{where}: policy_kwargs {value!r} does not evaluate: {error}"
            raise ZooUsageError(message) from None
        if isinstance(result, dict):
            return result
    raise ZooUsageError(f"{where}: policy_kwargs must be a mapping, got {value!r}")


class PNNExperimentManager(ExperimentManager):
    """See the module docstring. ``options`` is set on a subclass by the ``train`` command."""

    options: ZooOptions = ZooOptions()

    def __init__(self, args: Any, algo: str, env_id: str, *rest: Any, **kwargs: Any) -> None:
        super().__init__(args, algo, env_id, *rest, **kwargs)
        self.env_id = env_id
        self.tuning_spec: dict[str, Any] = {}
        self.tuning_space: TuningSpace | None = None
        if self.optimize_hyperparameters or self.trial_id is not None:
            if self.storage is None:
                self.storage = default_journal_path(self.log_folder, algo, str(self.env_name))
            if self.study_name is None:
                self.study_name = f"{algo}_{self.env_name}"

    # ------------------------------------------------------------------ hyperparameters
    def read_hyperparameters(self) -> tuple[dict[str, Any], dict[str, Any]]:
        print(f"Loading hyperparameters from: {self.config}")
        algo_class = zoo_exp_manager.ALGOS[self.algo]
        config = load_config_file(self.config)
        name, entry = select_entry(config, self.env_name.gym_id, self.config)
        where = f"{self.config} [{name}]"
        hyperparams = copy.deepcopy(
            validate_entry(
                entry, name=name, path=self.config, algo=self.algo, algo_class=algo_class
            )
        )
        policy_kwargs = policy_kwargs_dict(hyperparams.get("policy_kwargs"), where)
        has_policy_kwargs = "policy_kwargs" in hyperparams

        if self.trial_id is not None and not self.optimize_hyperparameters:
            print(f"Loading trial {self.trial_id} of study {self.study_name!r}")
            trial_params = self._load_trial_params(self.trial_id)
            study_hyperparams = convert_params(trial_params)
            policy_kwargs.update(study_hyperparams.pop("policy_kwargs", {}))
            has_policy_kwargs = has_policy_kwargs or bool(policy_kwargs)
            hyperparams.update(study_hyperparams)
        if self.custom_hyperparams:
            custom = dict(self.custom_hyperparams)
            if "policy_kwargs" in custom:
                policy_kwargs.update(policy_kwargs_dict(custom.pop("policy_kwargs"), "-params"))
                has_policy_kwargs = True
            hyperparams.update(custom)
        if self.custom_hyperparams or self.trial_id is not None:
            source = f"{self.config} with -params"
            validate_entry(
                hyperparams, name=name, path=source, algo=self.algo, algo_class=algo_class
            )
        if "env_kwargs" in hyperparams and self.env_kwargs:
            # --env-kwargs is merged key by key over the entry's (rl_zoo3 would replace it,
            # dropping the set-up's control period, observation and reward settings).
            hyperparams["env_kwargs"] = {**(hyperparams["env_kwargs"] or {}), **self.env_kwargs}
            if self._eval_env_kwargs_args is None:
                self.eval_env_kwargs = hyperparams["env_kwargs"]
            # args.yml records the merged set: rl_zoo3's enjoy lets its env_kwargs replace
            # the config's, which would drop the entry's keys.
            self.args.env_kwargs = dict(hyperparams["env_kwargs"])

        self.tuning_spec = dict(hyperparams.pop("tuning", None) or {})
        if self.optimize_hyperparameters and self.algo in OUR_ALGOS:
            # Checked before the priors, so a bad bound is reported first.
            self.tuning_space = self._build_tuning_space(policy_kwargs, hyperparams)
        priors = hyperparams.pop("priors", None)
        if priors is None:
            priors = policy_kwargs.get("priors")
        if priors is not None or self.options.priors:
            policy_kwargs["priors"] = resolve_priors(
                list(priors or []),
                algo=self.algo,
                env_id=self.env_id,
                log_folder=self.log_folder,
                where=where,
                override=self.options.priors,
            )
            has_policy_kwargs = True
        elif self.algo in ("pnn", "spnn", "sac_multi"):
            raise ZooUsageError(f"{where}: {self.algo} needs 'priors:' (or --priors PATH.zip)")

        if self.algo == "spnn" and "sonar_range" not in policy_kwargs:
            sonar_range = self._env_sonar_range(hyperparams.get("env_kwargs"))
            if sonar_range is not None:
                policy_kwargs["sonar_range"] = sonar_range
        if has_policy_kwargs:
            hyperparams["policy_kwargs"] = policy_kwargs

        saved_hyperparams = OrderedDict((key, hyperparams[key]) for key in sorted(hyperparams))
        print("Default hyperparameters for environment (ones being tuned will be overridden):")
        pprint(saved_hyperparams)
        return hyperparams, saved_hyperparams

    def _preprocess_hyperparams(self, hyperparams: dict[str, Any]) -> Any:
        """The zoo's, then the evaluation env gets the entry's ``env_kwargs`` too.

        rl_zoo3 binds ``eval_env_kwargs`` to the command line's ``--env-kwargs`` (or ``{}``)
        before it reads the config, so without ``--env-kwargs`` its EvalCallback and every
        ``-optimize`` trial would evaluate on the env's defaults: another observation space
        than the one trained on (``KeyError: 'motion'`` at the first evaluation).
        """
        result = super()._preprocess_hyperparams(hyperparams)
        if self._eval_env_kwargs_args is None:
            self.eval_env_kwargs = dict(self.env_kwargs)
        return result

    def setup_experiment(self) -> tuple[BaseAlgorithm, dict[str, Any]] | None:
        """The zoo's setup; a bad value that the env or the learner refuses becomes one line."""
        try:
            return super().setup_experiment()
        except (ValueError, TypeError) as error:
            if isinstance(error, ZooUsageError):
                raise
            raise ZooUsageError(
                f"{self.algo} on {self.env_id} with {self.config}: {type(error).__name__}: {error}"
            ) from error

    def _env_sonar_range(self, env_kwargs: dict[str, Any] | None) -> float | None:
        kwargs = dict(env_kwargs or {})
        kwargs.update(self.env_kwargs or {})
        env = gym.make(self.env_name.gym_id, **kwargs)
        try:
            value = getattr(env.unwrapped, "sonar_range", None)
        finally:
            env.close()
        return None if value is None else float(value)

    def _open_storage(self) -> optuna.storages.BaseStorage:
        assert self.storage is not None
        return create_storage(
            self.storage,
            heartbeat_interval=self.options.heartbeat_interval,
            grace_period=self.options.grace_period,
        )

    def _load_trial_params(self, trial_id: int) -> dict[str, Any]:
        try:
            study = optuna.load_study(storage=self._open_storage(), study_name=self.study_name)
        except KeyError:
            raise ZooUsageError(
                f"no study {self.study_name!r} in {hide_password(str(self.storage))}"
            ) from None
        trials = study.get_trials(deepcopy=False)
        if not 0 <= trial_id < len(trials):
            raise ZooUsageError(
                f"--trial-id {trial_id}: study {self.study_name!r} has trials 0..{len(trials) - 1}"
            )
        return dict(trials[trial_id].params)

    # ------------------------------------------------------------------ training
    def create_callbacks(self) -> None:
        super().create_callbacks()
        if not self.optimize_hyperparameters:
            self.callbacks.append(RovMetricsCallback())

    def learn(self, model: BaseAlgorithm) -> None:
        """The zoo's learn, with ``tb_log_name`` set per algo (``SPNN_1``, ``PNN_1`` ...)."""
        kwargs: dict[str, Any] = {}
        if self.log_interval > -1:
            kwargs = {"log_interval": self.log_interval}
        elif self.log_interval < -1:
            kwargs = {"log_interval": None}
        if self.callbacks:
            kwargs["callback"] = self.callbacks
        if self.algo in TB_LOG_NAMES:
            kwargs["tb_log_name"] = TB_LOG_NAMES[self.algo]
        try:
            model.learn(self.n_timesteps, **kwargs)
        except KeyboardInterrupt:
            pass
        finally:
            if self.callbacks:
                self.callbacks[0].on_training_end()
            try:
                assert model.env is not None
                model.env.close()
            except EOFError:
                pass

    # ------------------------------------------------------------------ tuning
    def _tuning_space_spec(self) -> dict[str, Any]:
        spec = dict(self.tuning_spec)
        spec.update(self.options.tune)
        if self.options.tune_sac:
            spec["sac"] = True
        return spec

    def _build_tuning_space(
        self, policy_kwargs: dict[str, Any], hyperparams: dict[str, Any]
    ) -> TuningSpace:
        sonar_range = policy_kwargs.get("sonar_range")
        if sonar_range is None:
            sonar_range = self._env_sonar_range(hyperparams.get("env_kwargs")) or 25.0
        return build_space(
            self.algo,
            self._tuning_space_spec(),
            sonar_range=float(sonar_range),
            gate=policy_kwargs.get("gate", "hard"),
            origin=f"tuning of {self.algo} on {self.env_id}",
        )

    def hyperparameters_optimization(self) -> None:
        """Optuna search of :mod:`sb3_pnn.zoo.tuning`'s space over the zoo's objective/pruning."""
        base_policy_kwargs = self._hyperparams.get("policy_kwargs")
        space = self.tuning_space
        if self.algo in OUR_ALGOS and space is not None:
            HYPERPARAMS_SAMPLER[self.algo] = make_sampler(space, base_policy_kwargs)
            HYPERPARAMS_CONVERTER[self.algo] = make_converter(base_policy_kwargs)
            print(f"Tuning {', '.join(space.names())}; fixed: {space.fixed or 'none'}")
        if self.verbose > 0:
            print("Optimizing hyperparameters")
        if self.tensorboard_log is not None:
            warnings.warn(
                "Tensorboard log is deactivated when running hyperparameter optimization",
                stacklevel=2,
            )
            self.tensorboard_log = None

        storage = self._open_storage()
        print(f"Study {self.study_name!r} in {hide_password(str(self.storage))}")
        study = optuna.create_study(
            sampler=self._create_sampler(self.sampler),
            pruner=self._create_pruner(self.pruner),
            storage=storage,
            study_name=self.study_name,
            load_if_exists=True,
            direction="maximize",
        )
        if "command" not in study.user_attrs:
            study.set_user_attr("command", " ".join(sys.orig_argv))
        counted = [TrialState.COMPLETE, TrialState.RUNNING, TrialState.PRUNED]
        try:
            if self.max_total_trials is not None:
                if len(study.get_trials(states=counted)) < self.max_total_trials:
                    study.optimize(
                        self.objective,
                        n_jobs=self.n_jobs,
                        callbacks=[MaxTrialsCallback(self.max_total_trials, states=counted)],
                        gc_after_trial=True,
                    )
            else:
                study.optimize(
                    self.objective, n_jobs=self.n_jobs, n_trials=self.n_trials, gc_after_trial=True
                )
        except KeyboardInterrupt:
            pass
        self._report(study)

    def _report(self, study: optuna.Study) -> None:
        trials = study.get_trials(deepcopy=False)
        states = {state.name: sum(t.state == state for t in trials) for state in TrialState}
        print(f"Number of finished trials: {len(trials)} ({states})")
        completed = [t for t in trials if t.state == TrialState.COMPLETE]
        if not completed:
            print("No trial completed: no best parameters to report")
            return
        best = study.best_trial
        print(f"Best trial: #{best.number}, value {best.value}")
        print("Params:")
        for key, value in best.params.items():
            print(f"    {key}: {value}")
        switch = {k: v for k, v in best.params.items() if k in SPNN_PARAMETERS}
        if switch:
            found = ", ".join(f"{k} = {v:.4g}" for k, v in switch.items())
            paper = ", ".join(f"{k} = {v:g}" for k, v in PAPER_VALUES.items())
            print(f"Best switch: {found} (paper: {paper}, d_th in metres)")
        report_name = (
            f"report_{self.env_name}_{self.n_trials}-trials-{self.n_timesteps}"
            f"-{self.sampler}-{self.pruner}_{int(time.time())}"
        )
        log_path = Path(self.log_folder) / self.algo / report_name
        os.makedirs(log_path.parent, exist_ok=True)
        report = {
            "study_name": self.study_name,
            "storage": hide_password(str(self.storage)),
            "env": self.env_id,
            "algo": self.algo,
            "n_trials": len(trials),
            "states": states,
            "best_trial": best.number,
            "best_value": best.value,
            "best_params": best.params,
            "paper_values": PAPER_VALUES,
        }
        write_text_atomic(f"{log_path}.json", json.dumps(report, indent=2, default=str))
        study.trials_dataframe().to_csv(f"{log_path}.csv")
        print(f"Writing report to {log_path}.json and .csv")
        if not self.no_optim_plots:
            try:
                from optuna.visualization import plot_optimization_history, plot_param_importances

                plot_optimization_history(study).write_html(f"{log_path}_history.html")
                plot_param_importances(study).write_html(f"{log_path}_importances.html")
            except (ValueError, ImportError, RuntimeError):
                pass
