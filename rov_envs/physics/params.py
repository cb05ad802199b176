"""BlueROV2 model parameters (paper eq. (3)-(7)): two published sets, selectable by name.

Frames (see ``rov_envs.physics.dynamics``): world x along the straight path, y to its left, z up;
body frame forward-left-up (FLU). Diagonal mass, added-mass and damping coefficients are the same
in FLU and in the NED/FRD convention some sources use (flipping y and z leaves diagonal quadratic
forms unchanged); vectors such as the centre of gravity flip the sign of z.

Vehicles (:data:`VEHICLES`, :func:`vehicle_params`; the environments' ``vehicle=`` argument):

``"uuv_simulator"`` (default; :meth:`BlueROV2Params.uuv_simulator`): the BlueROV2 of UUV
Simulator's ``bluerov2_description`` package, the Gazebo model the paper ran (section 4.1).
Source files: ``urdf/base.xacro`` (mass, bounding box, inertia formula), ``urdf/gazebo.xacro``
(hydrodynamic model: added mass, damping, centre of buoyancy, volume; values cited there from
Berg 2012), ``urdf/snippets.xacro`` (thruster model), ``urdf/actuators.xacro`` (thruster poses);
read from the public UUVControl/bluerov2 repository.

* mass m = 10 kg; centre of gravity at the origin (``cog = 0 0 0``), so M_RB is diagonal.
* inertia of a solid box 0.448 x 0.2384 x 0.28066 m written as 0.2 m (a^2 + b^2) per axis:
  Ix = 0.2 * 10 * (0.2384^2 + 0.28066^2) = 0.27121, Iy = 0.2 * 10 * (0.448^2 + 0.28066^2) =
  0.55895, Iz = 0.2 * 10 * (0.448^2 + 0.2384^2) = 0.51508 kg m^2.
* added mass diag(1.7182, 0, 5.468, 0, 1.2481, 0.4006) (kg, kg m^2).
* linear damping diag(11.7391, 20, 31.8678, 25, 44.9085, 5) (N s/m, N m s/rad); no quadratic
  damping (``quadratic_damping`` all 0 in gazebo.xacro).
* centre of buoyancy (0, 0, 0.3) m, 30 cm above the centre of gravity (``cob = 0.0 0.0 0.3`` in
  gazebo.xacro; its comment reads Berg's (0.0822, -0.00773, 0.3872) as NWU and keeps only z).
* buoyancy: the description's volume 0.011054 m^3 at rho = 1028 kg/m^3 gives B = 111.48 N
  against W = 98.1 N (``uuv_simulator(neutrally_buoyant=False)``); the 2D tasks run neutrally
  buoyant (B = W), as for Wu's set below.
* thrusters: first-order lag, ``dyn_time_constant = 0.05`` s; the same poses as Wu's set below
  (actuators.xacro), renumbered the same way. The description's ``rotor_constant`` 1e-5 is not
  used (see *Thrust calibration*).
* Properties that matter for control: the vehicle is directionally stable (no sway added mass,
  yaw damping 5) and turns slowly with Table 1's one-sided commands (about 0.16 / 0.27 rad/s for
  Turn 1 / Turn 2, in a circle of about 1.8 m radius for Turn 2); roll and pitch are stiff
  (Ix / K_p = 0.011 s, (Iy + M_qdot) / M_q = 0.040 s), which the integrator handles by
  integrating the linear damping exactly (:mod:`rov_envs.physics.integrator`).

``"wu2018"`` (:meth:`BlueROV2Params.wu2018`): Wu (2018), "A 6-DOF dynamic model of BlueROV2"
(the set also used by OsloMet-OceanLab/BlueROV2 and Robotic-Decision-Making-Lab/blue): m = 11.5
kg, W = 112.8 N, B = 114.8 N, r_g = (0, 0, 0.02) m NED (below the origin), inertia 0.16 kg m^2
per axis, added mass (5.5, 12.7, 14.57, 0.12, 0.12, 0.12), linear damping (4.03, 6.22, 5.18,
0.07, 0.07, 0.07), quadratic damping (18.18, 21.66, 36.99, 1.55, 1.55, 1.55). Our departures:

* **Metacentric height.** Wu's set puts the centre of gravity 2 cm below the body origin and the
  centre of buoyancy at the origin (2 cm righting arm). In full 6-DOF with no attitude control that
  is pitch-unstable under "Go straight": the added-mass Munk moment ``u w (Z_wdot - X_udot)``
  beats the 2 cm righting arm and the vehicle loops. We keep Wu's centre of gravity
  (``r_g = (0, 0, -0.02)`` m in FLU) and put the centre of buoyancy 8 cm above the origin
  (``r_b = (0, 0, 0.08)`` m), a metacentric height ``z_b - z_g = 0.10`` m (the value of a widely
  used BlueROV2 NMPC parameter set). The thrusters sit 7.25 cm below the origin, so at the 1 m/s
  cruise the thrust/drag couple (0.0725 m x 22.2 N) is balanced by a steady nose-up pitch of
  asin(1.61 / (W * 0.10)) = 8.2 deg.
* **Buoyancy.** The paper's tasks are 2D with T5 = T6 = 0 (Table 1), so with W = 112.8 N and
  B = 114.8 N the vehicle would rise at about 0.3 m/s. The preset is **neutrally buoyant**
  (``B = W = m g``); ``BlueROV2Params.wu2018(neutrally_buoyant=False)`` keeps Wu's B = 114.8 N.
* **Thruster lag** time constant 0.1 s (Wu gives none; UUV Simulator uses 0.05-0.2 s).
* **Directional (sway-yaw) instability -- a property of this parameter set, not a bug.** Wu's
  set is diagonal with sway added mass (12.7 kg) far above surge added mass (5.5 kg) and almost
  no yaw damping (N_r = -0.07). The added-mass Munk moment (Y_vdot - X_udot) u v of C_A (eq. 5)
  then turns the vehicle away from its velocity: linearised about straight running at 1 m/s the
  sway-yaw pair has an eigenvalue of about +4 1/s. Straight running under "Go straight" exists
  only by exact symmetry (an aligned start stays exactly straight); after any turn "Go straight"
  settles into a steady spin (u = 0.53 m/s, v = -/+0.55 m/s, r = +/-1.14 rad/s). Heading must be
  held actively (agents do it by alternating Table 1 turns). Table 1 turns nearly pivot (about
  1.0 / 1.4 rad/s for Turn 1 / Turn 2).

Common to both sets:

* **Thruster numbering.** T1 front-left, T2 front-right, T3 rear-left, T4 rear-right (horizontal,
  vectored at 45 degrees), T5 left vertical, T6 right vertical, at UUV Simulator's poses. With
  this numbering Table 1 means what it says: "Go straight" (8000, 8000, -8000, -8000) gives pure
  surge, "Turn left" (T2, T4) a positive (counter-clockwise) yaw moment. (UUV Simulator's ids put
  T1 front-right, which would make the paper's "Turn left" turn right.)
* **Thruster model.** First-order lag ``n_dot = (n_cmd - n) / thruster_time_constant`` on the
  commanded speed (rev/min, the paper's unit goes straight in, as in UUV Simulator), then
  ``thrust = k |n| n`` (paper eq. (7) with K(s) the lag and F the quadratic map).
* **Thrust calibration.** UUV Simulator's public k = 1e-5 would give 640 N per thruster at
  8000 rev/min. Each preset calibrates k (:func:`thrust_coefficient_for_speed`) so that "Go
  straight" cruises at exactly 1.0 m/s: steady surge solves ``X_u u + X_u|u| u|u| = X`` and the
  four horizontal thrusters each contribute cos(45 deg) of their thrust to X, so
  ``k = (X_u + X_u|u|) / (4 cos(45 deg) 8000^2)``: UUV Simulator X = 11.7391 N, k = 6.4850e-8;
  Wu X = 4.03 + 18.18 = 22.21 N, k = 1.2270e-7 N/(rev/min)^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

__all__ = [
    "BlueROV2Params",
    "VEHICLES",
    "DEFAULT_VEHICLE",
    "vehicle_params",
    "vehicle_code",
    "GRAVITY",
    "CRUISE_SPEED",
    "MAX_THRUSTER_SPEED",
    "THRUSTER_POSITIONS",
    "THRUSTER_DIRECTIONS",
    "UUV_SIMULATOR_THRUST_COEFFICIENT",
    "WU2018_THRUST_COEFFICIENT",
    "P_MINV",
    "P_MASS",
    "P_WEIGHT",
    "P_BUOYANCY",
    "P_RG",
    "P_RB",
    "P_INERTIA",
    "P_ADDED",
    "P_DLIN",
    "P_DQUAD",
    "P_ALLOC",
    "P_THRUST_K",
    "P_INV_TAU",
    "P_LDIAG",
    "P_SIZE",
    "thrust_coefficient_for_speed",
]

GRAVITY: float = 9.81
"""Gravitational acceleration, m/s^2."""

MAX_THRUSTER_SPEED: float = 8000.0
"""Largest thruster speed used by the paper's Table 1, rev/min."""

