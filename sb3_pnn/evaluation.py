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
* per-episode records and, optionally, the first k trajectories (positions, heading deviation,
  distance from the route over time) for the trajectory figures.

Start poses: by default every episode starts from a Gaussian perturbation of the task's start pose
with std ``DEFAULT_START_NOISE = (1.0 m, 5 deg)`` (position x and y, heading), through the
environments' ``start_noise`` keyword, so that a deterministic policy is tested on 100 different
episodes rather than the same one 100 times. Pass ``start_noise=(0, 0)`` for the paper's exact
start at (0, 0) heading along the path.

Episodes run in lock-step batches of ``n_envs`` vehicles (one batched ``predict`` per control
step) on the natively batched simulator ``rov_envs.engine.RovBatch``; a finished vehicle starts the
next pending episode. Each episode depends only on its own seed, so the results do not depend on
``n_envs`` (for policies whose per-environment outputs do not depend on the rest of the batch).
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from gymnasium.spaces import Dict

#: Default start-pose perturbation: (position std in m, heading std in rad).
DEFAULT_START_NOISE: tuple[float, float] = (1.0, math.radians(5.0))
#: Default largest batch of vehicles stepped together.
DEFAULT_MAX_ENVS = 50


def wilson_interval(successes: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """Wilson score interval for a binomial proportion (95 % for ``z = 1.96``).

    ``p = k / n``; centre ``(p + z^2 / 2n) / (1 + z^2 / n)``, half-width
    ``z / (1 + z^2 / n) * sqrt(p (1 - p) / n + z^2 / 4n^2)``. Returns ``(lo, hi)`` in [0, 1].
    """
    for name, value in (("successes", successes), ("n", n)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise ValueError(f"{name}={value!r} is not allowed: expected an int")
    if n < 1:
        raise ValueError(f"n={n!r} is not allowed: expected an int >= 1")
    if not 0 <= successes <= n:
        raise ValueError(f"successes={successes!r} is not allowed: expected an int in [0, n={n}]")
    z = float(z)
    if not math.isfinite(z) or z <= 0:
        raise ValueError(f"z={z!r} is not allowed: expected a finite float > 0")
    p = successes / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2.0 * n)) / denom
    half = z / denom * math.sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n))
    return (max(0.0, centre - half), min(1.0, centre + half))


@dataclass
class EpisodeRecord:
    """One evaluation episode (distances in m, angles in rad, times in s).

    The cross-track and heading statistics are over the states after each step (the reset state
    is not counted); ``duration_s = steps * dt``; ``time_to_target`` is it for a success, else None.
    """

    index: int
    seed: int
    success: bool
    end_reason: str
    collision: bool
    steps: int
    duration_s: float
    episode_return: float
    mean_abs_cross_track: float
    max_abs_cross_track: float
    mean_abs_heading_error: float
    time_to_target: float | None


@dataclass
class Trajectory:
    """Time series of one episode; ``t[0] = 0`` is the reset pose, then one entry per step.

    ``actions[j]`` is the action taken at ``t[j]`` (one fewer entry than ``t``).
    """

    index: int
    seed: int
    success: bool
    end_reason: str
    t: list[float]
    x: list[float]
    y: list[float]
    heading_error: list[float]
    cross_track: list[float]
    actions: list[Any]
    obstacles: list[list[float]]


