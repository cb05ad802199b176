"""BlueROV2 model parameters (paper eq. (3)-(7); Wu 2018, "A 6-DOF dynamic model of BlueROV2").

Frames (see ``rov_envs.physics.dynamics``): world x along the straight path, y to its left, z up;
body frame forward-left-up (FLU). Wu's coefficients are given in the NED/FRD convention; the
diagonal mass, added-mass and damping coefficients are the same in FLU (flipping y and z leaves
diagonal quadratic forms unchanged); vectors such as the centre of gravity flip the sign of z.

Documented choices
------------------
* **Metacentric height.** Wu's set puts the centre of gravity 2 cm below the body origin and the
  centre of buoyancy at the origin (2 cm righting arm). In full 6-DOF with no attitude control that
  is pitch-unstable under "Go straight": the added-mass Munk moment ``u w (Z_wdot - X_udot)``
  beats the 2 cm righting arm and the vehicle loops. We keep Wu's centre of gravity
  (``r_g = (0, 0, -0.02)`` m in FLU) and put the centre of buoyancy 8 cm above the origin
  (``r_b = (0, 0, 0.08)`` m), a metacentric height ``z_b - z_g = 0.10`` m (the value of a widely
  used BlueROV2 NMPC parameter set; UUV Simulator's description uses an even larger arm). The
  thrusters sit 7.25 cm below the origin, so at the 1 m/s cruise the thrust/drag couple
  (0.0725 m x 22.2 N) is balanced by a steady nose-up pitch of asin(1.61 / (W * 0.10)) = 8.2 deg.
* **Buoyancy.** The paper's tasks are 2D with T5 = T6 = 0 (Table 1), so with Wu's W = 112.8 N and
  B = 114.8 N the vehicle would rise at about 0.3 m/s. We run **neutrally buoyant by default**
  (``B = W = m g``); ``BlueROV2Params.wu2018()`` keeps Wu's positive buoyancy for 3D users.
* **Directional (sway-yaw) instability -- a property of this parameter set, not a bug.** Wu's
  set is diagonal with sway added mass (12.7 kg) far above surge added mass (5.5 kg) and almost
  no yaw damping (N_r = -0.07). The added-mass Munk moment (Y_vdot - X_udot) u v of C_A (eq. 5)
  then turns the vehicle away from its velocity: linearised about straight running at 1 m/s the
  sway-yaw pair has an eigenvalue of about +4 1/s. Straight running under "Go straight" exists
  only by exact symmetry (an aligned start stays exactly straight); after any turn "Go straight"
  settles into a steady spin (u = 0.53 m/s, v = -/+0.55 m/s, r = +/-1.14 rad/s). Heading must be
  held actively (agents do it by alternating Table 1 turns; a simple heading rule holds |e| < 0.1
  m on the straight line). UUV Simulator's BlueROV2 description uses a different, directionally
  stable set (added mass Y_vdot = 0, linear N_r = -5) but no inertia to go with it here.
* **Thruster numbering.** T1 front-left, T2 front-right, T3 rear-left, T4 rear-right (horizontal,
  vectored at 45 degrees), T5 left vertical, T6 right vertical. With this numbering Table 1 means
  what it says: "Go straight" (8000, 8000, -8000, -8000) gives pure surge, "Turn left" (T2, T4)
  a positive (counter-clockwise) yaw moment. (UUV Simulator's ids put T1 front-right, which would
  make the paper's "Turn left" turn right.)
* **Thruster model.** First-order lag ``n_dot = (n_cmd - n) / THRUSTER_TIME_CONSTANT`` on the
  commanded speed (rev/min, the paper's unit goes straight in, as in UUV Simulator), then
  ``thrust = k |n| n`` (paper eq. (7) with K(s) the lag and F the quadratic map). The time constant
  is 0.1 s (UUV Simulator uses 0.05-0.2 s).
* **Thrust calibration.** UUV Simulator's public k = 1e-5 would give 640 N per thruster at
  8000 rev/min. We calibrate k so that "Go straight" cruises at exactly 1.0 m/s: at steady surge
  ``X_u u + X_u|u| u|u| = X`` gives X = 4.03 + 18.18 = 22.21 N at u = 1, and the four horizontal
  thrusters each contribute cos(45 deg) of their thrust to X, so
  ``k = 22.21 / (4 cos(45 deg) 8000^2) = 1.2270e-7 N/(rev/min)^2`` (``THRUST_COEFFICIENT``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

__all__ = [
    "BlueROV2Params",
    "GRAVITY",
    "THRUSTER_TIME_CONSTANT",
    "THRUST_COEFFICIENT",
    "CRUISE_SPEED",
    "MAX_THRUSTER_SPEED",
    "THRUSTER_POSITIONS",
    "THRUSTER_DIRECTIONS",
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
    "P_SIZE",
    "thrust_coefficient_for_speed",
]

GRAVITY: float = 9.81
"""Gravitational acceleration, m/s^2."""

MAX_THRUSTER_SPEED: float = 8000.0
"""Largest thruster speed used by the paper's Table 1, rev/min."""

