"""The study's plan: which runs to make, with which budget (paper section 4.3, Figures 10-20).

A study is a list of :class:`RunSpec` built by :func:`build_plan` from a :class:`StudyConfig`:

* ``prior`` runs train the source columns with DiscreteSAC: path following on the straight line
  and on the sinusoid (the prior of PNN, SAC-Multi and SPNN's first column) and obstacle
  avoidance (SPNN's second column): one set per training seed (``prior_per_seed``, the
  default), so the spread across seeds includes the spread of the columns; without it one set
  (seed 0) is shared by every seed of the transfer runs, and the intervals cover only the
  agents' own training.
* ``transfer`` runs train the four agents of section 4.3 on both planning tasks: SAC-Single
  (DiscreteSAC from scratch), SAC-Multi (DiscreteSAC started from the path-following prior's
  weights), PNN (two columns, eq. 13) and SPNN (three columns, eq. 15). Each ends by evaluating its
  final policy (see :mod:`.evaluate`).
* ``baseline`` runs evaluate the PID and adaptive PID controllers on the same tasks.
* ``select`` runs (with the set-up's ``prior_candidates`` k > 1): each source column is trained
  k times, and a select run keeps the candidate that did best on validation episodes of its own
  task; the transfer runs read that one.

Training budgets are counted in EPISODES, as in the paper's Figures 10, 11 and 14.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field, replace
from typing import Any

from sb3_pnn.reproduce.planning.setups import SETUPS, TrainingSetup

#: The source tasks of the prior columns.
PRIOR_ENVS: dict[str, str] = {
    "pf_straight": "rov_envs/PathFollowingStraight-v0",
    "pf_sine": "rov_envs/PathFollowingSine-v0",
    "oa": "rov_envs/ObstacleAvoidance-v0",
}
#: The two planning tasks the agents are trained on, by path.
PLANNING_ENVS: dict[str, str] = {
    "straight": "rov_envs/PlanningStraight-v0",
    "sine": "rov_envs/PlanningSine-v0",
}
#: The learning agents of section 4.3, in the paper's order, and their priors (by prior name
#: template; ``{path}`` is replaced by ``straight`` / ``sine``).
AGENTS: dict[str, tuple[str, ...]] = {
    "pnn": ("pf_{path}",),
    "spnn": ("pf_{path}", "oa"),
    "sac_single": (),
    "sac_multi": ("pf_{path}",),
}
AGENT_LABELS: dict[str, str] = {
    "pnn": "PNN",
    "spnn": "SPNN",
    "sac_single": "SAC-Single",
    "sac_multi": "SAC-Multi",
    "pid": "PID",
    "adaptive_pid": "Adaptive PID",
}
BASELINES: tuple[str, ...] = ("pid", "adaptive_pid")


def agent_priors(setup: TrainingSetup, agent: str, path: str) -> tuple[str, ...]:
    """The source columns ``agent`` reads on planning path ``path``, in its priors' order:
    :data:`AGENTS`' and, for PNN where ``pnn_avoidance_column`` is on, the avoidance column."""
    names = tuple(t.format(path=path) for t in AGENTS[agent])
    if agent == "pnn" and setup.pnn_reads_avoidance(path):
        names += ("oa",)
    return names


#: Evaluation tasks per path: (label, env id, env kwargs). "path following" keeps the planning
#: task's observation (sonar included) and removes its obstacles, so that the same policy runs.
EVAL_TASKS: dict[str, tuple[tuple[str, str, dict[str, Any]], ...]] = {
    "straight": (
        ("original", "rov_envs/PlanningStraight-v0", {}),
        ("path_following", "rov_envs/PlanningStraight-v0", {"obstacles": []}),
        ("uniform", "rov_envs/PlanningStraightUniform-v0", {}),
        ("dense", "rov_envs/PlanningStraightDense-v0", {}),
    ),
    "sine": (
        ("original", "rov_envs/PlanningSine-v0", {}),
        ("path_following", "rov_envs/PlanningSine-v0", {"obstacles": []}),
        ("dense", "rov_envs/PlanningSineDense-v0", {}),
    ),
}
#: Episodes at which the paper draws training trajectories (Figure 11: straight, 14: sine).
PAPER_TRAJECTORY_EPISODES: dict[str, tuple[int, ...]] = {
    "straight": (0, 80, 150, 230, 250, 300),
    "sine": (0, 80, 140, 180, 220, 400),
}