@dataclass
class EvaluationResult:
    """Statistics of :func:`evaluate_policy_on_task` (see the module docstring)."""

    env_id: str
    policy_name: str
    n_episodes: int
    seed: int
    start_noise: tuple[float, float]
    env_kwargs: dict[str, Any]
    deterministic: bool
    successes: int
    success_rate: float
    success_ci95: tuple[float, float]
    collisions: int
    collision_rate: float
    end_reasons: dict[str, int]
    mean_abs_cross_track: float
    max_abs_cross_track: float
    mean_abs_heading_error: float
    mean_time_to_target: float | None
    mean_return: float
    episodes: list[EpisodeRecord] = field(default_factory=list)
    trajectories: list[Trajectory] = field(default_factory=list)
    wall_time_s: float = 0.0
    #: the rov_envs vehicle preset that ran (``env.unwrapped.vehicle``; None for other envs)
    vehicle: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """A JSON-serialisable dict (tuples become lists)."""
        return _jsonable(asdict(self))

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> EvaluationResult:
        """Rebuild a result written by :meth:`to_dict`."""
        d = dict(data)
        d["start_noise"] = tuple(d["start_noise"])
        d["success_ci95"] = tuple(d["success_ci95"])
        d["episodes"] = [EpisodeRecord(**e) for e in d.get("episodes", [])]
        d["trajectories"] = [Trajectory(**t) for t in d.get("trajectories", [])]
        return cls(**d)

    def save_json(self, path: str | Path) -> Path:
        """Write :meth:`to_dict` as JSON to ``path`` (parents created); return the path."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(self.to_dict(), indent=1))
        return path

    def summary_rows(self) -> list[tuple[str, str]]:
        """(label, value) rows for a readable table."""
        lo, hi = self.success_ci95
        ttt = self.mean_time_to_target
        reasons = ", ".join(f"{k} {v}" for k, v in sorted(self.end_reasons.items()))
        last = self.seed + self.n_episodes - 1
        pos, head = self.start_noise[0], math.degrees(self.start_noise[1])
        rate = f"{100 * self.success_rate:.1f} % [{100 * lo:.1f}, {100 * hi:.1f}] (95 % Wilson)"
        return [
            ("task", self.env_id),
            ("vehicle", self.vehicle or "n/a"),
            ("policy", self.policy_name),
            ("episodes (seeds)", f"{self.n_episodes} ({self.seed}..{last})"),
            ("start noise", f"{pos:g} m, {head:g} deg"),
            ("success rate", rate),
            ("collisions", f"{self.collisions} ({100 * self.collision_rate:.1f} %)"),
            ("episode endings", reasons),
            ("mean |distance from route|", f"{self.mean_abs_cross_track:.3f} m"),
            ("max |distance from route|", f"{self.max_abs_cross_track:.3f} m"),
            ("mean |heading deviation|", f"{math.degrees(self.mean_abs_heading_error):.2f} deg"),
            ("mean time to target", "n/a (no success)" if ttt is None else f"{ttt:.1f} s"),
            ("mean return", f"{self.mean_return:.1f}"),
            ("wall time", f"{self.wall_time_s:.1f} s"),
        ]

    def format_table(self) -> str:
        """The summary as an aligned two-column text table."""
        rows = self.summary_rows()
        width = max(len(k) for k, _ in rows)
        return "\n".join(f"{k:<{width}}  {v}" for k, v in rows)


def _jsonable(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, (np.bool_, bool)):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, (np.floating, float)):
        v = float(value)
        return v if math.isfinite(v) else None
    return value


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
    from sb3_pnn.suggest import did_you_mean

    ours = list(rov_envs.ENV_IDS)
    hint = did_you_mean(env_id, [*ours, *(i.split("/", 1)[1] for i in ours), *gym.registry])
    raise ValueError(
        f"env_id={env_id!r} is not allowed: {hint}expected a registered env id, e.g. one of "
        f"{', '.join(ours)}"
    )


# ---------------------------------------------------------------------------------------------
# Backends: N vehicles stepped together, each (re)started with its own seed.
# ---------------------------------------------------------------------------------------------
class _Backend:
    n: int
    dt: float
    continuous: bool
    observation_space: Any
    action_space: Any

    def reset(self, i: int, seed: int) -> None: ...
    def step(self, actions: np.ndarray, active: np.ndarray) -> dict[str, np.ndarray]: ...
    def observations(self) -> dict[str, np.ndarray]: ...
    def obstacles(self, i: int) -> np.ndarray: ...
    def positions(self) -> np.ndarray: ...
    def start_errors(self) -> tuple[np.ndarray, np.ndarray]: ...


class _BatchBackend(_Backend):
    """rov_envs' natively batched simulator (one numba call per step for all vehicles)."""

    def __init__(self, task: str, n: int, env_kwargs: dict[str, Any]) -> None:
        from rov_envs import kernel as K
        from rov_envs.engine import RovBatch
        from rov_envs.rewards import END_REASONS

        self._K = K
        self._reasons = END_REASONS
        self.batch = RovBatch(n, task, **env_kwargs)
        self.n = n
        self.dt = float(self.batch.config.dt)
        self.continuous = bool(self.batch.continuous)
        self.sonar_range = float(self.batch.config.sonar_range)
        self.config = self.batch.config
        self.observation_space = self.batch.single_observation_space
        self.action_space = self.batch.single_action_space

    def reset(self, i: int, seed: int) -> None:
        self.batch.reset_index(i, seed=seed)

    def observations(self) -> dict[str, np.ndarray]:
        return self.batch.observations()

    def obstacles(self, i: int) -> np.ndarray:
        return self.batch.vehicle_obstacles(i)

    def positions(self) -> np.ndarray:
        return self.batch.positions()

    def start_errors(self) -> tuple[np.ndarray, np.ndarray]:
        K = self._K
        return self.batch.out[K.O_AC].copy(), self.batch.out[K.O_G].copy()

    def step(self, actions: np.ndarray, active: np.ndarray) -> dict[str, np.ndarray]:
        K = self._K
        if self.continuous:
            actions = np.where(active[:, None], actions, np.array([1.0, 0.0]))
        else:
            actions = np.where(active, actions, 2)
        self.batch.step(actions)
        o = self.batch.out
        end = o[K.O_END].astype(np.int64)
        return {
            "reward": o[K.O_R].copy(),
            "done": (o[K.O_TERM] != 0) | (o[K.O_TRUNC] != 0),
            "end_reason": np.array([self._reasons[e] for e in end], dtype=object),
            "cross_track": o[K.O_G].copy(),
            "heading_error": o[K.O_AC].copy(),
            "position": self.batch.positions(),
        }