CRUISE_SPEED: float = 1.0
"""Steady surge speed (m/s) that "Go straight" reaches with the calibrated thrust coefficient."""

THRUSTER_TIME_CONSTANT: float = 0.1
"""First-order thruster lag time constant, seconds."""

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
    speed: float = CRUISE_SPEED,
    x_u: float = 4.03,
    x_uu: float = 18.18,
    n_cmd: float = MAX_THRUSTER_SPEED,
) -> float:
    """k such that "Go straight" (horizontal thrusters at +-n_cmd) gives steady surge ``speed``.

    Steady surge: ``x_u u + x_uu u|u| = X`` with ``X = 4 cos(45 deg) k n_cmd^2``.
    """
    if not (speed > 0.0 and n_cmd > 0.0):
        raise ValueError(f"speed and n_cmd must be positive, got speed={speed}, n_cmd={n_cmd}")
    surge_force = x_u * speed + x_uu * speed * abs(speed)
    return surge_force / (4.0 * _C45 * n_cmd * n_cmd)


THRUST_COEFFICIENT: float = thrust_coefficient_for_speed()
"""k in thrust = k |n| n, N/(rev/min)^2 (= 1.2270e-7): "Go straight" cruises at 1.0 m/s."""

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
P_SIZE = 104


def _skew(a: np.ndarray) -> np.ndarray:
    """S(a) with S(a) b = a x b (Fossen 2011, eq. 2.10)."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


@dataclass(frozen=True)
class BlueROV2Params:
    """Physical parameters of the BlueROV2 (Wu 2018) in the FLU body frame.

    Damping and added-mass values are stored as positive magnitudes (Wu's derivatives are
    negative). Defaults: neutrally buoyant, metacentric height 0.10 m, k calibrated for 1.0 m/s.
    """

    mass: float = 11.5
    weight: float = 11.5 * GRAVITY  # 112.8 N
    buoyancy: float = 11.5 * GRAVITY  # neutrally buoyant by default (Wu: 114.8 N)
    r_g: tuple[float, float, float] = (0.0, 0.0, -0.02)
    r_b: tuple[float, float, float] = (0.0, 0.0, 0.08)
    inertia: tuple[float, float, float] = (0.16, 0.16, 0.16)
    added_mass: tuple[float, ...] = (5.5, 12.7, 14.57, 0.12, 0.12, 0.12)
    linear_damping: tuple[float, ...] = (4.03, 6.22, 5.18, 0.07, 0.07, 0.07)
    quadratic_damping: tuple[float, ...] = (18.18, 21.66, 36.99, 1.55, 1.55, 1.55)
    thruster_positions: tuple[tuple[float, float, float], ...] = THRUSTER_POSITIONS
    thruster_directions: tuple[tuple[float, float, float], ...] = THRUSTER_DIRECTIONS
    thrust_coefficient: float = THRUST_COEFFICIENT
    thruster_time_constant: float = THRUSTER_TIME_CONSTANT
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
    def wu2018(cls) -> BlueROV2Params:
        """Wu's positively buoyant set (B = 114.8 N), this package's 0.10 m metacentric height."""
        return cls(buoyancy=114.8)

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
        a.setflags(write=False)
        return a

    def to_array(self) -> np.ndarray:
        """All parameters packed as float64 (layout: the ``P_*`` constants) for the kernels.

        Returns a fresh writable copy.
        """
        return self._array.copy()