CRUISE_SPEED: float = 1.0
"""Steady surge speed (m/s) that "Go straight" reaches with each preset's thrust coefficient."""

VEHICLES: tuple[str, ...] = ("uuv_simulator", "wu2018")
"""Names of the parameter presets; a vehicle's kernel code is its index here."""

DEFAULT_VEHICLE: str = "uuv_simulator"
"""The vehicle every environment runs unless told otherwise (the paper's Gazebo model)."""

_C45 = math.cos(math.pi / 4.0)

# Thruster poses, body frame forward-left-up (metres), from UUV Simulator's BlueROV2 description,
# renumbered T1 front-left, T2 front-right, T3 rear-left, T4 rear-right, T5 left vertical,
# T6 right vertical. Directions are the force direction for a positive speed command.
THRUSTER_POSITIONS: tuple[tuple[float, float, float], ...] = (
    (0.1355, 0.1, -0.0725),  # T1 front-left
    (0.1355, -0.1, -0.0725),  # T2 front-right
    (-0.1475, 0.1, -0.0725),  # T3 rear-left
    (-0.1475, -0.1, -0.0725),  # T4 rear-right
    (0.0025, 0.1105, -0.005),  # T5 left vertical
    (0.0025, -0.1105, -0.005),  # T6 right vertical
)
THRUSTER_DIRECTIONS: tuple[tuple[float, float, float], ...] = (
    (_C45, -_C45, 0.0),  # T1: forward and towards the centre line (right)
    (_C45, _C45, 0.0),  # T2: forward and towards the centre line (left)
    (-_C45, -_C45, 0.0),  # T3: backward-right; a negative command pushes forward-left
    (-_C45, _C45, 0.0),  # T4: backward-left; a negative command pushes forward-right
    (0.0, 0.0, 1.0),  # T5 up
    (0.0, 0.0, 1.0),  # T6 up
)


