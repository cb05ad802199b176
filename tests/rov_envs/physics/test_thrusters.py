"""Thruster allocation, the calibration of k, Table 1 and the continuous mapping."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rov_envs.physics import ACTION_TABLE, continuous_to_speeds
from rov_envs.physics.params import (
    P_ALLOC,
    P_LDIAG,
    P_MINV,
    UUV_SIMULATOR_THRUST_COEFFICIENT,
    VEHICLES,
    WU2018_THRUST_COEFFICIENT,
    thrust_coefficient_for_speed,
    vehicle_params,
)
from rov_envs.physics.thrusters import (
    ACTION_NAMES,
    allocation_matrix,
    continuous_to_speeds_into,
    thrust_from_speeds,
)

T = allocation_matrix()


def wrench(speeds):
    return T @ thrust_from_speeds(speeds)


def test_calibrated_thrust_coefficients():
    # UUV Simulator: 11.7391 u = X at u = 1 m/s: X = 11.7391 N = 4 cos(45 deg) k 8000^2
    c = 4 * math.cos(math.pi / 4) * 8000.0**2
    assert UUV_SIMULATOR_THRUST_COEFFICIENT == pytest.approx(11.7391 / c)
    assert UUV_SIMULATOR_THRUST_COEFFICIENT == pytest.approx(6.4850e-8, rel=1e-4)
    assert wrench(ACTION_TABLE[2])[0] == pytest.approx(11.7391)  # default vehicle: UUV
    # Wu: 4.03 u + 18.18 u|u| = X at u = 1 m/s: X = 22.21 N
    assert WU2018_THRUST_COEFFICIENT == pytest.approx(22.21 / c)
    assert WU2018_THRUST_COEFFICIENT == pytest.approx(1.2269e-7, rel=1e-4)
    wu = vehicle_params("wu2018")
    assert (T @ thrust_from_speeds(ACTION_TABLE[2], wu))[0] == pytest.approx(22.21)
    # another speed: k scales with the surge force the damping needs there
    assert thrust_coefficient_for_speed(x_u=4.03, x_uu=18.18, speed=0.5) == pytest.approx(
        (4.03 * 0.5 + 18.18 * 0.25) / c
    )
    with pytest.raises(ValueError, match="x_u"):
        thrust_coefficient_for_speed(x_u=0.0, x_uu=0.0)


def test_allocation_rows_from_the_poses():
    np.testing.assert_allclose(np.abs(T[0, :4]), math.sqrt(0.5))
    np.testing.assert_allclose(np.abs(T[1, :4]), math.sqrt(0.5))
    np.testing.assert_allclose(np.abs(T[5, :4]), [0.1665, 0.1665, 0.1750, 0.1750], atol=1e-4)
    np.testing.assert_allclose(T[2, 4:], [1.0, 1.0])  # vertical thrusters push up


def test_go_straight_is_pure_surge_and_turns_yaw_the_right_way():
    X, Y, Z, K, M, N = wrench(ACTION_TABLE[2])
    assert X > 0 and abs(Y) < 1e-12 and abs(N) < 1e-12 and abs(K) < 1e-12 and Z == 0
    for i, name in enumerate(ACTION_NAMES):
        X, Y, _, _, _, N = wrench(ACTION_TABLE[i])
        assert abs(Y) < 1e-12  # no sway force in any Table 1 action
        if name.startswith("Turn left"):
            assert N > 0 and X > 0
        elif name.startswith("Turn right"):
            assert N < 0 and X > 0
    assert wrench(ACTION_TABLE[1])[5] > wrench(ACTION_TABLE[0])[5]
    assert ACTION_NAMES[2] == "Go straight" and ACTION_TABLE.shape == (5, 6)
    assert not ACTION_TABLE.flags.writeable


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_packed_array_layout(vehicle):
    prm = vehicle_params(vehicle)
    a = prm.to_array()
    np.testing.assert_allclose(a[P_ALLOC : P_ALLOC + 36].reshape(6, 6), T)  # same thrusters
    minv = a[P_MINV : P_MINV + 36].reshape(6, 6)
    np.testing.assert_allclose(minv @ prm.mass_matrix(), np.eye(6), atol=1e-12)
    np.testing.assert_allclose(
        a[P_LDIAG : P_LDIAG + 6], np.diag(minv @ np.diag(prm.linear_damping)), rtol=1e-14
    )
    assert prm.metacentric_height == pytest.approx(0.30 if vehicle == "uuv_simulator" else 0.10)
    assert prm.weight == prm.buoyancy


def test_continuous_mapping():
    np.testing.assert_array_equal(continuous_to_speeds(1.0, 0.0), ACTION_TABLE[2])
    np.testing.assert_allclose(continuous_to_speeds(0.5, 0.5), ACTION_TABLE[1], atol=0)
    np.testing.assert_allclose(continuous_to_speeds(0.5, -0.5), ACTION_TABLE[4], atol=0)
    np.testing.assert_array_equal(continuous_to_speeds(0.0, 0.0), np.zeros(6))
    # wrench is linear in (surge, yaw) inside the unclipped region
    w1 = wrench(continuous_to_speeds(0.3, 0.1))
    w2 = wrench(continuous_to_speeds(0.6, 0.2))
    np.testing.assert_allclose(w2, 2 * w1, atol=1e-12)
    assert wrench(continuous_to_speeds(0.0, 0.4))[5] > 0  # yaw > 0 turns left
    out = np.empty(6)
    for s in np.linspace(-1, 1, 7):
        for y in np.linspace(-1, 1, 7):
            continuous_to_speeds_into(s, y, 8000.0, out)
            np.testing.assert_array_equal(out, continuous_to_speeds(s, y))
    with pytest.raises(ValueError, match="surge"):
        continuous_to_speeds(1.5, 0.0)
    with pytest.raises(ValueError, match="yaw"):
        continuous_to_speeds(0.0, float("nan"))
