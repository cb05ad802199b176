"""Evaluate a policy (SB3 model or baseline controller) on an rov_envs task (paper section 4.3).

:func:`evaluate_policy_on_task` runs ``n_episodes`` episodes with fixed seeds (episode i is reset
with ``seed + i``, which fixes its obstacle layout, its start-pose perturbation and its sonar
noise) and returns an :class:`EvaluationResult` with

* the success rate and its 95 % Wilson score interval (:func:`wilson_interval`) - the statistic
  behind Figure 20;
* collisions (episodes ended by ``d <= 2`` m, eq. 21) and every ending's count;
* mean and max |distance from the route| (``info["cross_track"]`` = g, m) and mean |heading
  deviation| (``info["heading_error"]`` = a_c of eq. 16, rad) - Figures 12, 13, 15-19 (b, c);
* the mean time to target (s) over the successful episodes;
* the mean return and, given a discount gamma, the mean discounted return sum_t gamma^t r_t;
* per-episode records and, optionally, the first k trajectories (positions, heading deviation,
  distance from the route over time) for the trajectory figures.

Start poses: by default every episode starts from a Gaussian perturbation of the task's start pose
with std ``DEFAULT_START_NOISE = (1.0 m, 5 deg)`` (position x and y, heading), through the
environments' ``start_noise`` keyword, so that a deterministic policy is tested on 100 different
episodes rather than the same one 100 times. Pass ``start_noise=(0, 0)`` for the paper's exact
start at (0, 0) heading along the path.

Episodes run in lock-step batches of ``n_envs`` vehicles (one batched ``predict`` per control
step) on the natively batched simulator ``rov_envs.sim.engine.RovBatch``; a finished vehicle starts
the
next pending episode. Each episode depends only on its own seed, so the results do not depend on
``n_envs`` (for policies whose per-environment outputs do not depend on the rest of the batch).
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
from gymnasium.spaces import Dict

from sb3_pnn.common.checks import check_int, is_finite_number
from sb3_pnn.evaluation.backends import Backend, make_backend
from sb3_pnn.evaluation.result import EpisodeRecord, EvaluationResult, Trajectory, summarise

#: Default start-pose perturbation: (position std in m, heading std in rad).
DEFAULT_START_NOISE: tuple[float, float] = (1.0, math.radians(5.0))
#: Default largest batch of vehicles stepped together.
DEFAULT_MAX_ENVS = 50


def resolve_env_id(env_id: str) -> str:
    """``"PlanningStraight-v0"`` or ``"rov_envs/PlanningStraight-v0"`` -> the registered id."""
    import gymnasium as gym

    import rov_envs  # noqa: F401  (registers the ids)

    if not isinstance(env_id, str) or not env_id:
        raise ValueError(f"env_id={env_id!r} is not allowed: expected a registered env id")
    candidates = [env_id] if "/" in env_id else [f"rov_envs/{env_id}", env_id]
    for cand in candidates:
        if cand in gym.registry:
            return cand
    from sb3_pnn.common.checks import did_you_mean

    ours = list(rov_envs.ENV_IDS)
    hint = did_you_mean(env_id, [*ours, *(i.split("/", 1)[1] for i in ours), *gym.registry])
    raise ValueError(
        f"env_id={env_id!r} is not allowed: {hint}expected a registered env id, e.g. one of "
        f"{', '.join(ours)}"
    )


def _as_actions(actions: Any, n: int, continuous: bool) -> np.ndarray:
    a = np.asarray(actions)
    if continuous:
        a = a.astype(np.float64).reshape(n, -1)
        if a.shape[1] != 2:
            raise ValueError(
                f"the policy returned actions of shape {np.shape(actions)}: expected ({n}, 2)"
            )
        return np.clip(a, -1.0, 1.0)
    if a.size != n:
        raise ValueError(
            f"the policy returned actions of shape {np.shape(actions)}: expected ({n},)"
        )
    return a.reshape(n).astype(np.int64)


def _resolve_policy(policy: Any, env_config: Any, policy_name: str | None) -> tuple[Any, str]:
    if isinstance(policy, str):
        from sb3_pnn.baselines import BASELINE_NAMES, make_baseline

        if policy not in BASELINE_NAMES:
            raise ValueError(
                f"policy={policy!r} is not allowed: expected an object with predict() or one of "
                f"{list(BASELINE_NAMES)}"
            )
        if env_config is None:
            raise ValueError(f"policy={policy!r} needs an rov_envs task")
        return make_baseline(policy, env=env_config), policy_name or policy
    if not callable(getattr(policy, "predict", None)):
        raise ValueError(
            f"policy={policy!r} is not allowed: expected an object with "
            "predict(obs, state, episode_start, deterministic) (an SB3 model or a baseline)"
        )
    return policy, policy_name or type(policy).__name__


def _check_spaces(policy: Any, name: str, backend: Backend, env_id: str) -> None:
    """A model (anything with ``observation_space`` / ``action_space``) must have the env's
    spaces: evaluated on another task it would fail deep inside ``predict`` (a KeyError for a
    missing observation part)."""
    for what in ("observation", "action"):
        mine, theirs = getattr(policy, f"{what}_space", None), getattr(backend, f"{what}_space")
        if mine is None or mine == theirs:
            continue
        hint = ""
        if isinstance(mine, Dict) and isinstance(theirs, Dict):
            lacks = [k for k in mine.spaces if k not in theirs.spaces]
            extra = [k for k in theirs.spaces if k not in mine.spaces]
            hint = "".join(
                f"; {side}: {', '.join(map(repr, keys))}"
                for side, keys in (("missing there", lacks), ("unknown to the policy", extra))
                if keys
            )
        raise ValueError(
            f"policy {name!r} was trained with the {what} space {mine}, but {env_id} has "
            f"{theirs}{hint}. Evaluate it on a task with the same {what}s"
        )


class _Episodes:
    """The episodes of one evaluation, run in lock-step on ``backend``'s slots: a slot that
    finishes an episode starts the next pending one (episode ``ep`` is reset with
    ``seed + ep``)."""

    def __init__(
        self,
        backend: Backend,
        n_episodes: int,
        seed: int,
        record: int,
        discount: float | None = None,
    ) -> None:
        n = backend.n
        self.backend, self.n_episodes, self.seed = backend, n_episodes, seed
        self.discount = discount
        self.discounted = np.zeros(n)
        self.records: list[EpisodeRecord | None] = [None] * n_episodes
        self.trajectories: list[Trajectory | None] = [None] * record
        self.slot_ep = np.full(n, -1, dtype=np.int64)
        self.next_ep = 0
        self.ret = np.zeros(n)
        self.steps = np.zeros(n, dtype=np.int64)
        self.sum_g = np.zeros(n)
        self.sum_ac = np.zeros(n)
        self.max_g = np.zeros(n)
        self.traces: dict[int, dict[str, list]] = {}
        self.episode_start = np.ones(n, dtype=bool)

    def start(self, i: int) -> None:
        """Start the next pending episode in slot i (or leave the slot idle)."""
        if self.next_ep >= self.n_episodes:
            self.slot_ep[i] = -1
            return
        ep = self.next_ep
        self.next_ep += 1
        self.slot_ep[i] = ep
        self.backend.reset(i, self.seed + ep)
        self.ret[i] = self.sum_g[i] = self.sum_ac[i] = self.max_g[i] = self.discounted[i] = 0.0
        self.steps[i] = 0
        self.episode_start[i] = True
        if ep < len(self.trajectories):
            pos = self.backend.positions()[i]
            ac, g = self.backend.start_errors()
            self.traces[ep] = {
                "t": [0.0],
                "x": [float(pos[0])],
                "y": [float(pos[1])],
                "heading_error": [float(ac[i])],
                "cross_track": [float(g[i])],
                "actions": [],
            }

    def run(self, policy: Any, deterministic: bool) -> None:
        """Step every slot until every episode has ended."""
        backend = self.backend
        for i in range(backend.n):
            self.start(i)
        state = None
        while (self.slot_ep >= 0).any():
            active = self.slot_ep >= 0
            actions, state = policy.predict(
                backend.observations(),
                state=state,
                episode_start=self.episode_start.copy(),
                deterministic=deterministic,
            )
            actions = _as_actions(actions, backend.n, backend.continuous)
            self.episode_start[:] = False
            res = backend.step(actions, active)
            for i in np.flatnonzero(active):
                self.account(i, res, actions[i])

    def account(self, i: int, res: dict[str, np.ndarray], action: Any) -> None:
        """Add slot i's step to its episode; close the episode if it ended."""
        ep = int(self.slot_ep[i])
        g = abs(float(res["cross_track"][i]))
        ac = abs(float(res["heading_error"][i]))
        self.ret[i] += res["reward"][i]
        if self.discount is not None:  # reward of step t (from 0) weighs gamma^t
            self.discounted[i] += self.discount ** int(self.steps[i]) * res["reward"][i]
        self.steps[i] += 1
        self.sum_g[i] += g
        self.sum_ac[i] += ac
        self.max_g[i] = max(self.max_g[i], g)
        if ep in self.traces:
            trace = self.traces[ep]
            trace["t"].append(self.steps[i] * self.backend.dt)
            trace["x"].append(float(res["position"][i, 0]))
            trace["y"].append(float(res["position"][i, 1]))
            trace["heading_error"].append(float(res["heading_error"][i]))
            trace["cross_track"].append(float(res["cross_track"][i]))
            trace["actions"].append(action.tolist() if self.backend.continuous else int(action))
        if res["done"][i]:
            self.finish(i, ep, str(res["end_reason"][i]))
            self.start(i)

    def finish(self, i: int, ep: int, reason: str) -> None:
        success = reason == "success"
        steps = int(self.steps[i])
        duration = steps * self.backend.dt
        self.records[ep] = EpisodeRecord(
            index=ep,
            seed=self.seed + ep,
            success=success,
            end_reason=reason,
            collision=reason == "collision",
            steps=steps,
            duration_s=duration,
            episode_return=float(self.ret[i]),
            mean_abs_cross_track=float(self.sum_g[i] / steps),
            max_abs_cross_track=float(self.max_g[i]),
            mean_abs_heading_error=float(self.sum_ac[i] / steps),
            time_to_target=duration if success else None,
            discounted_return=None if self.discount is None else float(self.discounted[i]),
        )
        if ep in self.traces:
            self.trajectories[ep] = Trajectory(
                index=ep,
                seed=self.seed + ep,
                success=success,
                end_reason=reason,
                obstacles=self.backend.obstacles(i).tolist(),
                **self.traces.pop(ep),
            )