def thrust_coefficient_for_speed(
    *,
    x_u: float,
    x_uu: float,
    speed: float = CRUISE_SPEED,
    n_cmd: float = MAX_THRUSTER_SPEED,
) -> float:
    """k such that "Go straight" (horizontal thrusters at +-n_cmd) gives steady surge ``speed``.

    ``x_u``, ``x_uu``: the vehicle's linear and quadratic surge damping magnitudes (N s/m,
    N s^2/m^2). Steady surge: ``x_u u + x_uu u|u| = X`` with ``X = 4 cos(45 deg) k n_cmd^2``.
    """
    if not (speed > 0.0 and n_cmd > 0.0):
        raise ValueError(f"speed and n_cmd must be positive, got speed={speed}, n_cmd={n_cmd}")
    if not (x_u >= 0.0 and x_uu >= 0.0 and x_u + x_uu > 0.0):
        raise ValueError(
            f"x_u={x_u!r}, x_uu={x_uu!r} are not allowed: expected non-negative surge damping "
            "magnitudes, not both zero"
        )
    surge_force = x_u * speed + x_uu * speed * abs(speed)
    return surge_force / (4.0 * _C45 * n_cmd * n_cmd)


# ---- UUV Simulator's bluerov2_description (module docstring) ----
_UUV_MASS = 10.0
_UUV_BOX = (0.448, 0.2384, 0.28066)  # x, y, z size of the bounding box, m
_UUV_VOLUME = 0.011054  # m^3
_UUV_RHO = 1028.0  # kg/m^3
_UUV_LINEAR_DAMPING = (11.7391, 20.0, 31.8678, 25.0, 44.9085, 5.0)
UUV_SIMULATOR_THRUST_COEFFICIENT: float = thrust_coefficient_for_speed(
    x_u=_UUV_LINEAR_DAMPING[0], x_uu=0.0
)
"""k of the UUV Simulator preset, N/(rev/min)^2 (= 6.4850e-8): "Go straight" cruises at 1 m/s."""

