"""The training set-up's ablation: which departures from the paper make the agents learn.

A cell is one :class:`~sb3_pnn.reproduce.planning.setups.TrainingSetup`. The cells are

* ``paper`` (the paper read literally, :data:`~sb3_pnn.reproduce.planning.setups.PAPER`) and
  ``paper+<factor>=<value>``: one factor changed at a time from it;
* ``ours`` (the study's default, :data:`~sb3_pnn.reproduce.planning.setups.OURS`) and
  ``ours+<factor>=<value>``: one factor put back (or changed) at a time from it, plus
  ``ours+prior_budget=0.5``: half the source columns' episodes;
* on the command line also any composite ``<base>+<factor>=<value>+...`` (:func:`cell_of`), e.g.
  ``ours+updates=step:4+prior_updates=step:1+train_start_noise=off``: the study's own set-up
  (ours with the schedule it runs, ``--set updates=step:4 prior_updates=step:1``) with one
  more factor put back, for rows the catalog's one-factor cells do not cover.

Every cell is trained on each chosen task of :data:`TASKS` (by default :data:`DEFAULT_TASKS`)
with ``--seeds`` seeds: DiscreteSAC on the three source tasks, and SPNN (eq. 15) on
PlanningStraight (and, when asked for, PlanningSine) from that cell's own seed-0
path-following and obstacle-avoidance runs. Each run ends with ``eval_episodes`` evaluation
episodes on its own task under the evaluation library's start noise (seeds apart from the
training seeds). The runs go through the study's executor and store (:mod:`.executor`,
:mod:`.store`): parallel, resumable, one folder per run. :mod:`.ablation_report` writes the table.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from sb3_pnn.reproduce.planning.plan import FULL as STUDY_FULL
from sb3_pnn.reproduce.planning.plan import PRIOR_ENVS, RunSpec, check_budget_and_seeds, prior_run
from sb3_pnn.reproduce.planning.setups import (
    FACTOR_LABELS,
    OURS,
    PAPER,
    TrainingSetup,
    describe_value,
    parse_setup_changes,
    path_of_env,
)

#: Ablation tasks: name -> (environment id, agent, names of the tasks that give its priors).
TASKS: dict[str, tuple[str, str, tuple[str, ...]]] = {
    "pf_straight": (PRIOR_ENVS["pf_straight"], "dsac", ()),
    "pf_sine": (PRIOR_ENVS["pf_sine"], "dsac", ()),
    "oa": (PRIOR_ENVS["oa"], "dsac", ()),
    "planning_straight": ("rov_envs/PlanningStraight-v0", "spnn", ("pf_straight", "oa")),
    "planning_sine": ("rov_envs/PlanningSine-v0", "spnn", ("pf_sine", "oa")),
}
#: The tasks an invocation without ``--tasks`` trains: the issue's four. PlanningSine is asked for
#: by name (``--tasks planning_sine``), e.g. to screen a change on the second planning task.
DEFAULT_TASKS: tuple[str, ...] = ("pf_straight", "pf_sine", "oa", "planning_straight")
TASK_LABELS: dict[str, str] = {
    "pf_straight": "PathFollowingStraight",
    "pf_sine": "PathFollowingSine",
    "oa": "ObstacleAvoidance",
    "planning_straight": "PlanningStraight (SPNN)",
    "planning_sine": "PlanningSine (SPNN)",
}
#: Values tried per factor besides PAPER's and OURS' (the issue's "1 per k steps", Wu's vehicle,
#: a lower target entropy).
EXTRA_VALUES: dict[str, tuple[Any, ...]] = {
    "vehicle": ("wu2018",),
    "updates": ("step:1", "step:4"),
    "target_entropy_ratio": (0.2,),
    "oa_layout": ("scatter",),
    "oa_corridor": (15.0,),
    "spnn_gate": ("soft",),
}
#: Factors with no cell of their own, each with why and where it is measured instead.
_ONLY_PNN = "only PNN reads it and no ablation task trains PNN; measured "
NOT_ABLATED: dict[str, str] = {
    "prior_candidates": "an ablation cell trains one seed-0 column per source task; measured "
    "with the study's own runs, its SPNN on columns chosen among three candidates "
    "(docs/ablation/README.md, section 10)",
    "planning_layout": "beyond the paper's protocol (the agents train on other obstacles than "
    "the paper's tasks have): its runs are reported apart, as extra rows of Figure 20 "
    "(docs/results.md)",
    "spnn_d_th_sine": "an ablation cell's SPNN trains on one path at a time (spnn_d_th's cell); "
    "measured with the study's own SPNN runs (docs/ablation/README.md, section 15)",
    "spnn_gate_sine": "an ablation cell's SPNN trains on one path at a time (spnn_gate's cell); "
    "measured with the study's own SPNN runs (docs/ablation/README.md, section 11)",
    "spnn_gate_temperature": "read only with spnn_gate=soft, whose cell uses the factor's "
    "default (2 m); measured with the study's own SPNN runs (docs/ablation/README.md, "
    "section 11)",
    "spnn_d_th": "the paper's and ours are equal (12.5 m); 8 m was measured by retraining the "
    "5-seed study's ten SPNN runs with it (docs/ablation/spnn_d_th)",
    "pnn_lateral_init": _ONLY_PNN
    + "with bench/learning_trace.py --agent pnn (docs/ablation/README.md)",
    "pnn_lateral_init_sine": _ONLY_PNN
    + "with bench/learning_trace.py --agent pnn on PlanningSine, seeds 0-14 "
    "(docs/ablation/README.md)",
    "pnn_critic_priors": _ONLY_PNN
    + "by retraining the 5-seed study's PNN runs with it off (docs/ablation/pnn_critic_priors)",
    "pnn_start_as_prior": _ONLY_PNN
    + "by retraining the 5-seed study's PNN runs with it on (docs/ablation/start_as_prior)",
    "spnn_start_as_prior": "measured beside pnn_start_as_prior by retraining the 5-seed "
    "study's SPNN runs with it on (docs/ablation/start_as_prior), then, on in ours, with "
    "spnn_sigma = spnn_own_weight = 1 (docs/ablation/spnn_weights)",
    "pnn_init_from_prior": _ONLY_PNN
    + "by retraining the 5-seed study's PNN runs with it on (docs/ablation/init_from_prior)",
    "spnn_init_from_prior": "measured beside pnn_init_from_prior by retraining the 5-seed "
    "study's SPNN runs with it on (docs/ablation/init_from_prior)",
    "spnn_sigma": "ours 1 (the paper's 0.5), chosen with spnn_own_weight and "
    "spnn_start_as_prior by retraining the 5-seed study's ten SPNN runs and checked on fresh "
    "seeds (docs/ablation/spnn_weights, docs/ablation/README.md)",
    "spnn_own_weight": "ours 1 (the paper's 0.5); measured with spnn_sigma "
    "(docs/ablation/spnn_weights)",
    "spnn_n_steps": "measured by retraining the 5-seed study's ten SPNN runs with n = 8 "
    "(docs/ablation/README.md, section 12)",
    "pnn_n_steps": _ONLY_PNN
    + "by retraining the 5-seed study's ten PNN runs with n = 8 (docs/ablation/README.md, "
    "section 12)",
    "pnn_prior_kl_clearance": _ONLY_PNN
    + "beside pnn_prior_kl, by retraining the 5-seed study's PNN runs (docs/ablation/README.md, "
    "section 13)",
    "pnn_n_steps_sine": _ONLY_PNN
    + "beside pnn_n_steps, whose value it replaces on the sine path (docs/ablation/README.md, "
    "section 12)",
    "pnn_exploration_epsilon": _ONLY_PNN
    + "by retraining PNN's runs on seeds 0-2 and on fresh seeds 5-9 (docs/ablation/README.md, "
    "section 14)",
    "planning_start_spread": "measured by retraining the study's SPNN and PNN runs on seeds "
    "0-2 at 5x, with a validation measure of generalization (docs/ablation/README.md, "
    "section 15)",
    "learner_target_entropy_ratio": "it differs from target_entropy_ratio (whose cell trains "
    "source columns and learners alike) only by keeping the source columns; measured by "
    "retraining the study's SPNN and PNN runs on seeds 0-2 and on fresh straight-path seeds "
    "(docs/ablation/README.md, section 14)",
    "pnn_exploration_epsilon_sine": _ONLY_PNN
    + "beside pnn_exploration_epsilon, whose value it replaces on the sine path "
    "(docs/ablation/README.md, section 14)",
}
#: Share of the source columns' budget in the ``ours+prior_budget=...`` cell.
REDUCED_PRIOR_SHARE = 0.5


@dataclass(frozen=True)
class AblationBudget:
    """Training episodes per task, and evaluation episodes per run."""

    episodes: dict[str, int]
    eval_episodes: int


#: ``full`` is the study's budget (:data:`~sb3_pnn.reproduce.planning.plan.FULL`): the paper's on
#: the
#: planning tasks (Figure 10: about 300 episodes on the straight line, 400 on the sinusoid), so
#: a cell with the study's set-up trains the study's own runs.
BUDGETS: dict[str, AblationBudget] = {
    "full": AblationBudget(
        {
            **STUDY_FULL.prior_episodes,
            **{
                task: STUDY_FULL.transfer_episodes[path_of_env(env_id)]
                for task, (env_id, _, prior_tasks) in TASKS.items()
                if prior_tasks
            },
        },
        STUDY_FULL.eval_episodes,
    ),
    "quick": AblationBudget(dict.fromkeys(TASKS, 20), 10),
    "tiny": AblationBudget(dict.fromkeys(TASKS, 2), 2),
}


@dataclass(frozen=True)
class AblationCell:
    """One set-up to train, and the share of the budget its source columns get."""

    name: str
    setup: TrainingSetup
    prior_share: float = 1.0

    def describe(self) -> str:
        """The cell in words: its base set-up and what it changes there."""
        base_name = "paper" if self.name.startswith("paper") else "ours"
        base = PAPER if base_name == "paper" else OURS
        diff = self.setup.differences(base)
        text = ", ".join(f"{FACTOR_LABELS[k]} {describe_value(k, v)}" for k, v in diff.items())
        if self.prior_share != 1.0:
            text = f"priors trained for {self.prior_share:g} of their budget"
        return f"{base_name} with {text}" if text else f"{base_name} (see the set-up table)"


def _token(name: str, value: Any) -> str:
    """A factor value as a run-id-safe word."""
    if name == "net_arch":
        return "x".join(str(w) for w in value)
    if isinstance(value, bool):
        return "on" if value else "off"
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def _factor_values(name: str) -> list[Any]:
    values: list[Any] = []
    for value in (getattr(PAPER, name), getattr(OURS, name), *EXTRA_VALUES.get(name, ())):
        if value not in values:
            values.append(value)
    return values


def all_cells() -> list[AblationCell]:
    """Every cell, in report order (see the module docstring)."""
    cells = [AblationCell("paper", PAPER)]
    names = [name for name in PAPER.to_dict() if name not in NOT_ABLATED]
    for base_name, base in (("paper", PAPER), ("ours", OURS)):
        if base_name == "ours":
            cells.append(AblationCell("ours", OURS))
        for name in names:
            for value in _factor_values(name):
                if value != getattr(base, name):
                    label = f"{base_name}+{name}={_token(name, value)}"
                    cells.append(AblationCell(label, base.with_(**{name: value})))
    cells.append(AblationCell(f"ours+prior_budget={REDUCED_PRIOR_SHARE:g}", OURS, 0.5))
    return cells


CELLS: dict[str, AblationCell] = {cell.name: cell for cell in all_cells()}
BASES: dict[str, TrainingSetup] = {"paper": PAPER, "ours": OURS}


def _factor_value(name: str, text: str) -> Any:
    """A factor value written as in a cell name: the catalog's words (``on`` / ``off``,
    ``64x64``) or a ``--set`` value (``false``, ``[64,64]``, ``step:4``)."""
    default = getattr(PAPER, name, None)
    if isinstance(default, tuple) and re.fullmatch(r"\d+(x\d+)*", text):
        return tuple(int(w) for w in text.split("x"))
    return parse_setup_changes([f"{name}={text}"])[name]


def cell_of(name: str) -> AblationCell:
    """The cell called ``name``: one of :data:`CELLS`, or a composite
    ``<base>+<factor>=<value>+...`` (base ``paper`` or ``ours``; each factor changed in turn).
    ValueError naming the bad part and what was expected otherwise."""
    if name in CELLS:
        return CELLS[name]
    base_name, *items = str(name).split("+")
    expected = (
        "a cell of the catalog (--list) or <base>+<factor>=<value>+... with base one of "
        f"{list(BASES)}"
    )
    if base_name not in BASES or not items:
        raise ValueError(f"cell {name!r} is unknown; expected {expected}")
    changes: dict[str, Any] = {}
    for item in items:
        factor, sep, text = item.partition("=")
        if factor == "prior_budget":
            raise ValueError(
                f"cell {name!r}: prior_budget is only the catalog's "
                f"ours+prior_budget={REDUCED_PRIOR_SHARE:g} cell, not part of a composite"
            )
        if not sep or factor in changes:
            raise ValueError(f"cell {name!r}: {item!r} is not allowed; expected {expected}")
        try:
            changes[factor] = _factor_value(factor, text)
        except ValueError as error:
            raise ValueError(f"cell {name!r}: {error}") from None
    try:
        setup = BASES[base_name].with_(**changes)
    except (TypeError, ValueError) as error:
        raise ValueError(f"cell {name!r}: {error}") from None
    return AblationCell(str(name), setup)


@dataclass(frozen=True)
class AblationConfig:
    """What ``python -m sb3_pnn.reproduce --ablation`` was asked for."""

    budget_name: str = "full"
    seeds: int = 3
    cells: tuple[str, ...] = tuple(CELLS)
    tasks: tuple[str, ...] = DEFAULT_TASKS

    def __post_init__(self) -> None:
        check_budget_and_seeds(self.budget_name, BUDGETS, self.seeds)
        for kind, given, known in (("cell", self.cells, CELLS), ("task", self.tasks, TASKS)):
            if not given:
                raise ValueError(f"no {kind} chosen: expected some of {list(known)}")
            for name in given:
                if kind == "cell":
                    cell_of(name)  # raises naming the bad part
                elif name not in known:
                    raise ValueError(f"{kind} {name!r} is unknown; expected one of {list(known)}")

    @property
    def budget(self) -> AblationBudget:
        return BUDGETS[self.budget_name]


def run_id(cell: str, task: str, seed: int) -> str:
    return f"{cell}-{task}-s{seed}"


def reduced_column_id(cell: str, task: str) -> str:
    """The seed-0 source column a reduced-prior-budget cell trains for its planning runs."""
    return run_id(cell, f"{task}_prior", 0)


def build_ablation_plan(config: AblationConfig) -> list[RunSpec]:
    """All runs, each after the runs it needs (a planning run needs its cell's seed-0 priors)."""
    budget = config.budget
    runs: dict[str, RunSpec] = {}

    def add_single(cell: AblationCell, task: str, seed: int, share: float) -> str:
        rid = run_id(cell.name, task, seed) if share == 1.0 else reduced_column_id(cell.name, task)
        if rid not in runs:
            episodes = cell.setup.column_episodes(task, budget.episodes[task])  # oa_budget
            episodes = max(1, round(episodes * share))
            runs[rid] = prior_run(task, seed, episodes, cell.setup, budget.eval_episodes, rid)
        return rid

    for name in config.cells:
        cell = cell_of(name)
        for task in config.tasks:
            env_id, agent, prior_tasks = TASKS[task]
            for seed in range(config.seeds):
                if agent == "dsac":
                    if cell.prior_share == 1.0:  # else the cell is the same set-up as another
                        add_single(cell, task, seed, 1.0)
                    continue
                deps = tuple(add_single(cell, t, 0, cell.prior_share) for t in prior_tasks)
                setup = cell.setup
                rid = run_id(name, task, seed)
                path = path_of_env(env_id)
                runs[rid] = RunSpec(
                    run_id=rid,
                    kind="transfer",
                    agent=agent,
                    path=path,
                    env_id=env_id,
                    seed=seed,
                    episodes=budget.episodes[task],
                    deps=deps,
                    eval_tasks=(
                        (
                            "own",
                            env_id,
                            {**setup.env_kwargs(), **setup.agent_env_kwargs(agent, path)},
                        ),
                    ),
                    eval_episodes=budget.eval_episodes,
                    sac_kwargs=setup.sac_kwargs(agent=agent, path=path),
                    env_kwargs={
                        **setup.train_env_kwargs(env_id),
                        **setup.agent_env_kwargs(agent, path),
                    },
                    validation=setup.validation(learner=True, path=path, agent=agent),
                )
    plan = list(runs.values())
    # priors first (a run's deps always come earlier), then seed by seed
    return sorted(plan, key=lambda spec: (bool(spec.deps), spec.seed))
