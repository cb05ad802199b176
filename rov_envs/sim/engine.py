"""The engine behind every rov_envs environment: arrays and kernels for N vehicles on one task.

:class:`RovBatch` owns the lane buffer of the physics (:mod:`rov_envs.physics.integrator`), each
vehicle's obstacles, random stream, counters and observation buffers, and calls the kernels of
:mod:`rov_envs.sim.kernel`. It has no autoreset policy of its own:
:class:`rov_envs.envs.env.RovEnv` runs
it with N = 1, :class:`rov_envs.envs.vector.RovVectorEnv` (Gymnasium) and
:class:`rov_envs.envs.sb3.RovSB3VecEnv` (Stable-Baselines3) with N vehicles and their autoreset
modes,
and ``sb3_pnn.evaluation`` steps it directly.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from gymnasium.utils import seeding

from rov_envs.physics.dynamics import STATE_DIM
from rov_envs.physics.integrator import load_euler_state, new_lanes
from rov_envs.physics.thrusters import ACTION_TABLE
from rov_envs.sim import kernel as K
from rov_envs.sim.config import EnvConfig, make_config
from rov_envs.sim.episode import cfg_array, obstacle_capacity
from rov_envs.sim.random_stream import stream_seed
from rov_envs.sim.rewards import END_COLLISION, END_REASONS
from rov_envs.sim.spaces import make_spaces

#: Vehicles from which ``step`` and ``reset_all`` use numba's threads (same numbers either way).
#: Below it no thread pool is started at all, so small batches stay safe to use in forked
#: processes (GNU OpenMP) and from several Python threads (numba's workqueue layer).
PARALLEL_MIN_ENVS = 64

K.check_compiled_params()


def schmitt_trigger(nearest: np.ndarray, before: np.ndarray, on: float, off: float) -> np.ndarray:
    """The ``obstacle_latch`` rule after a nearest-obstacle reading (m): on within ``on``, kept
    on (``before``) until beyond ``off``."""
    return (nearest <= on) | (before & (nearest <= off))


class RovBatch:
    """N vehicles on one task (``config`` or ``task`` plus the single env's keyword arguments)."""

    def __init__(
        self,
        num_envs: int,
        task: str = "PlanningStraight",
        config: EnvConfig | None = None,
        **kwargs: Any,
    ) -> None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)):
            raise ValueError(f"num_envs={num_envs!r} is not allowed: expected an int >= 1")
        if num_envs < 1:
            raise ValueError(f"num_envs={num_envs!r} is not allowed: expected an int >= 1")
        if config is not None and kwargs:
            raise ValueError(
                f"{sorted(kwargs)[0]}=... is not allowed together with config: pass one of them"
            )
        self.config: EnvConfig = config if config is not None else make_config(task, **kwargs)
        self.num_envs = n = int(num_envs)
        self.single_observation_space, self.single_action_space = make_spaces(self.config)
        c = self.config
        self.has_path = "path" in c.obs_parts
        self.has_goal = "goal" in c.obs_parts
        #: columns of the path buffer that make the goal part: the goal's heading deviation,
        #: then, with ``goal_offset``, g / d_L (rov_envs.sim.kernel's obs_path layout)
        self.goal_columns = [2, 1] if c.goal_offset else [2]
        self.has_sonar = c.has_sonar
        #: the "latch" part (``obstacle_latch``): per vehicle, the trigger's state now and at
        #: the final step of an episode that ended and was reset in the same step
        self.latch_bounds = c.obstacle_latch
        self.latch = np.zeros(n, dtype=np.bool_)
        self.term_latch = np.zeros(n, dtype=np.bool_)
        self.has_motion = c.motion_obs
        self.continuous = c.continuous
        q = c.sonar_sectors if c.has_sonar else 0
        m = obstacle_capacity(c)
        self.table = np.ascontiguousarray(ACTION_TABLE, dtype=np.float64)
        self.cfg = cfg_array(c)
        self.lanes = new_lanes(n)
        self.obstacles = np.zeros((n, m, 3))
        self.n_obs = np.zeros(n, dtype=np.int64)
        fixed = c.fixed_obstacles()
        if fixed is not None and fixed.shape[0]:
            self.obstacles[:] = fixed
            self.n_obs[:] = fixed.shape[0]
        self.rng = np.zeros(n, dtype=np.uint64)
        self.sonar_raw = np.zeros((n, q))
        self.obs_path = np.zeros((n, K.PATH_COLUMNS), dtype=np.float32)
        self.obs_sonar = np.zeros((n, q), dtype=np.float32)
        self.obs_motion = np.zeros((n, 2), dtype=np.float32)
        #: results and counters, one row per ``rov_envs.sim.kernel.O_*`` field
        self.out = np.zeros((K.O_SIZE, n))
        #: per vehicle: autoreset pending (next-step mode) / was reset this step (same-step mode)
        self.pending = np.zeros(n, dtype=np.bool_)
        self.term_path = np.zeros((n, K.PATH_COLUMNS), dtype=np.float32)
        self.term_sonar = np.zeros((n, q), dtype=np.float32)
        self.term_motion = np.zeros((n, 2), dtype=np.float32)
        self.final = np.zeros((K.F_SIZE, n))
        self.seeded = np.zeros(n, dtype=np.bool_)
        self._no_int = np.zeros(n, dtype=np.int64)
        self._no_cont = np.zeros((n, 2))
        threads = n >= PARALLEL_MIN_ENVS
        self._kernel = K.step_batch_parallel if threads else K.step_batch
        self._reset_kernel = K.reset_all_parallel if threads else K.reset_all
        #: the arrays ``kernel.step_batch`` takes after (mode, n, actions, cont, continuous)
        self.step_arrays = (
            self.table, self.cfg, self.lanes, self.obstacles, self.n_obs, self.rng,
            self.sonar_raw, self.obs_path, self.obs_sonar, self.obs_motion, self.out, self.pending,
            self.term_path, self.term_sonar, self.term_motion, self.final,
        )  # fmt: skip

    # ---- episodes ----
    def _arrays(self) -> tuple:
        return (
            self.lanes, self.cfg, self.obstacles, self.n_obs, self.rng, self.sonar_raw,
            self.obs_path, self.obs_sonar, self.obs_motion, self.out,
        )  # fmt: skip

    def _index(self, i: int) -> int:
        """``i`` checked against the batch (the kernels do not check their indices)."""
        if (
            isinstance(i, bool)
            or not isinstance(i, (int, np.integer))
            or not 0 <= i < self.num_envs
        ):
            raise ValueError(
                f"i={i!r} is not allowed: expected a vehicle index in [0, {self.num_envs})"
            )
        return int(i)

    def seed_stream(self, i: int, generator: np.random.Generator) -> None:
        """Seed vehicle i's random stream from ``generator`` (one draw)."""
        i = self._index(i)
        self.rng[i] = stream_seed(generator)
        self.seeded[i] = True

    def reset_index(self, i: int, seed: int | None = None) -> None:
        """Start vehicle i's next episode; ``seed`` (or a first reset) seeds its stream first."""
        i = self._index(i)
        if seed is not None or not self.seeded[i]:
            self.seed_stream(i, seeding.np_random(seed)[0])
        K.reset_vehicle(i, *self._arrays())
        self._update_latch(i)

    def reset_all(self, seeds: list[int | None]) -> None:
        """Start every vehicle's next episode; vehicle i's stream is seeded with ``seeds[i]``
        when that is not None or the vehicle was never seeded."""
        if len(seeds) != self.num_envs:
            raise ValueError(
                f"seeds of length {len(seeds)} are not allowed: expected {self.num_envs}"
            )
        for i, s in enumerate(seeds):
            if s is not None or not self.seeded[i]:
                self.seed_stream(i, seeding.np_random(s)[0])
        self._reset_kernel(self.num_envs, *self._arrays())
        self._update_latch(slice(None))

    def set_pose(self, i: int, x: float, y: float, heading: float) -> None:
        """Put vehicle i at rest at (x, y) with ``heading`` (rad), clear its counters, observe."""
        i = self._index(i)
        try:
            pose = (float(x), float(y), float(heading))
        except (TypeError, ValueError):
            pose = (math.nan,)  # refused below
        if not all(map(math.isfinite, pose)):
            raise ValueError(
                f"pose=({x!r}, {y!r}, {heading!r}) is not allowed: expected three finite floats "
                "(x, y in m, heading in rad)"
            )
        K.place_vehicle(i, self.lanes, self.cfg, *pose)
        K.start_episode(i, *self._arrays())
        self._update_latch(i)

    # ---- stepping ----
    def step(self, actions: Any, mode: int = K.MODE_PLAIN) -> None:
        """Advance every vehicle one control period (results in ``out``, ``obs_*``)."""
        n = self.num_envs
        if self.continuous:
            a = np.asarray(actions, dtype=np.float64)
            if a.shape != (n, 2):
                raise ValueError(
                    f"actions of shape {a.shape} are not allowed: expected ({n}, 2) finite floats"
                )
            ai, ac = self._no_int, np.ascontiguousarray(a)
        else:
            ai = np.asarray(actions)
            if ai.shape != (n,) or ai.dtype.kind not in "iu":
                raise ValueError(
                    f"actions={actions!r} are not allowed: expected ({n},) ints in [0, 4]"
                )
            ai = ai.astype(np.int64, copy=False)
            ac = self._no_cont
        bad = K.first_bad_action(n, ai, ac, self.continuous, self.table.shape[0])
        if bad >= 0:
            what = "two finite floats" if self.continuous else "an int in [0, 4]"
            got = ac[bad] if self.continuous else ai[bad]
            raise ValueError(
                f"actions[{bad}]={got!r} is not allowed: expected {what} for every vehicle"
            )
        self._kernel(mode, n, ai, ac, self.continuous, *self.step_arrays)
        self.after_kernel_step(mode)

    def after_kernel_step(self, mode: int) -> None:
        """What follows every kernel step in Python (a caller that runs ``kernel.step_batch``
        itself calls it too): the ``obstacle_latch`` trigger."""
        if self.latch_bounds is not None:
            if mode == K.MODE_SAME_STEP:  # the ended episodes' final step, before their reset
                ended = self.pending
                self.term_latch[ended] = self._trigger(self.term_sonar[ended], self.latch[ended])
            self._update_latch(slice(None))

    def _trigger(self, sonar: np.ndarray, before: np.ndarray) -> np.ndarray:
        """:func:`schmitt_trigger` on rows of (normalized) sonar readings."""
        nearest = sonar.min(axis=1) * self.config.sonar_range
        return schmitt_trigger(nearest, before, *self.latch_bounds)

    def _update_latch(self, rows: int | slice) -> None:
        """Advance the trigger of vehicles ``rows`` on their current readings; a vehicle whose
        episode has taken no step yet (just reset: its step counter is 0) starts from its
        reading alone."""
        if self.latch_bounds is None:
            return
        rows = np.atleast_1d(np.arange(self.num_envs)[rows])
        started = self.out[K.O_STEPS, rows] > 0
        self.latch[rows] = self._trigger(self.obs_sonar[rows], self.latch[rows] & started)

    # ---- reading ----
    def positions(self) -> np.ndarray:
        """(N, 2) world x, y (m)."""
        return self.out[K.O_X : K.O_Y + 1].T.copy()

    def headings(self) -> np.ndarray:
        """(N,) heading psi (rad, continuous: not wrapped)."""
        return self.out[K.O_PSI].copy()

    def state(self, i: int) -> np.ndarray:
        """Vehicle i's 18-dim Euler-angle state (``rov_envs.physics.dynamics`` layout)."""
        i = self._index(i)
        out = np.zeros(STATE_DIM)
        load_euler_state(self.lanes, i, out)
        return out

    def vehicle_obstacles(self, i: int) -> np.ndarray:
        """Vehicle i's current obstacles (M_i, 3) (a copy)."""
        i = self._index(i)
        return self.obstacles[i, : self.n_obs[i]].copy()

    def _parts(
        self, path: np.ndarray, sonar: np.ndarray, motion: np.ndarray, latch: np.ndarray
    ) -> dict:
        """The task's observation parts from rows of the given arrays (copies)."""
        parts = {}
        if self.has_path:
            parts["path"] = path[..., :2].copy()
        if self.has_goal:
            parts["goal"] = path[..., self.goal_columns]
        if self.has_sonar:
            parts["sonar"] = sonar.copy()
        if self.has_motion:
            parts["motion"] = motion.copy()
        if self.latch_bounds is not None:
            parts["latch"] = np.asarray(latch, dtype=np.float32)[..., None]
        return parts

    def observations(self) -> dict[str, np.ndarray]:
        """The current observations (copies), one row per vehicle."""
        return self._parts(self.obs_path, self.obs_sonar, self.obs_motion, self.latch)

    def observation(self, i: int) -> dict[str, np.ndarray]:
        """Vehicle i's current observation (copies)."""
        return self._parts(self.obs_path[i], self.obs_sonar[i], self.obs_motion[i], self.latch[i])

    def terminal_observations(self, rows: np.ndarray) -> dict[str, np.ndarray]:
        """The final observations of the vehicles ``rows`` reset in the same step (copies)."""
        return self._parts(
            self.term_path[rows],
            self.term_sonar[rows],
            self.term_motion[rows],
            self.term_latch[rows],
        )

    def heading_errors(self) -> np.ndarray:
        """(N,) the heading deviation a_c of each vehicle now (rad; eq. 16)."""
        return self.out[K.O_AC].copy()

    def cross_tracks(self) -> np.ndarray:
        """(N,) the signed distance g of each vehicle from the path now (m)."""
        return self.out[K.O_G].copy()

    def step_results(self) -> dict[str, np.ndarray]:
        """What the last :meth:`step` gave each vehicle (copies): ``reward``, ``terminated``,
        ``truncated``, ``end_reason`` (``rov_envs.sim.rewards.END_REASONS`` names, ``"none"``
        while it runs), ``cross_track`` g (m) and ``heading_error`` a_c (rad)."""
        o = self.out
        return {
            "reward": o[K.O_R].copy(),
            "terminated": o[K.O_TERM] != 0,
            "truncated": o[K.O_TRUNC] != 0,
            "end_reason": np.array(
                [END_REASONS[e] for e in o[K.O_END].astype(np.int64)], dtype=object
            ),
            "cross_track": o[K.O_G].copy(),
            "heading_error": o[K.O_AC].copy(),
        }

    def infos(self) -> dict[str, np.ndarray]:
        """Per-vehicle info arrays (the single env's info keys, batched), views of one copy."""
        o = self.out.copy()
        return {
            "position": o[K.O_X : K.O_Y + 1].T,
            "heading": o[K.O_PSI],
            "velocity": o[K.O_U : K.O_YAW_RATE + 1].T,
            "cross_track": o[K.O_G],
            "heading_error": o[K.O_AC],
            "obstacle_distance": o[K.O_D],
            "progress": o[K.O_PROG],
            "collision": o[K.O_END] == END_COLLISION,
            "r_c": o[K.O_RC],
            "r_v": o[K.O_RV],
            "r_terminal": o[K.O_RT],
            "end_code": o[K.O_END].astype(np.int64),
            "steps": o[K.O_STEPS].astype(np.int64),
        }