class _SingleBackend(_Backend):
    """Any Gymnasium env id, one ``gymnasium.make`` env per slot (reads the rov_envs info keys)."""

    def __init__(self, env_id: str, n: int, env_kwargs: dict[str, Any]) -> None:
        import gymnasium as gym

        self.envs = [gym.make(env_id, **env_kwargs) for _ in range(n)]
        self.n = n
        base = self.envs[0].unwrapped
        config = getattr(base, "config", None)
        self.config = config
        self.dt = float(getattr(config, "dt", getattr(base, "dt", 0.2)))
        from gymnasium import spaces

        self.continuous = isinstance(self.envs[0].action_space, spaces.Box)
        self.observation_space = self.envs[0].observation_space
        self.action_space = self.envs[0].action_space
        self._obs: list[dict[str, np.ndarray]] = [{} for _ in range(n)]
        self._info: list[dict[str, Any]] = [{} for _ in range(n)]

    def reset(self, i: int, seed: int) -> None:
        self._obs[i], self._info[i] = self.envs[i].reset(seed=seed)

    def observations(self) -> dict[str, np.ndarray]:
        keys = next(o for o in self._obs if o).keys()
        out = {}
        for k in keys:
            ref = next(o[k] for o in self._obs if o)
            out[k] = np.stack([np.asarray(o[k]) if o else np.zeros_like(ref) for o in self._obs])
        return out

    def obstacles(self, i: int) -> np.ndarray:
        obs = getattr(self.envs[i].unwrapped, "obstacles", np.zeros((0, 3)))
        return np.asarray(obs, dtype=np.float64).reshape(-1, 3)

    def positions(self) -> np.ndarray:
        return np.array([np.asarray(inf.get("position", (np.nan, np.nan))) for inf in self._info])

    def start_errors(self) -> tuple[np.ndarray, np.ndarray]:
        ac = np.array([float(inf.get("heading_error", np.nan)) for inf in self._info])
        g = np.array([float(inf.get("cross_track", np.nan)) for inf in self._info])
        return ac, g

    def step(self, actions: np.ndarray, active: np.ndarray) -> dict[str, np.ndarray]:
        n = self.n
        res = {
            "reward": np.zeros(n),
            "done": np.zeros(n, dtype=bool),
            "end_reason": np.array(["none"] * n, dtype=object),
            "cross_track": np.full(n, np.nan),
            "heading_error": np.full(n, np.nan),
            "position": np.full((n, 2), np.nan),
        }
        for i in np.flatnonzero(active):
            a = actions[i] if self.continuous else int(actions[i])
            obs, r, term, trunc, info = self.envs[i].step(a)
            self._obs[i], self._info[i] = obs, info
            res["reward"][i] = r
            res["done"][i] = term or trunc
            if term or trunc:
                reason = info.get("end_reason")
                if reason is None:
                    reason = "success" if info.get("is_success") else "failure"
                res["end_reason"][i] = reason
            res["cross_track"][i] = info.get("cross_track", np.nan)
            res["heading_error"][i] = info.get("heading_error", np.nan)
            res["position"][i] = info.get("position", (np.nan, np.nan))
        return res


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