# ---- Wu (2018) (module docstring) ----
_WU_MASS = 11.5
_WU_BUOYANCY = 114.8  # N
_WU_LINEAR_DAMPING = (4.03, 6.22, 5.18, 0.07, 0.07, 0.07)
_WU_QUADRATIC_DAMPING = (18.18, 21.66, 36.99, 1.55, 1.55, 1.55)
WU2018_THRUST_COEFFICIENT: float = thrust_coefficient_for_speed(
    x_u=_WU_LINEAR_DAMPING[0], x_uu=_WU_QUADRATIC_DAMPING[0]
)
"""k of the Wu (2018) preset, N/(rev/min)^2 (= 1.2270e-7): "Go straight" cruises at 1 m/s."""


def _box_inertia(mass: float, box: tuple[float, float, float]) -> tuple[float, float, float]:
    """0.2 m (a^2 + b^2) per axis, as UUV Simulator's base.xacro writes it."""
    x, y, z = box
    return (
        0.2 * mass * (y * y + z * z),
        0.2 * mass * (x * x + z * z),
        0.2 * mass * (x * x + y * y),
    )


# ---- layout of BlueROV2Params.to_array() (float64), read by the numba kernels ----
P_MINV = 0  # 36: inverse of M = M_RB + M_A (eq. 4), row-major
P_MASS = 36  # m, kg
P_WEIGHT = 37  # W, N
P_BUOYANCY = 38  # B, N
P_RG = 39  # 3: centre of gravity, body FLU, m
P_RB = 42  # 3: centre of buoyancy, body FLU, m
P_INERTIA = 45  # 3: Ix, Iy, Iz about the body origin, kg m^2
P_ADDED = 48  # 6: added mass magnitudes -X_udot, -Y_vdot, -Z_wdot, -K_pdot, -M_qdot, -N_rdot
P_DLIN = 54  # 6: linear damping magnitudes -X_u, ..., -N_r
P_DQUAD = 60  # 6: quadratic damping magnitudes -X_u|u|, ..., -N_r|r|
P_ALLOC = 66  # 36: allocation matrix T (tau = T f), row-major, rows X Y Z K M N, cols T1..T6
P_THRUST_K = 102  # k in thrust = k |n| n
P_INV_TAU = 103  # 1 / thruster time constant, 1/s
P_LDIAG = 104  # 6: diagonal of M^-1 D_lin, 1/s (the part the integrator solves exactly)
P_SIZE = 110