@dataclass(frozen=True)
class Budget:
    """Training and evaluation sizes of a study.

    Attributes:
        prior_episodes: training episodes of each source column, by prior name.
        transfer_episodes: training episodes of each agent on each planning task, by path.
        eval_episodes: evaluation episodes per (policy, task) (Figure 20's success rates).
        trace_episodes: evaluation episodes whose trajectories are kept for Figures 12-19.
    """

    prior_episodes: dict[str, int]
    transfer_episodes: dict[str, int]
    eval_episodes: int
    trace_episodes: int = 1


#: Full study: 5 seeds, the paper's training budgets on the planning tasks (Figures 10 and 14:
#: about 300 episodes on the straight line, 400 on the sinusoid). The report gives the wall and
#: CPU time of every run (README.md, "Reproduction status", gives the measured total).
FULL = Budget(
    prior_episodes={"pf_straight": 150, "pf_sine": 150, "oa": 300},
    transfer_episodes={"straight": 300, "sine": 400},
    eval_episodes=50,
)
#: ``--quick``: a smoke test of the whole study, meant to take at most five minutes on 2 cores.
QUICK = Budget(
    prior_episodes={"pf_straight": 10, "pf_sine": 10, "oa": 10},
    transfer_episodes={"straight": 10, "sine": 10},
    eval_episodes=10,
)
#: Hidden test budget (``--tiny``): a few seconds per run.
TINY = Budget(
    prior_episodes={"pf_straight": 3, "pf_sine": 3, "oa": 3},
    transfer_episodes={"straight": 3, "sine": 3},
    eval_episodes=2,
)
BUDGETS: dict[str, Budget] = {"full": FULL, "quick": QUICK, "tiny": TINY}


def check_budget_and_seeds(budget_name: str, budgets: dict[str, Any], seeds: Any) -> None:
    """Refuse an unknown budget name or a seed count that is not an integer >= 1."""
    if budget_name not in budgets:
        raise ValueError(f"budget {budget_name!r} is unknown; expected one of {sorted(budgets)}")
    if isinstance(seeds, bool) or not isinstance(seeds, int) or seeds < 1:
        raise ValueError(f"seeds={seeds!r} is not allowed: expected an integer >= 1")


@dataclass(frozen=True)
class StudyConfig:
    """What ``python -m sb3_pnn.reproduce`` was asked for (see :func:`build_plan`)."""

    budget_name: str = "full"
    seeds: int = 5
    episodes: int | None = None  # overrides every transfer budget when given
    eval_episodes: int | None = None
    prior_per_seed: bool = True
    paths: tuple[str, ...] = ("straight", "sine")
    agents: tuple[str, ...] = tuple(AGENTS)
    setup_name: str = "ours"
    # (factor, value) pairs changed from the named set-up (``--set``)
    setup_changes: tuple[tuple[str, Any], ...] = ()

    def __post_init__(self) -> None:
        check_budget_and_seeds(self.budget_name, BUDGETS, self.seeds)
        for name in ("episodes", "eval_episodes"):
            value = getattr(self, name)
            if value is not None and (
                isinstance(value, bool) or not isinstance(value, int) or value < 1
            ):
                raise ValueError(f"{name}={value!r} is not allowed: expected an integer >= 1")
        for path in self.paths:
            if path not in PLANNING_ENVS:
                raise ValueError(
                    f"path {path!r} is unknown; expected one of {sorted(PLANNING_ENVS)}"
                )
        if self.setup_name not in SETUPS:
            raise ValueError(
                f"setup {self.setup_name!r} is unknown; expected one of {sorted(SETUPS)}"
            )
        if not self.agents or len(set(self.agents)) != len(self.agents):
            raise ValueError(
                f"agents={list(self.agents)!r} is not allowed: expected distinct agents, at least "
                f"one of {list(AGENTS)}"
            )
        for agent in self.agents:
            if agent not in AGENTS:
                raise ValueError(f"agent {agent!r} is unknown; expected one of {sorted(AGENTS)}")
        self.setup  # noqa: B018 - a bad change raises here, before any run starts

    @property
    def setup(self) -> TrainingSetup:
        return SETUPS[self.setup_name].with_(**dict(self.setup_changes))

    @property
    def budget(self) -> Budget:
        base = BUDGETS[self.budget_name]
        if self.episodes is not None:
            base = replace(
                base, transfer_episodes={p: self.episodes for p in base.transfer_episodes}
            )
        if self.eval_episodes is not None:
            base = replace(base, eval_episodes=self.eval_episodes)
        return base