#: Keyword arguments of a training env that describe its own task's layout (its obstacles,
#: obstacle generator, path and corridor): not carried over to another task by
#: :func:`trained_env_kwargs` (an avoidance column trained among random fields is evaluated on
#: the dense layout's obstacles, not on random fields).
LAYOUT_KWARGS = (
    "obstacles",
    "layout",
    "length",
    "amplitude",
    "wavelength",
    "corridor",
    "max_episode_seconds",
)


def trained_env_kwargs(policy: Any, env_id: str) -> dict[str, Any]:
    """The keyword arguments ``policy`` was trained with (``policy.trained_env``, which
    :class:`sb3_pnn.DiscreteSAC` keeps in its checkpoints), for an evaluation on ``env_id``:
    without the training start noise and render mode (evaluation sets its own), and without the
    layout arguments when ``env_id`` is another task. {} when the policy does not say."""
    trained = getattr(policy, "trained_env", None)
    if not isinstance(trained, dict) or not isinstance(trained.get("kwargs"), dict):
        return {}
    dropped = {"start_noise", "render_mode"}
    if trained.get("id") != env_id:
        dropped.update(LAYOUT_KWARGS)
    return {k: v for k, v in trained["kwargs"].items() if k not in dropped}


def _check_start_noise(start_noise: Any) -> tuple[float, float]:
    try:
        noise = tuple(float(v) for v in start_noise)
    except (TypeError, ValueError):
        noise = ()
    if len(noise) != 2 or not all(math.isfinite(v) and v >= 0 for v in noise):
        raise ValueError(
            f"start_noise={start_noise!r} is not allowed: expected (position_std_m, "
            "heading_std_rad), both finite and >= 0"
        )
    return noise  # type: ignore[return-value]


