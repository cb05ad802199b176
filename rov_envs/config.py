"""Keyword arguments of the rov_envs tasks, checked and resolved into an :class:`EnvConfig`.

Every bad value raises ``ValueError`` naming the argument, the bad value and what is allowed.
The same configuration drives the single environment and the batched one, so both see exactly
the same task.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from rov_envs.physics.dynamics import DEFAULT_CONTROL_PERIOD
from rov_envs.physics.guidance import DEFAULT_LOOKAHEAD
from rov_envs.physics.params import DEFAULT_VEHICLE, VEHICLES
from rov_envs.tasks import HEADING_REFERENCES, PATH_SINE, TASKS, TaskSpec

#: Control period (s): one environment step, the physics' default (0.2 s, 4 ETDRK4 substeps).
CONTROL_PERIOD = DEFAULT_CONTROL_PERIOD
#: Shortest and longest control periods accepted (s) (``control_period``).
CONTROL_PERIOD_RANGE = (0.05, 1.0)
#: Longest integrator substep (s): the physics' default, 0.2 s in 4 substeps.
MAX_SUBSTEP = DEFAULT_CONTROL_PERIOD / 4
#: Reference speed (m/s) for the default time limit and the progress reward.
U_REF = 1.0
#: Default time limit = TIME_LIMIT_FACTOR * (path arc length / U_REF).
TIME_LIMIT_FACTOR = 2.0
#: Sonar defaults (CONTRACTS.md): span pi centred ahead, 9 sectors, 25 m range.
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
    if isinstance(value, bool):
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
    """A task with every keyword argument resolved (see :func:`make_config`)."""

    task: TaskSpec
    length: float
    amplitude: float
    wavelength: float
    obstacles: np.ndarray | None  # custom fixed layout (M, 3), or None for the task's layout
    current: tuple[float, float]
    sonar_noise: float
    start_noise: tuple[float, float]
    sonar_sectors: int
    sonar_span: float
    sonar_range: float
    continuous: bool
    max_episode_seconds: float
    render_mode: str | None
    success_reward: float = 200.0
    dt: float = CONTROL_PERIOD
    vehicle: str = DEFAULT_VEHICLE
    motion_obs: bool = False
    progress_weighted: bool = False
    heading_reference: str = "path"
    los_lookahead: float = DEFAULT_LOOKAHEAD
    path_obs: bool = True
    goal_obs: bool = False

    @property
    def obs_parts(self) -> tuple[str, ...]:
        """Names of the observation's parts, in the order of the ``Dict`` space."""
        wanted = (
            ("path", self.path_obs),
            ("goal", self.goal_obs),
            ("sonar", self.task.sonar),
            ("motion", self.motion_obs),
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
        if self.task.layout == "none":
            return np.zeros((0, 3))
        if self.task.layout == "fixed":
            return np.asarray(self.task.obstacles, dtype=np.float64).reshape(-1, 3)
        return None


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


def make_config(task_name: str, **kwargs: Any) -> EnvConfig:
    """Check the keyword arguments of task ``task_name`` and resolve the defaults.

    Arguments (all optional):
        obstacles: ``[(x, y, radius), ...]`` in metres: a custom fixed layout replacing the task's.
        current: ``(vx, vy)`` world-frame water velocity in m/s (default ``(0, 0)``), |v| <= 2.
        sonar_noise: std (m) of Gaussian noise on each sonar return (default 0).
        start_noise: ``(position_std_m, heading_std_rad)`` of the Gaussian start-pose
            perturbation (default ``(0, 0)``).
        length: path length along x (m); amplitude, wavelength: sine path shape (m).
        sonar_sectors (q, default 9), sonar_span (S, rad, default pi), sonar_range (m, default 25).
        continuous: Box(-1, 1, (2,)) (surge, yaw) actions instead of Discrete(5).
        max_episode_seconds: time limit in simulated seconds (default: twice the path's arc
            length at 1 m/s).
        render_mode: None or ``"rgb_array"``.
        success_reward: reward added on the step that reaches the target (default 200; our
            addition to eq. 21, see :mod:`rov_envs.rewards`; 0 gives the paper's reward literally).
        vehicle: the BlueROV2 parameter set, one of ``rov_envs.physics.params.VEHICLES``:
            ``"uuv_simulator"`` (default, the paper's Gazebo model) or ``"wu2018"`` (Wu 2018).
        motion_obs: add a ``"motion"`` part to the observation: (sway v in m/s, yaw rate r in
            rad/s) in the body frame, clipped to (+-3 m/s, +-2 rad/s) (default False).
        control_period: seconds per environment step, in [0.05, 1] (default ``CONTROL_PERIOD``,
            0.2 s); the physics takes as many substeps as keep each at most 0.05 s.
        progress_weighted: pay r_c of eq. 18/19 (when positive) in proportion to the step's
            progress along the path, as a fraction of 1 m/s (default False; not in the paper,
            see :mod:`rov_envs.rewards`): without it, staying near the path pays as much as
            following it, and stopping short of an obstacle beats passing it.
        heading_reference: ``"path"`` (a_c from the LOS course, eq. 16) or ``"goal"`` (a_c
            from the bearing to the target point); default: the task's (``"goal"`` for
            ObstacleAvoidance, whose policy avoids obstacles on its way to a goal rather than
            following a path; ``"path"`` for every other task).
        los_lookahead: the LOS lookahead distance Delta of eq. 16 in metres, in [0.5, 100]
            (default 5; the paper gives none): the desired course points at the path point
            Delta ahead of the closest one, so a vehicle d metres off the path is steered back
            at atan(d / Delta).
        path_obs: observe the "path" part [a_c / pi, g / d_L] (default: the task's; True for
            every task but ObstacleAvoidance).
        goal_obs: observe the "goal" part [heading deviation from the bearing to the target
            point / pi] (default: the task's; True for ObstacleAvoidance only).
    """
    if task_name not in TASKS:
        raise ValueError(f"task={task_name!r} is not allowed: expected one of {sorted(TASKS)}")
    task = TASKS[task_name]
    known = {
        "obstacles",
        "current",
        "sonar_noise",
        "start_noise",
        "length",
        "amplitude",
        "wavelength",
        "sonar_sectors",
        "sonar_span",
        "sonar_range",
        "continuous",
        "max_episode_seconds",
        "render_mode",
        "success_reward",
        "vehicle",
        "motion_obs",
        "control_period",
        "progress_weighted",
        "heading_reference",
        "los_lookahead",
        "path_obs",
        "goal_obs",
    }
    unknown = sorted(set(kwargs) - known)
    if unknown:
        raise ValueError(
            f"{unknown[0]}={kwargs[unknown[0]]!r} is not allowed: unknown argument; "
            f"expected one of {sorted(known)}"
        )
    min_len = 60.0 if task.layout not in ("none", "fixed") else 10.0
    length = _finite_float("length", kwargs.get("length", task.length), f"a float >= {min_len}")
    if length < min_len or length > 10000.0:
        raise _bad("length", length, f"a float in [{min_len}, 10000] (m)")
    amplitude = _finite_float(
        "amplitude", kwargs.get("amplitude", task.amplitude), "a float in [0, 50] (m)"
    )
    if not 0.0 <= amplitude <= 50.0:
        raise _bad("amplitude", amplitude, "a float in [0, 50] (m)")
    wavelength = _finite_float(
        "wavelength", kwargs.get("wavelength", task.wavelength), "a float >= 20"
    )
    if wavelength < 20.0:
        raise _bad("wavelength", wavelength, "a float >= 20 (m)")
    obstacles = kwargs.get("obstacles")
    obstacles = None if obstacles is None else _obstacles(obstacles)
    current = _pair("current", kwargs.get("current", (0.0, 0.0)), "(vx, vy) finite floats in m/s")
    if math.hypot(*current) > 2.0:
        raise _bad("current", kwargs["current"], "(vx, vy) with speed <= 2 m/s")
    sonar_noise = _finite_float(
        "sonar_noise", kwargs.get("sonar_noise", 0.0), "a finite float >= 0 (m)"
    )
    if sonar_noise < 0:
        raise _bad("sonar_noise", sonar_noise, "a finite float >= 0 (m)")
    start_noise = _pair(
        "start_noise",
        kwargs.get("start_noise", (0.0, 0.0)),
        "(position_std_m, heading_std_rad), both finite and >= 0",
        nonneg=True,
    )
    q = kwargs.get("sonar_sectors", SONAR_SECTORS)
    if isinstance(q, bool) or not isinstance(q, (int, np.integer)) or not 1 <= q <= MAX_SECTORS:
        raise _bad("sonar_sectors", q, f"an int in [1, {MAX_SECTORS}]")
    span = _finite_float("sonar_span", kwargs.get("sonar_span", SONAR_SPAN), "a float in (0, 2 pi]")
    if not 0.0 < span <= 2.0 * math.pi + 1e-12:
        raise _bad("sonar_span", span, "a float in (0, 2 pi] (rad)")
    rng_ = _finite_float("sonar_range", kwargs.get("sonar_range", SONAR_RANGE), "a float > 0")
    if rng_ <= 0:
        raise _bad("sonar_range", rng_, "a float > 0 (m)")
    continuous = kwargs.get("continuous", False)
    if not isinstance(continuous, (bool, np.bool_)):
        raise _bad("continuous", continuous, "True or False")
    motion_obs = kwargs.get("motion_obs", False)
    if not isinstance(motion_obs, (bool, np.bool_)):
        raise _bad("motion_obs", motion_obs, "True or False")
    render_mode = kwargs.get("render_mode")
    if render_mode not in (None, "rgb_array"):
        raise _bad("render_mode", render_mode, "None or 'rgb_array'")
    success_reward = _finite_float(
        "success_reward", kwargs.get("success_reward", 200.0), "a finite float >= 0"
    )
    if success_reward < 0:
        raise _bad("success_reward", success_reward, "a finite float >= 0")
    lo, hi = CONTROL_PERIOD_RANGE
    dt = _finite_float(
        "control_period",
        kwargs.get("control_period", CONTROL_PERIOD),
        f"a float in [{lo}, {hi}] (s)",
    )
    if not lo <= dt <= hi:
        raise _bad("control_period", dt, f"a float in [{lo}, {hi}] (s)")
    progress_weighted = kwargs.get("progress_weighted", False)
    if not isinstance(progress_weighted, (bool, np.bool_)):
        raise _bad("progress_weighted", progress_weighted, "True or False")
    heading_reference = kwargs.get("heading_reference", task.heading_reference)
    if not isinstance(heading_reference, str) or heading_reference not in HEADING_REFERENCES:
        raise _bad("heading_reference", heading_reference, f"one of {list(HEADING_REFERENCES)}")
    los_lookahead = _finite_float(
        "los_lookahead", kwargs.get("los_lookahead", DEFAULT_LOOKAHEAD), "a float in [0.5, 100] (m)"
    )
    if not 0.5 <= los_lookahead <= 100.0:
        raise _bad("los_lookahead", los_lookahead, "a float in [0.5, 100] (m)")
    path_obs = kwargs.get("path_obs", task.path_obs)
    goal_obs = kwargs.get("goal_obs", task.goal_obs)
    for name, value in (("path_obs", path_obs), ("goal_obs", goal_obs)):
        if not isinstance(value, (bool, np.bool_)):
            raise _bad(name, value, "True or False")
    if not (path_obs or goal_obs):
        raise _bad(
            "path_obs", path_obs, "True when goal_obs is False (the observation needs a heading)"
        )
    vehicle = kwargs.get("vehicle", DEFAULT_VEHICLE)
    if not isinstance(vehicle, str) or vehicle not in VEHICLES:
        raise _bad("vehicle", vehicle, f"one of {list(VEHICLES)}")
    base = EnvConfig(
        task=task,
        length=length,
        amplitude=amplitude,
        wavelength=wavelength,
        obstacles=obstacles,
        current=current,
        sonar_noise=sonar_noise,
        start_noise=start_noise,
        sonar_sectors=int(q),
        sonar_span=span,
        sonar_range=rng_,
        continuous=bool(continuous),
        max_episode_seconds=1.0,
        render_mode=render_mode,
        success_reward=success_reward,
        vehicle=vehicle,
        motion_obs=bool(motion_obs),
        dt=dt,
        progress_weighted=bool(progress_weighted),
        heading_reference=heading_reference,
        los_lookahead=los_lookahead,
        path_obs=bool(path_obs),
        goal_obs=bool(goal_obs),
    )
    default_t = TIME_LIMIT_FACTOR * base.path_length / U_REF
    t_max = _finite_float(
        "max_episode_seconds", kwargs.get("max_episode_seconds", default_t), "a float > 0 (s)"
    )
    if t_max <= 0:
        raise _bad("max_episode_seconds", t_max, "a float > 0 (s)")
    return EnvConfig(**{**base.__dict__, "max_episode_seconds": t_max})
