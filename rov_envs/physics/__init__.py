"""BlueROV2 physics core (no Gymnasium): Fossen 6-DOF dynamics, thrusters, sonar, LOS guidance.

Modules: ``params`` (BlueROV2Params, the two vehicle presets by name, calibration),
``thrusters`` (allocation, Table 1), ``dynamics`` (eq. (1)-(7)), ``etd`` (one exponential RK4
step), ``integrator`` (SIMD over blocks of vehicles), ``sonar`` (sector sonar), ``guidance``
(LOS, eq. (16)).
"""

from rov_envs.physics.dynamics import (
    DEFAULT_CONTROL_PERIOD,
    DEFAULT_SUBSTEPS,
    STATE_DIM,
    derivative,
)
from rov_envs.physics.guidance import (
    DEFAULT_LOOKAHEAD,
    PATH_SINE,
    PATH_STRAIGHT,
    SINE_AMPLITUDE,
    SINE_PATH_LENGTH,
    SINE_WAVELENGTH,
    STRAIGHT_PATH_LENGTH,
    los_guidance,
    los_sine,
    los_straight,
    wrap_to_pi,
)
from rov_envs.physics.integrator import advance, advance_batch
from rov_envs.physics.params import DEFAULT_VEHICLE, VEHICLES, BlueROV2Params, vehicle_params
from rov_envs.physics.sonar import nearest_surface_distance, sonar_scan
from rov_envs.physics.thrusters import ACTION_NAMES, ACTION_TABLE, continuous_to_speeds

__all__ = [
    "ACTION_NAMES",
    "ACTION_TABLE",
    "BlueROV2Params",
    "DEFAULT_CONTROL_PERIOD",
    "DEFAULT_LOOKAHEAD",
    "DEFAULT_SUBSTEPS",
    "DEFAULT_VEHICLE",
    "PATH_SINE",
    "PATH_STRAIGHT",
    "SINE_AMPLITUDE",
    "SINE_PATH_LENGTH",
    "SINE_WAVELENGTH",
    "STATE_DIM",
    "STRAIGHT_PATH_LENGTH",
    "VEHICLES",
    "advance",
    "advance_batch",
    "continuous_to_speeds",
    "derivative",
    "los_guidance",
    "los_sine",
    "los_straight",
    "nearest_surface_distance",
    "sonar_scan",
    "vehicle_params",
    "wrap_to_pi",
]