def evaluate_policy_on_task(
    policy: Any,
    env_id: str,
    n_episodes: int = 100,
    seed: int = 0,
    start_noise: tuple[float, float] = DEFAULT_START_NOISE,
    env_kwargs: dict[str, Any] | None = None,
    record_trajectories: int = 0,
    deterministic: bool = True,
    n_envs: int | None = None,
    policy_name: str | None = None,
    discount: float | None = None,
) -> EvaluationResult:
    """Run ``n_episodes`` seeded episodes of ``policy`` on ``env_id`` and collect statistics.

    Args:
        policy: an object with SB3's ``predict(obs, state, episode_start, deterministic)``
            (a model, ``PIDController``, ...) or a baseline name ``"pid"`` / ``"adaptive_pid"``
            (built for the env with ``make_baseline``).
        env_id: a registered id; the ``"rov_envs/"`` prefix may be left out.
        n_episodes: number of episodes (>= 1); episode i is reset with seed ``seed + i``.
        seed: first seed (>= 0).
        start_noise: ``(position std m, heading std rad)`` of the start-pose perturbation, passed
            as the env's ``start_noise`` keyword (``(0, 0)``: the exact start pose).
        env_kwargs: further keyword arguments of the env (not ``start_noise``); None (the
            default): those the model was trained with (:func:`trained_env_kwargs`), {} for the
            env's defaults.
        record_trajectories: keep the time series of the first k episodes (0 <= k <= n_episodes).
        deterministic: passed to ``predict``.
        n_envs: vehicles stepped together (default ``min(n_episodes, 50)``).
        policy_name: label stored in the result (default: the baseline name or the class name).
        discount: with a discount factor gamma in (0, 1], each episode also records its
            discounted return sum_t gamma^t r_t, and the result their mean (what an agent
            trained with that gamma maximises from the start state); None (default): not.

    Returns:
        An :class:`EvaluationResult`; episodes in index order.
    """
    t0 = time.perf_counter()
    n_episodes = check_int("n_episodes", n_episodes, 1)
    seed = check_int("seed", seed, 0)
    record_trajectories = check_int("record_trajectories", record_trajectories, 0)
    if discount is not None and not (is_finite_number(discount) and 0 < discount <= 1):
        raise ValueError(
            f"discount={discount!r} is not allowed: expected a number in (0, 1] or None"
        )
    if record_trajectories > n_episodes:
        raise ValueError(
            f"record_trajectories={record_trajectories!r} is not allowed: expected an int in "
            f"[0, n_episodes={n_episodes}]"
        )
    n_envs = min(n_episodes, DEFAULT_MAX_ENVS) if n_envs is None else n_envs
    n_envs = min(check_int("n_envs", n_envs, 1), n_episodes)
    noise = _check_start_noise(start_noise)
    env_id = resolve_env_id(env_id)
    env_kwargs = dict(trained_env_kwargs(policy, env_id) if env_kwargs is None else env_kwargs)
    if "start_noise" in env_kwargs:
        raise ValueError(
            f"env_kwargs={env_kwargs!r} is not allowed: pass the start-pose perturbation as "
            "start_noise=..., not inside env_kwargs"
        )
    backend = make_backend(env_id, n_envs, {**env_kwargs, "start_noise": noise})
    policy, name = _resolve_policy(policy, getattr(backend, "config", None), policy_name)
    _check_spaces(policy, name, backend, env_id)
    if hasattr(policy, "reset") and callable(policy.reset):
        policy.reset()
    episodes = _Episodes(
        backend,
        n_episodes,
        seed,
        record_trajectories,
        None if discount is None else float(discount),
    )
    episodes.run(policy, deterministic)
    records = [r for r in episodes.records if r is not None]
    assert len(records) == n_episodes
    return summarise(
        records,
        [t for t in episodes.trajectories if t is not None],
        env_id=env_id,
        policy_name=name,
        seed=seed,
        start_noise=noise,
        env_kwargs=env_kwargs,
        deterministic=bool(deterministic),
        wall_time_s=time.perf_counter() - t0,
        vehicle=getattr(getattr(backend, "config", None), "vehicle", None),
    )
