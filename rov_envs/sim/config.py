"""The keyword arguments of every rov_envs task, typed and documented once: :class:`EnvConfig`.

``gymnasium.make("rov_envs/<Task>-v0", **kwargs)`` passes ``kwargs`` to :func:`make_config`,
which checks each against its field of :class:`EnvConfig` and resolves the defaults that depend
on the task. Every bad value raises ``ValueError`` naming the argument, the bad value and what is
allowed. The same configuration drives the single environment and the batched one, so both see
exactly the same task.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

from rov_envs.physics.dynamics import DEFAULT_CONTROL_PERIOD
from rov_envs.physics.guidance import DEFAULT_LOOKAHEAD, LOOKAHEAD_RANGE
from rov_envs.physics.params import DEFAULT_VEHICLE, VEHICLES
from rov_envs.sim.layouts import LAYOUT_CODES
from rov_envs.sim.tasks import HEADING_REFERENCES, PATH_SINE, TASKS, TaskSpec

#: Control period (s) of one environment step by default: 1.0 s (the paper gives none; the
#: physics integrates it in substeps of at most 0.05 s; the study's set-up, chosen in
#: docs/ablation sections 26 and 30). Read literally the paper's set-up in this package runs
#: 0.2 s (``DEFAULT_CONTROL_PERIOD``, 4 substeps).
CONTROL_PERIOD = 1.0
#: Start-pose perturbation by default: (position std in m, heading std in rad), 1 m and 5 deg,
#: as in evaluation (the paper starts every episode at exactly (0, 0)).
START_NOISE = (1.0, math.radians(5.0))
#: Shortest and longest control periods accepted (s) (``control_period``).
CONTROL_PERIOD_RANGE = (0.05, 1.0)
#: Longest integrator substep (s): the physics' default, 0.2 s in 4 substeps.
MAX_SUBSTEP = DEFAULT_CONTROL_PERIOD / 4
#: Reference speed (m/s) for the default time limit and the progress reward.
U_REF = 1.0
#: Default time limit = TIME_LIMIT_FACTOR * (path arc length / U_REF).
TIME_LIMIT_FACTOR = 2.0
#: Sonar defaults: span pi centred ahead, 9 sectors, 25 m range (so that SPNN's d_th = 12.5 m is
#: mid-range).
SONAR_SPAN = math.pi
SONAR_SECTORS = 9
SONAR_RANGE = 25.0
#: Success radius around the target point (m), used besides the along-path progress test.
TARGET_RADIUS = 2.0
#: The largest number of sonar sectors accepted.
MAX_SECTORS = 360


def _bad(name: str, value: Any, allowed: str) -> ValueError:
    return ValueError(f"{name}={value!r} is not allowed: expected {allowed}")


def _finite_float(name: str, value: Any, allowed: str) -> float:
    if isinstance(value, (bool, str, bytes)):  # "0.2" is a typo in a config, not a number
        raise _bad(name, value, allowed)
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise _bad(name, value, allowed) from None
    if not math.isfinite(out):
        raise _bad(name, value, allowed)
    return out


def _pair(name: str, value: Any, allowed: str, nonneg: bool = False) -> tuple[float, float]:
    try:
        seq = tuple(value)
    except TypeError:
        raise _bad(name, value, allowed) from None
    if len(seq) != 2:
        raise _bad(name, value, allowed)
    out = tuple(_finite_float(name, v, allowed) for v in seq)
    if nonneg and min(out) < 0:
        raise _bad(name, value, allowed)
    return out  # type: ignore[return-value]


def sine_arc_length(length: float, amplitude: float, wavelength: float) -> float:
    """Arc length of y = amplitude * sin(2 pi x / wavelength) for 0 <= x <= length (m)."""
    x = np.linspace(0.0, length, 20001)
    dy = amplitude * 2.0 * math.pi / wavelength * np.cos(2.0 * math.pi * x / wavelength)
    f = np.sqrt(1.0 + dy * dy)
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x)))


@dataclass(frozen=True)
class EnvConfig:
    """A task and its keyword arguments: ``gymnasium.make(id, **kwargs)``'s ``kwargs``.

    Every field but ``task`` is a keyword argument of every rov_envs task; a field left at None
    takes the task's value (:mod:`rov_envs.sim.tasks`). :func:`make_config` checks the values
    and fills those in.

    ## Arguments
    * ``obstacles``: ``[(x, y, radius), ...]`` in metres, a fixed layout replacing the task's
      (no surface within 2 m of the start point).
    * ``current``: ``(vx, vy)``, the world-frame water velocity in m/s, speed <= 2
      (default ``(0, 0)``).
    * ``sonar_noise``: std (m) of Gaussian noise on each sonar return (default 0).
    * ``start_noise``: ``(position_std_m, heading_std_rad)`` of the Gaussian perturbation of the
      start pose (default ``(1, 5 deg)``; ``(0, 0)``: the paper's exact start).
    * ``length``: path length along x (m); ``amplitude``, ``wavelength``: the sine path's shape
      (m; a negative amplitude gives the path's mirror image). Default: the task's (200 m line;
      y = 15 sin(2 pi x / 120) over 120 m).
    * ``sonar_sectors`` (q, default 9), ``sonar_span`` (S, rad, default pi, centred ahead),
      ``sonar_range`` (m, default 25).
    * ``continuous``: ``Box(-1, 1, (2,))`` (surge, yaw) actions instead of Table 1's
      ``Discrete(5)`` (default False).
    * ``max_episode_seconds``: the time limit in simulated seconds (default: twice the path's
      arc length at 1 m/s).
    * ``render_mode``: None or ``"rgb_array"``.
    * ``success_reward``: reward added on the step that reaches the target (default 200; an
      addition to eq. 21, see :mod:`rov_envs.sim.rewards`; 0 gives the paper's reward).
    * ``obstacle_penalty``: weight of eq. 20's r_v, the charge for passing within 8 m / 5 m of
      an obstacle's surface (default 1, the paper's; 0 leaves only eq. 21's collision).
    * ``arrival_gate``: metres in [2, 100]: an episode that reaches the end of the path farther
      than this from the target point fails (end reason ``"missed_target"``, eq. 21's -200)
      instead of succeeding. The paper's vehicle must "avoid the obstacle and return to the
      set path to complete the task" (section 4.2.1). Default None: the end of the path
      reached anywhere inside the corridor is a success (within 2 m of the target also is).
    * ``vehicle``: the BlueROV2 parameter set, ``"uuv_simulator"`` (default, the paper's Gazebo
      model) or ``"wu2018"`` (Wu 2018), see :mod:`rov_envs.physics.params`.
    * ``motion_obs``: add the ``"motion"`` part (body-frame sway v in m/s and yaw rate r in
      rad/s, clipped to +-3 and +-2) to the observation (default True; the paper's state has
      no such part).
    * ``control_period``: seconds per environment step, in [0.05, 1] (default 1.0); the physics
      takes as many substeps as keep each at most 0.05 s.
    * ``progress_weighted``: pay r_c of eq. 18/19 (when positive) in proportion to the step's
      progress along the path, as a fraction of 1 m/s (default True; not in the paper, see
      :mod:`rov_envs.sim.rewards`).
    * ``progress_along``: the direction along which ``progress_weighted`` measures the step's
      advance: ``"path"`` (default, the path's tangent) or ``"course"`` (the LOS course, the
      direction from which a_c is measured: the return to the path is then paid in full; not
      in the paper, see :mod:`rov_envs.sim.rewards`). The obstacle-avoidance task's progress
      reward does not read it.
    * ``heading_reference``: ``"path"`` (a_c from the LOS course, eq. 16) or ``"goal"`` (a_c
      from the bearing to the target point), for the "path" part and eq. 21's heading rule;
      default: the task's (``"goal"`` for ObstacleAvoidance, ``"path"`` for the others).
    * ``los_lookahead``: the LOS lookahead distance Delta of eq. 16 in metres, in [0.5, 100]
      (default 5; the paper gives none): the desired course points at the path point Delta
      ahead of the closest one, so a vehicle d metres off the path is steered back at
      atan(d / Delta).
    * ``path_obs``: observe the "path" part [a_c / pi, g / d_L] (default: the task's; True for
      every task but ObstacleAvoidance).
    * ``goal_obs``: observe the "goal" part [heading deviation from the bearing to the goal /
      pi] (default: the task's; True for ObstacleAvoidance and the planning tasks).
    * ``goal_offset``: the "goal" part also holds the signed distance from the path, g / d_L
      (clipped to [-1, 1]): [heading deviation from the goal's bearing / pi, g / d_L] (default
      False). An obstacle-avoidance column that reads it knows how far a detour has taken it
      from its route, which a corridor (``corridor``) asks it to keep in mind; it still reads
      no heading of the path.
    * ``goal_distance``: the goal of the "goal" part: D > 0 for the route point D m further
      along x than the closest one (the route continued past its end), default
      25; None for the target point itself.
    * ``heading_rule``: what eq. 21's |a_c| >= pi/2 failure reads: ``"path"`` (the heading
      deviation a_c of ``heading_reference``, as the paper) or ``"goal"`` (the deviation from
      the goal's bearing: the episode fails when the vehicle turns away from where the route
      goes, not when a detour takes it off the LOS course); default: ``"goal"`` for the
      planning tasks, ``heading_reference`` for the others.
    * ``corridor``: the half-width d_L (m) of the corridor |g| < d_L around the path, in
      [1, 100]: eq. 21's off-path failure, eq. 18/19's distance term and the path part's g / d_L
      read it (default: the task's, 30 on the straight tasks and ObstacleAvoidance, 15 on the
      sine tasks, as section 4.2.1 gives them).
    * ``obstacle_latch``: ``(on, off)`` metres, 0 < on <= off, adds the ``"latch"`` part: 1
      once the nearest sonar reading is within ``on`` m, back to 0 only when it is beyond
      ``off`` m (a Schmitt trigger on the sonar, a one-bit memory of a near obstacle; each
      episode starts from its first reading alone). Default None: no such part. SPNN's gate
      can switch on it (``SelectivePolicy(gate_latch_key="latch")``): the sonar loses an
      obstacle that the vehicle turns its back on, and a switch without memory then hands
      control back to the path follower at once (docs/ablation section 42).
    * ``layout``: obstacles drawn afresh each episode by a generator of
      :mod:`rov_envs.sim.layouts` instead of the task's own (``"scatter"``: a random field of
      random density and size around the route, for training on layouts beyond the paper's;
      default None: the task's).
    """

    task: TaskSpec
    obstacles: np.ndarray | None = None
    current: tuple[float, float] = (0.0, 0.0)
    sonar_noise: float = 0.0
    start_noise: tuple[float, float] = START_NOISE
    length: float | None = None
    amplitude: float | None = None
    wavelength: float | None = None
    sonar_sectors: int = SONAR_SECTORS
    sonar_span: float = SONAR_SPAN
    sonar_range: float = SONAR_RANGE
    continuous: bool = False
    max_episode_seconds: float | None = None
    render_mode: str | None = None
    success_reward: float = 200.0
    obstacle_penalty: float = 1.0
    arrival_gate: float | None = None
    vehicle: str = DEFAULT_VEHICLE
    motion_obs: bool = True
    control_period: float = CONTROL_PERIOD
    progress_weighted: bool = True
    progress_along: str = "path"
    heading_reference: str | None = None
    los_lookahead: float = DEFAULT_LOOKAHEAD
    path_obs: bool | None = None
    goal_obs: bool | None = None
    goal_distance: float | None = None
    goal_offset: bool = False
    heading_rule: str | None = None
    corridor: float | None = None
    layout: str | None = None
    obstacle_latch: tuple[float, float] | None = None

    @property
    def layout_name(self) -> str:
        """The obstacle layout: ``layout`` when given, else the task's."""
        return self.layout or self.task.layout

    @property
    def d_L(self) -> float:
        """The corridor half-width (m): ``corridor`` when given, else the task's."""
        return self.task.d_L if self.corridor is None else self.corridor

    @property
    def dt(self) -> float:
        """The control period (s)."""
        return self.control_period

    @property
    def obs_parts(self) -> tuple[str, ...]:
        """Names of the observation's parts, in the order of the ``Dict`` space."""
        wanted = (
            ("path", self.path_obs),
            ("goal", self.goal_obs),
            ("sonar", self.task.sonar),
            ("motion", self.motion_obs),
            ("latch", self.obstacle_latch is not None),
        )
        return tuple(name for name, on in wanted if on)

    @property
    def n_substeps(self) -> int:
        """Integrator substeps per control period: the fewest with h <= ``MAX_SUBSTEP`` s."""
        return max(1, int(math.ceil(self.dt / MAX_SUBSTEP - 1e-9)))

    @property
    def path_length(self) -> float:
        """Arc length of the path (m)."""
        if self.task.path_kind == PATH_SINE:
            return sine_arc_length(self.length, self.amplitude, self.wavelength)
        return self.length

    @property
    def max_steps(self) -> int:
        return max(1, int(math.ceil(self.max_episode_seconds / self.dt - 1e-9)))

    @property
    def target(self) -> tuple[float, float]:
        if self.task.path_kind == PATH_SINE:
            k = 2.0 * math.pi / self.wavelength
            return (self.length, self.amplitude * math.sin(k * self.length))
        return (self.length, 0.0)

    @property
    def has_sonar(self) -> bool:
        return self.task.sonar

    def fixed_obstacles(self) -> np.ndarray | None:
        """The layout when it does not change between episodes, else None."""
        if self.obstacles is not None:
            return self.obstacles
        if self.layout is not None:
            return None
        if self.task.layout == "none":
            return np.zeros((0, 3))
        if self.task.layout == "fixed":
            return np.asarray(self.task.obstacles, dtype=np.float64).reshape(-1, 3)
        return None


#: The keyword arguments of every task: the fields of :class:`EnvConfig` but ``task``.
ARGUMENTS: tuple[str, ...] = tuple(f.name for f in fields(EnvConfig) if f.name != "task")
#: Their defaults (None: the task's).
DEFAULTS: dict[str, Any] = {f.name: f.default for f in fields(EnvConfig) if f.name != "task"}


def _obstacles(value: Any) -> np.ndarray:
    allowed = "a sequence of (x, y, radius) triples of finite floats with radius > 0"
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise _bad("obstacles", value, allowed) from None
    if arr.size == 0:
        return np.zeros((0, 3))
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise _bad("obstacles", value, allowed)
    if not np.all(np.isfinite(arr)) or np.any(arr[:, 2] <= 0):
        raise _bad("obstacles", value, allowed)
    start_d = np.hypot(arr[:, 0], arr[:, 1]) - arr[:, 2]
    if np.any(start_d <= 2.0):
        raise _bad(
            "obstacles",
            value,
            "no obstacle surface within 2 m of the start point (0, 0) (that is a collision)",
        )
    return arr.copy()


def _boolean(name: str, value: Any) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise _bad(name, value, "True or False")
    return bool(value)


def _in_range(name: str, value: Any, low: float, high: float, unit: str) -> float:
    allowed = f"a float in [{low}, {high}] ({unit})"
    out = _finite_float(name, value, allowed)
    if not low <= out <= high:
        raise _bad(name, out, allowed)
    return out


def _check_path(task: TaskSpec, args: dict[str, Any]) -> dict[str, Any]:
    min_len = 60.0 if task.layout not in ("none", "fixed") else 10.0
    length = _finite_float("length", args.get("length", task.length), f"a float >= {min_len}")
    if length < min_len or length > 10000.0:
        raise _bad("length", length, f"a float in [{min_len}, 10000] (m)")
    amplitude = _in_range("amplitude", args.get("amplitude", task.amplitude), -50.0, 50.0, "m")
    wavelength = _finite_float(
        "wavelength", args.get("wavelength", task.wavelength), "a float >= 20"
    )
    if wavelength < 20.0:
        raise _bad("wavelength", wavelength, "a float >= 20 (m)")
    obstacles = args.get("obstacles")
    layout = args.get("layout")
    if layout is not None and layout not in LAYOUT_CODES:
        raise _bad("layout", layout, f"None or one of {sorted(LAYOUT_CODES)}")
    if layout is not None and obstacles is not None:
        raise _bad("layout", layout, "None when obstacles are given")
    corridor = args.get("corridor")
    if corridor is not None:
        corridor = _in_range("corridor", corridor, 1.0, 100.0, "m, the half-width d_L")
    return {
        "corridor": corridor,
        "layout": layout,
        "length": length,
        "amplitude": amplitude,
        "wavelength": wavelength,
        "obstacles": None if obstacles is None else _obstacles(obstacles),
    }


def _check_world(args: dict[str, Any]) -> dict[str, Any]:
    current = _pair(
        "current", args.get("current", DEFAULTS["current"]), "(vx, vy) finite floats in m/s"
    )
    if math.hypot(*current) > 2.0:
        raise _bad("current", args["current"], "(vx, vy) with speed <= 2 m/s")
    start_noise = _pair(
        "start_noise",
        args.get("start_noise", DEFAULTS["start_noise"]),
        "(position_std_m, heading_std_rad), both finite and >= 0",
        nonneg=True,
    )
    vehicle = args.get("vehicle", DEFAULTS["vehicle"])
    if not isinstance(vehicle, str) or vehicle not in VEHICLES:
        raise _bad("vehicle", vehicle, f"one of {list(VEHICLES)}")
    lo, hi = CONTROL_PERIOD_RANGE
    period = _in_range(
        "control_period", args.get("control_period", DEFAULTS["control_period"]), lo, hi, "s"
    )
    return {
        "current": current,
        "start_noise": start_noise,
        "vehicle": vehicle,
        "control_period": period,
    }


def _check_sonar(args: dict[str, Any]) -> dict[str, Any]:
    sonar_noise = _finite_float(
        "sonar_noise", args.get("sonar_noise", DEFAULTS["sonar_noise"]), "a finite float >= 0 (m)"
    )
    if sonar_noise < 0:
        raise _bad("sonar_noise", sonar_noise, "a finite float >= 0 (m)")
    q = args.get("sonar_sectors", DEFAULTS["sonar_sectors"])
    if isinstance(q, bool) or not isinstance(q, (int, np.integer)) or not 1 <= q <= MAX_SECTORS:
        raise _bad("sonar_sectors", q, f"an int in [1, {MAX_SECTORS}]")
    span = _finite_float(
        "sonar_span", args.get("sonar_span", DEFAULTS["sonar_span"]), "a float in (0, 2 pi]"
    )
    if not 0.0 < span <= 2.0 * math.pi + 1e-12:
        raise _bad("sonar_span", span, "a float in (0, 2 pi] (rad)")
    sonar_range = _finite_float(
        "sonar_range", args.get("sonar_range", DEFAULTS["sonar_range"]), "a float > 0"
    )
    if sonar_range <= 0:
        raise _bad("sonar_range", sonar_range, "a float > 0 (m)")
    return {
        "sonar_noise": sonar_noise,
        "sonar_sectors": int(q),
        "sonar_span": span,
        "sonar_range": sonar_range,
    }


def _check_latch(task: TaskSpec, value: Any) -> tuple[float, float] | None:
    """``obstacle_latch``: None, or ``(on, off)`` finite metres with 0 < on <= off, on a task
    with a sonar."""
    if value is None:
        return None
    allowed = "None or (on, off) in metres with 0 < on <= off (a task with a sonar)"
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 2:
        raise _bad("obstacle_latch", value, allowed)
    on, off = (_finite_float("obstacle_latch", v, allowed) for v in value)
    if not 0 < on <= off or not task.sonar:
        raise _bad("obstacle_latch", value, allowed)
    return (on, off)


def _check_interface(task: TaskSpec, args: dict[str, Any]) -> dict[str, Any]:
    """Actions, observation parts, rendering and the heading reference."""
    render_mode = args.get("render_mode")
    if render_mode not in (None, "rgb_array"):
        raise _bad("render_mode", render_mode, "None or 'rgb_array'")
    heading_reference = args.get("heading_reference", task.heading_reference)
    if not isinstance(heading_reference, str) or heading_reference not in HEADING_REFERENCES:
        raise _bad("heading_reference", heading_reference, f"one of {list(HEADING_REFERENCES)}")
    out = {
        "continuous": _boolean("continuous", args.get("continuous", DEFAULTS["continuous"])),
        "motion_obs": _boolean("motion_obs", args.get("motion_obs", DEFAULTS["motion_obs"])),
        "render_mode": render_mode,
        "heading_reference": heading_reference,
        "los_lookahead": _in_range(
            "los_lookahead",
            args.get("los_lookahead", DEFAULTS["los_lookahead"]),
            *LOOKAHEAD_RANGE,
            "m",
        ),
        "path_obs": _boolean("path_obs", args.get("path_obs", task.path_obs)),
        "goal_obs": _boolean("goal_obs", args.get("goal_obs", task.goal_obs)),
        "goal_offset": _boolean("goal_offset", args.get("goal_offset", DEFAULTS["goal_offset"])),
    }
    heading_rule = args.get("heading_rule", task.heading_rule or heading_reference)
    if not isinstance(heading_rule, str) or heading_rule not in HEADING_REFERENCES:
        raise _bad("heading_rule", heading_rule, f"one of {list(HEADING_REFERENCES)}")
    out["heading_rule"] = heading_rule
    goal_distance = args.get("goal_distance", task.goal_distance)
    if goal_distance is not None:
        goal_distance = _in_range("goal_distance", goal_distance, 1.0, 1000.0, "m")
    out["goal_distance"] = goal_distance
    if out["goal_offset"] and not out["goal_obs"]:
        raise _bad("goal_offset", True, "False when goal_obs is False (it extends the goal part)")
    if not (out["path_obs"] or out["goal_obs"]):
        raise _bad(
            "path_obs", False, "True when goal_obs is False (the observation needs a heading)"
        )
    return out


#: ``progress_along`` values: the path's tangent, the LOS course.
PROGRESS_DIRECTIONS = ("path", "course")


def _choice(args: dict[str, Any], name: str, allowed: tuple[str, ...]) -> str:
    """Argument ``name`` (its default when absent), one of the strings ``allowed``."""
    value = args.get(name, DEFAULTS[name])
    if not isinstance(value, str) or value not in allowed:
        raise _bad(name, value, f"one of {list(allowed)}")
    return value


def _non_negative(args: dict[str, Any], name: str) -> float:
    """Argument ``name`` (its default when absent) as a finite float >= 0."""
    value = _finite_float(name, args.get(name, DEFAULTS[name]), "a finite float >= 0")
    if value < 0:
        raise _bad(name, value, "a finite float >= 0")
    return value


def _check_reward(args: dict[str, Any]) -> dict[str, Any]:
    return {
        "success_reward": _non_negative(args, "success_reward"),
        "obstacle_penalty": _non_negative(args, "obstacle_penalty"),
        "progress_weighted": _boolean(
            "progress_weighted", args.get("progress_weighted", DEFAULTS["progress_weighted"])
        ),
        "progress_along": _choice(args, "progress_along", PROGRESS_DIRECTIONS),
        "arrival_gate": _arrival_gate(args.get("arrival_gate", DEFAULTS["arrival_gate"])),
    }


def _arrival_gate(value: Any) -> float | None:
    """``arrival_gate``: None, or metres in [TARGET_RADIUS, 100]."""
    if value is None:
        return None
    return _in_range("arrival_gate", value, TARGET_RADIUS, 100.0, "m from the target point")


def make_config(task_name: str, **kwargs: Any) -> EnvConfig:
    """Check the keyword arguments of task ``task_name`` (see :class:`EnvConfig`) and resolve
    the defaults that depend on the task."""
    if task_name not in TASKS:
        raise ValueError(f"task={task_name!r} is not allowed: expected one of {sorted(TASKS)}")
    task = TASKS[task_name]
    unknown = sorted(set(kwargs) - set(ARGUMENTS))
    if unknown:
        raise ValueError(
            f"{unknown[0]}={kwargs[unknown[0]]!r} is not allowed: unknown argument; "
            f"expected one of {sorted(ARGUMENTS)}"
        )
    config = EnvConfig(
        task=task,
        **_check_path(task, kwargs),
        **_check_world(kwargs),
        **_check_sonar(kwargs),
        **_check_interface(task, kwargs),
        **_check_reward(kwargs),
        obstacle_latch=_check_latch(task, kwargs.get("obstacle_latch")),
    )
    default_t = TIME_LIMIT_FACTOR * config.path_length / U_REF
    t_max = _finite_float(
        "max_episode_seconds", kwargs.get("max_episode_seconds", default_t), "a float > 0 (s)"
    )
    if t_max <= 0:
        raise _bad("max_episode_seconds", t_max, "a float > 0 (s)")
    return replace(config, max_episode_seconds=t_max)