@dataclass(frozen=True)
class RunSpec:
    """One independent unit of work: train (and evaluate) one agent with one seed.

    ``deps`` are the run ids whose outputs (prior checkpoints) this run reads; ``config`` holds
    everything that determines the run's result, and its hash guards resumed studies.
    """

    run_id: str
    kind: str  # "prior" | "transfer" | "baseline"
    agent: str
    path: str | None
    env_id: str | None
    seed: int
    episodes: int
    deps: tuple[str, ...] = ()
    record_episodes: tuple[int, ...] = ()
    eval_tasks: tuple[tuple[str, str, dict[str, Any]], ...] = ()
    eval_episodes: int = 0
    trace_episodes: int = 0
    sac_kwargs: dict[str, Any] = field(default_factory=dict)
    env_kwargs: dict[str, Any] = field(default_factory=dict)  # the training environment's
    # {"every": N, "episodes": K[, "drawn_episodes": D][, "rank_by": "route"][, "route_bound": B]}:
    # keep the best policy on validation episodes (empty: the last)
    validation: dict[str, int | str] = field(default_factory=dict)
    # {"switch_memory": H, "no_reversal": True}: evaluate the trained SPNN through SwitchMemory
    # and / or NoReversal (empty: as trained)
    play: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        data = json.loads(json.dumps(asdict(self)))
        for key in ("validation", "play"):
            if not data[key]:
                # left out when off, so that runs made before the field existed keep their hash
                del data[key]
        return data

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> RunSpec:
        data = dict(data)
        for key in ("deps", "record_episodes"):
            data[key] = tuple(data[key])
        data["eval_tasks"] = tuple((a, b, dict(c)) for a, b, c in data["eval_tasks"])
        return cls(**data)

    def config_hash(self) -> str:
        """SHA-256 (16 hex digits) of everything that determines this run's result: the spec
        and the revision of the task definitions (``rov_envs.sim.tasks.TASKS_REVISION``)."""
        from rov_envs.sim.tasks import TASKS_REVISION

        return json_hash({**self.to_dict(), "tasks_revision": TASKS_REVISION})


def json_hash(data: dict[str, Any]) -> str:
    """SHA-256 (16 hex digits) of ``data`` as sorted-key JSON: how run configurations are hashed."""
    return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()[:16]


def prior_run_id(name: str, seed: int) -> str:
    return f"prior-{name}-s{seed}"


def column_run_id(name: str, column_set: int, candidates: int) -> str:
    """The run whose model.zip is source column ``name`` of column set ``column_set`` (0: the
    shared set; seed s with ``prior_per_seed``): the prior run itself, or with k > 1 candidates
    the select run that keeps the best of them."""
    if candidates == 1:
        return prior_run_id(name, column_set)
    return f"prior-{name}-best{candidates}-s{column_set}"


def candidate_seeds(column_set: int, candidates: int) -> range:
    """The training seeds of the candidates of column set ``column_set``: k * set + j, j < k
    (with one candidate: the set's own seed, as before candidates existed)."""
    return range(candidates * column_set, candidates * (column_set + 1))


def select_run(name: str, column_set: int, candidates: int) -> RunSpec:
    """The run that keeps the best of a source column's candidates (see :mod:`.running.work`)."""
    return RunSpec(
        run_id=column_run_id(name, column_set, candidates),
        kind="select",
        agent="dsac",
        path=None,
        env_id=PRIOR_ENVS[name],
        seed=column_set,
        episodes=0,
        deps=tuple(prior_run_id(name, s) for s in candidate_seeds(column_set, candidates)),
    )


def with_env_kwargs(
    tasks: tuple[tuple[str, str, dict[str, Any]], ...], env_kwargs: dict[str, Any]
) -> tuple[tuple[str, str, dict[str, Any]], ...]:
    """Evaluation tasks with a set-up's environment kwargs added (the task's own win)."""
    return tuple((label, env_id, {**env_kwargs, **kwargs}) for label, env_id, kwargs in tasks)