def _skew(a: np.ndarray) -> np.ndarray:
    """S(a) with S(a) b = a x b (Fossen 2011, eq. 2.10)."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


@dataclass(frozen=True)
class BlueROV2Params:
    """Physical parameters of a BlueROV2 in the FLU body frame (module docstring).

    The field defaults are the default vehicle's set, UUV Simulator's (neutrally buoyant, k
    calibrated for 1.0 m/s): ``BlueROV2Params() == BlueROV2Params.uuv_simulator()``. Use the
    presets :meth:`uuv_simulator` and :meth:`wu2018` (or :func:`vehicle_params` by name) and
    :meth:`replace` to change single values; k is not recalibrated by ``replace``.
    Damping and added-mass values are stored as positive magnitudes (the hydrodynamic derivatives
    are negative).
    """

    mass: float = _UUV_MASS
    weight: float = _UUV_MASS * GRAVITY  # 98.1 N
    buoyancy: float = _UUV_MASS * GRAVITY  # neutrally buoyant (the description: 111.48 N)
    r_g: tuple[float, float, float] = (0.0, 0.0, 0.0)
    r_b: tuple[float, float, float] = (0.0, 0.0, 0.3)
    inertia: tuple[float, float, float] = _box_inertia(_UUV_MASS, _UUV_BOX)
    added_mass: tuple[float, ...] = (1.7182, 0.0, 5.468, 0.0, 1.2481, 0.4006)
    linear_damping: tuple[float, ...] = _UUV_LINEAR_DAMPING
    quadratic_damping: tuple[float, ...] = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    thruster_positions: tuple[tuple[float, float, float], ...] = THRUSTER_POSITIONS
    thruster_directions: tuple[tuple[float, float, float], ...] = THRUSTER_DIRECTIONS
    thrust_coefficient: float = UUV_SIMULATOR_THRUST_COEFFICIENT
    thruster_time_constant: float = 0.05
    _array: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name, size in (
            ("r_g", 3),
            ("r_b", 3),
            ("inertia", 3),
            ("added_mass", 6),
            ("linear_damping", 6),
            ("quadratic_damping", 6),
        ):
            value = getattr(self, name)
            if len(value) != size or not all(math.isfinite(float(x)) for x in value):
                raise ValueError(f"{name} must be {size} finite numbers, got {value!r}")
        for name in ("mass", "weight", "thruster_time_constant", "thrust_coefficient"):
            value = float(getattr(self, name))
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name} must be a positive finite number, got {value!r}")
        if not (math.isfinite(self.buoyancy) and self.buoyancy >= 0.0):
            raise ValueError(f"buoyancy must be non-negative and finite, got {self.buoyancy!r}")
        if min(self.inertia) <= 0.0 or min(self.added_mass) < 0.0:
            raise ValueError(
                f"inertia must be positive and added_mass non-negative, got "
                f"inertia={self.inertia!r}, added_mass={self.added_mass!r}"
            )
        if min(self.linear_damping) < 0.0 or min(self.quadratic_damping) < 0.0:
            raise ValueError(
                "damping magnitudes must be non-negative, got "
                f"linear={self.linear_damping!r}, quadratic={self.quadratic_damping!r}"
            )
        if len(self.thruster_positions) != 6 or len(self.thruster_directions) != 6:
            raise ValueError("thruster_positions and thruster_directions must list 6 thrusters")
        object.__setattr__(self, "_array", self._pack())

    @classmethod
    def uuv_simulator(cls, neutrally_buoyant: bool = True) -> BlueROV2Params:
        """UUV Simulator's BlueROV2 (the default vehicle; module docstring).

        ``neutrally_buoyant=False``: the description's buoyancy, 1028 kg/m^3 x 0.011054 m^3 x g
        = 111.48 N against W = 98.1 N.
        """
        b = _UUV_MASS * GRAVITY if neutrally_buoyant else _UUV_RHO * _UUV_VOLUME * GRAVITY
        return cls(buoyancy=b)

    @classmethod
    def wu2018(cls, neutrally_buoyant: bool = True) -> BlueROV2Params:
        """Wu's (2018) set with this package's 0.10 m metacentric height (module docstring).

        ``neutrally_buoyant=False``: Wu's B = 114.8 N against W = 112.8 N (rises at ~0.3 m/s).
        """
        return cls(
            mass=_WU_MASS,
            weight=_WU_MASS * GRAVITY,
            buoyancy=_WU_MASS * GRAVITY if neutrally_buoyant else _WU_BUOYANCY,
            r_g=(0.0, 0.0, -0.02),
            r_b=(0.0, 0.0, 0.08),
            inertia=(0.16, 0.16, 0.16),
            added_mass=(5.5, 12.7, 14.57, 0.12, 0.12, 0.12),
            linear_damping=_WU_LINEAR_DAMPING,
            quadratic_damping=_WU_QUADRATIC_DAMPING,
            thrust_coefficient=WU2018_THRUST_COEFFICIENT,
            thruster_time_constant=0.1,
        )

    def replace(self, **changes: object) -> BlueROV2Params:
        """A copy with some fields changed (``dataclasses.replace``)."""
        return replace(self, **changes)

    @property
    def metacentric_height(self) -> float:
        """z_b - z_g, m (positive = centre of buoyancy above centre of gravity = stable)."""
        return self.r_b[2] - self.r_g[2]

    def rigid_body_mass_matrix(self) -> np.ndarray:
        """M_RB (Fossen 2011, eq. 3.44) about the body origin, FLU."""
        m = self.mass
        s = _skew(np.asarray(self.r_g, dtype=np.float64))
        out = np.zeros((6, 6))
        out[:3, :3] = m * np.eye(3)
        out[:3, 3:] = -m * s
        out[3:, :3] = m * s
        out[3:, 3:] = np.diag(self.inertia)
        return out

    def mass_matrix(self) -> np.ndarray:
        """M = M_RB + M_A (paper eq. (4))."""
        return self.rigid_body_mass_matrix() + np.diag(self.added_mass)

    def allocation_matrix(self) -> np.ndarray:
        """T (6x6): column i = [d_i; r_i x d_i], so tau = T f (paper eq. (7))."""
        out = np.zeros((6, 6))
        for i, (pos, direction) in enumerate(
            zip(self.thruster_positions, self.thruster_directions)
        ):
            d = np.asarray(direction, dtype=np.float64)
            out[:3, i] = d
            out[3:, i] = np.cross(np.asarray(pos, dtype=np.float64), d)
        return out

    def linear_decay_rates(self) -> np.ndarray:
        """diag(M^-1 D_lin) (1/s): the decay rate of each velocity under its own linear damping.

        The integrator solves this part exactly (``rov_envs.physics.integrator``); the largest
        entries are the stiffest modes (UUV Simulator: roll 92 1/s, pitch 25 1/s).
        """
        return np.diag(np.linalg.inv(self.mass_matrix())) * np.asarray(self.linear_damping)

    def _pack(self) -> np.ndarray:
        a = np.zeros(P_SIZE, dtype=np.float64)
        a[P_MINV : P_MINV + 36] = np.linalg.inv(self.mass_matrix()).ravel()
        a[P_MASS] = self.mass
        a[P_WEIGHT] = self.weight
        a[P_BUOYANCY] = self.buoyancy
        a[P_RG : P_RG + 3] = self.r_g
        a[P_RB : P_RB + 3] = self.r_b
        a[P_INERTIA : P_INERTIA + 3] = self.inertia
        a[P_ADDED : P_ADDED + 6] = self.added_mass
        a[P_DLIN : P_DLIN + 6] = self.linear_damping
        a[P_DQUAD : P_DQUAD + 6] = self.quadratic_damping
        a[P_ALLOC : P_ALLOC + 36] = self.allocation_matrix().ravel()
        a[P_THRUST_K] = self.thrust_coefficient
        a[P_INV_TAU] = 1.0 / self.thruster_time_constant
        a[P_LDIAG : P_LDIAG + 6] = self.linear_decay_rates()
        a.setflags(write=False)
        return a

    def to_array(self) -> np.ndarray:
        """All parameters packed as float64 (layout: the ``P_*`` constants) for the kernels.

        Returns a fresh writable copy.
        """
        return self._array.copy()


def _check_vehicle(name: Any) -> str:
    if not isinstance(name, str) or name not in VEHICLES:
        raise ValueError(f"vehicle={name!r} is not allowed: expected one of {list(VEHICLES)}")
    return name


def vehicle_params(name: str) -> BlueROV2Params:
    """The preset the environments run for ``vehicle=name`` (neutrally buoyant).

    ``"uuv_simulator"`` -> :meth:`BlueROV2Params.uuv_simulator`, ``"wu2018"`` ->
    :meth:`BlueROV2Params.wu2018`; anything else raises ``ValueError`` naming the allowed names.
    """
    name = _check_vehicle(name)
    if name == "wu2018":
        return BlueROV2Params.wu2018()
    return BlueROV2Params.uuv_simulator()


def vehicle_code(name: str) -> int:
    """The kernels' code of a vehicle: its index in :data:`VEHICLES` (ValueError if unknown)."""
    return VEHICLES.index(_check_vehicle(name))