def _check_int(name: str, value: Any, low: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
        raise ValueError(f"{name}={value!r} is not allowed: expected an int >= {low}")
    return int(value)


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


def _check_spaces(policy: Any, name: str, backend: _Backend, env_id: str) -> None:
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
        env_kwargs: further keyword arguments of the env (not ``start_noise``).
        record_trajectories: keep the time series of the first k episodes (0 <= k <= n_episodes).
        deterministic: passed to ``predict``.
        n_envs: vehicles stepped together (default ``min(n_episodes, 50)``).
        policy_name: label stored in the result (default: the baseline name or the class name).

    Returns:
        An :class:`EvaluationResult`; episodes in index order.
    """
    t0 = time.perf_counter()
    n_episodes = _check_int("n_episodes", n_episodes, 1)
    seed = _check_int("seed", seed, 0)
    record_trajectories = _check_int("record_trajectories", record_trajectories, 0)
    if record_trajectories > n_episodes:
        raise ValueError(
            f"record_trajectories={record_trajectories!r} is not allowed: expected an int in "
            f"[0, n_episodes={n_episodes}]"
        )
    n_envs = min(n_episodes, DEFAULT_MAX_ENVS) if n_envs is None else n_envs
    n_envs = min(_check_int("n_envs", n_envs, 1), n_episodes)
    try:
        noise = tuple(float(v) for v in start_noise)
    except (TypeError, ValueError):
        noise = ()
    if len(noise) != 2 or not all(math.isfinite(v) and v >= 0 for v in noise):
        raise ValueError(
            f"start_noise={start_noise!r} is not allowed: expected (position_std_m, "
            "heading_std_rad), both finite and >= 0"
        )
    env_kwargs = dict(env_kwargs or {})
    if "start_noise" in env_kwargs:
        raise ValueError(
            f"env_kwargs={env_kwargs!r} is not allowed: pass the start-pose perturbation as "
            "start_noise=..., not inside env_kwargs"
        )
    env_id = resolve_env_id(env_id)
    kwargs = {**env_kwargs, "start_noise": noise}

    from rov_envs.tasks import TASKS

    spec_kwargs = __import__("gymnasium").registry[env_id].kwargs or {}
    task = spec_kwargs.get("task")
    backend: _Backend
    if env_id.startswith("rov_envs/") and task in TASKS:
        backend = _BatchBackend(task, n_envs, kwargs)
    else:
        backend = _SingleBackend(env_id, n_envs, kwargs)
    policy, name = _resolve_policy(policy, getattr(backend, "config", None), policy_name)
    _check_spaces(policy, name, backend, env_id)
    if hasattr(policy, "reset") and callable(policy.reset):
        policy.reset()

    records: list[EpisodeRecord | None] = [None] * n_episodes
    trajectories: list[Trajectory | None] = [None] * record_trajectories
    slot_ep = np.full(n_envs, -1, dtype=np.int64)
    next_ep = 0
    acc_ret = np.zeros(n_envs)
    acc_steps = np.zeros(n_envs, dtype=np.int64)
    acc_g = np.zeros(n_envs)
    acc_ac = np.zeros(n_envs)
    max_g = np.zeros(n_envs)
    traj_buf: dict[int, dict[str, list]] = {}
    episode_start = np.ones(n_envs, dtype=bool)

    def start(i: int) -> None:
        nonlocal next_ep
        if next_ep >= n_episodes:
            slot_ep[i] = -1
            return
        ep = next_ep
        next_ep += 1
        slot_ep[i] = ep
        backend.reset(i, seed + ep)
        acc_ret[i] = acc_g[i] = acc_ac[i] = max_g[i] = 0.0
        acc_steps[i] = 0
        episode_start[i] = True
        if ep < record_trajectories:
            pos = backend.positions()[i]
            ac, g = backend.start_errors()
            traj_buf[ep] = {
                "t": [0.0],
                "x": [float(pos[0])],
                "y": [float(pos[1])],
                "heading_error": [float(ac[i])],
                "cross_track": [float(g[i])],
                "actions": [],
            }

    for i in range(n_envs):
        start(i)
    state = None
    while (slot_ep >= 0).any():
        active = slot_ep >= 0
        obs = backend.observations()
        actions, state = policy.predict(
            obs, state=state, episode_start=episode_start.copy(), deterministic=deterministic
        )
        actions = _as_actions(actions, n_envs, backend.continuous)
        episode_start[:] = False
        res = backend.step(actions, active)
        for i in np.flatnonzero(active):
            ep = int(slot_ep[i])
            g = abs(float(res["cross_track"][i]))
            ac = abs(float(res["heading_error"][i]))
            acc_ret[i] += res["reward"][i]
            acc_steps[i] += 1
            acc_g[i] += g
            acc_ac[i] += ac
            max_g[i] = max(max_g[i], g)
            if ep in traj_buf:
                tb = traj_buf[ep]
                tb["t"].append(acc_steps[i] * backend.dt)
                tb["x"].append(float(res["position"][i, 0]))
                tb["y"].append(float(res["position"][i, 1]))
                tb["heading_error"].append(float(res["heading_error"][i]))
                tb["cross_track"].append(float(res["cross_track"][i]))
                a = actions[i]
                tb["actions"].append(a.tolist() if backend.continuous else int(a))
            if not res["done"][i]:
                continue
            reason = str(res["end_reason"][i])
            success = reason == "success"
            steps = int(acc_steps[i])
            duration = steps * backend.dt
            records[ep] = EpisodeRecord(
                index=ep,
                seed=seed + ep,
                success=success,
                end_reason=reason,
                collision=reason == "collision",
                steps=steps,
                duration_s=duration,
                episode_return=float(acc_ret[i]),
                mean_abs_cross_track=float(acc_g[i] / steps),
                max_abs_cross_track=float(max_g[i]),
                mean_abs_heading_error=float(acc_ac[i] / steps),
                time_to_target=duration if success else None,
            )
            if ep in traj_buf:
                tb = traj_buf.pop(ep)
                trajectories[ep] = Trajectory(
                    index=ep,
                    seed=seed + ep,
                    success=success,
                    end_reason=reason,
                    obstacles=backend.obstacles(i).tolist(),
                    **tb,
                )
            start(i)
    eps = [r for r in records if r is not None]
    assert len(eps) == n_episodes
    return _summarise(
        eps,
        [t for t in trajectories if t is not None],
        env_id=env_id,
        policy_name=name,
        seed=seed,
        start_noise=noise,
        env_kwargs=env_kwargs,
        deterministic=bool(deterministic),
        wall_time_s=time.perf_counter() - t0,
        vehicle=getattr(getattr(backend, "config", None), "vehicle", None),
    )


def _summarise(
    eps: list[EpisodeRecord], trajectories: list[Trajectory], **meta: Any
) -> EvaluationResult:
    n = len(eps)
    successes = sum(e.success for e in eps)
    collisions = sum(e.collision for e in eps)
    reasons: dict[str, int] = {}
    for e in eps:
        reasons[e.end_reason] = reasons.get(e.end_reason, 0) + 1
    times = [e.time_to_target for e in eps if e.time_to_target is not None]
    return EvaluationResult(
        n_episodes=n,
        successes=successes,
        success_rate=successes / n,
        success_ci95=wilson_interval(successes, n),
        collisions=collisions,
        collision_rate=collisions / n,
        end_reasons=reasons,
        mean_abs_cross_track=float(np.mean([e.mean_abs_cross_track for e in eps])),
        max_abs_cross_track=float(max(e.max_abs_cross_track for e in eps)),
        mean_abs_heading_error=float(np.mean([e.mean_abs_heading_error for e in eps])),
        mean_time_to_target=float(np.mean(times)) if times else None,
        mean_return=float(np.mean([e.episode_return for e in eps])),
        episodes=eps,
        trajectories=trajectories,
        **meta,
    )