def prior_run(
    name: str, seed: int, episodes: int, setup: TrainingSetup, eval_episodes: int, run_id: str
) -> RunSpec:
    """A source column's run: DiscreteSAC on its task, evaluated there under start noise."""
    env_id = PRIOR_ENVS[name]
    return RunSpec(
        run_id=run_id,
        kind="prior",
        agent="dsac",
        path=None,
        env_id=env_id,
        seed=seed,
        episodes=episodes,
        eval_tasks=(("own", env_id, {**setup.env_kwargs(), **setup.source_env_kwargs(env_id)}),),
        eval_episodes=eval_episodes,
        sac_kwargs=setup.sac_kwargs(prior=True, column=name),
        env_kwargs=setup.train_env_kwargs(env_id),
        validation=setup.validation(column=name),
    )


def build_plan(config: StudyConfig) -> list[RunSpec]:
    """All runs of a study, priors first (a run's ``deps`` always come earlier in the list)."""
    budget = config.budget
    setup = config.setup
    prior_seeds = range(config.seeds) if config.prior_per_seed else range(1)
    needed: set[str] = set()
    for path in config.paths:
        for agent in config.agents:
            needed.update(agent_priors(setup, agent, path))
    runs: list[RunSpec] = []
    for column_set in prior_seeds:
        for name in PRIOR_ENVS:
            k = setup.column_candidates(name)
            if name in needed:
                for seed in candidate_seeds(column_set, k):
                    runs.append(
                        prior_run(
                            name,
                            seed,
                            setup.column_episodes(name, budget.prior_episodes[name]),
                            setup,
                            budget.eval_episodes,
                            prior_run_id(name, seed),
                        )
                    )
                if k > 1:
                    runs.append(select_run(name, column_set, k))
    # baselines next (cheap, no dependencies), then the learners seed by seed, so that an
    # interrupted study has every agent on both tasks for its first seeds
    for path in config.paths:
        for agent in BASELINES:
            runs.append(
                RunSpec(
                    run_id=f"{agent}-{path}",
                    kind="baseline",
                    agent=agent,
                    path=path,
                    env_id=PLANNING_ENVS[path],
                    seed=0,
                    episodes=0,
                    eval_tasks=with_env_kwargs(
                        EVAL_TASKS[path], {**setup.env_kwargs(), **setup.ending_env_kwargs()}
                    ),
                    eval_episodes=budget.eval_episodes,
                    trace_episodes=budget.trace_episodes,
                )
            )
    for seed in range(config.seeds):
        for path in config.paths:
            episodes = budget.transfer_episodes[path]
            record = tuple(e for e in PAPER_TRAJECTORY_EPISODES[path] if e < episodes)
            if episodes - 1 not in record:
                record += (episodes - 1,)  # the last training episode: where the budget ends
            prior_seed = seed if config.prior_per_seed else 0
            for agent in config.agents:
                deps = tuple(
                    column_run_id(name, prior_seed, setup.column_candidates(name))
                    for name in agent_priors(setup, agent, path)
                )
                own_env = setup.agent_env_kwargs(agent, path)
                runs.append(
                    RunSpec(
                        run_id=f"{agent}-{path}-s{seed}",
                        kind="transfer",
                        agent=agent,
                        path=path,
                        env_id=PLANNING_ENVS[path],
                        seed=seed,
                        episodes=episodes,
                        deps=deps,
                        record_episodes=record,
                        eval_tasks=with_env_kwargs(
                            EVAL_TASKS[path], {**setup.env_kwargs(), **own_env}
                        ),
                        eval_episodes=budget.eval_episodes,
                        trace_episodes=budget.trace_episodes,
                        sac_kwargs=setup.sac_kwargs(agent=agent, path=path),
                        env_kwargs={**setup.train_env_kwargs(PLANNING_ENVS[path]), **own_env},
                        validation=setup.validation(learner=True, path=path, agent=agent),
                        play=play_of(setup, agent, path),
                    )
                )
    return runs


def play_of(setup: TrainingSetup, agent: str, path: str) -> dict[str, Any]:
    """How the study evaluates learner ``agent``'s runs on ``path`` (RunSpec.play): SPNN's
    through a switch memory where ``spnn_play_memory`` acts; without immediate turn reversals
    SPNN's where ``spnn_play_no_reversal`` acts, PNN's where ``pnn_play_no_reversal`` does and
    every learner's where ``learners_play_no_reversal`` does; else as trained (empty)."""
    play: dict[str, Any] = {}
    memory = setup.spnn_play_memory_of(path) if agent == "spnn" else None
    if memory is not None:
        play["switch_memory"] = memory
    own = agent in ("spnn", "pnn") and setup.on_path(f"{agent}_play_no_reversal", path)
    if own or setup.on_path("learners_play_no_reversal", path):
        play["no_reversal"] = True
    return play
