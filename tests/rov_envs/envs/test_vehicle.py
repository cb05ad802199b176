"""The ``vehicle=`` argument: every task runs either preset, UUV Simulator's by default."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import rov_envs
from rov_envs.envs.sb3 import RovSB3VecEnv
from rov_envs.physics.params import DEFAULT_VEHICLE, VEHICLES


def test_default_vehicle_is_uuv_simulator(env_id: str) -> None:
    assert DEFAULT_VEHICLE == "uuv_simulator"
    env = gym.make(env_id)
    assert env.unwrapped.vehicle == "uuv_simulator" == env.unwrapped.config.vehicle
    venv = gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point")
    assert venv.vehicle == "uuv_simulator"
    assert RovSB3VecEnv(2, env_id).get_attr("vehicle") == ["uuv_simulator"] * 2


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_vehicle_reaches_every_env_flavour(vehicle: str) -> None:
    env_id = "rov_envs/PlanningSine-v0"
    assert gym.make(env_id, vehicle=vehicle).unwrapped.vehicle == vehicle
    venv = gym.make_vec(
        env_id, num_envs=2, vectorization_mode="vector_entry_point", vehicle=vehicle
    )
    assert venv.vehicle == vehicle and venv.to_sb3().vehicle == vehicle
    assert RovSB3VecEnv(2, env_id, vehicle=vehicle).vehicle == vehicle
    assert rov_envs.RovEnv("PlanningSine", vehicle=vehicle).vehicle == vehicle


@pytest.mark.parametrize("bad", ["uuv", "Wu2018", "", None, 1])
def test_bad_vehicle_is_refused_everywhere(bad: object) -> None:
    message = r"vehicle=.* is not allowed: expected one of \['uuv_simulator', 'wu2018'\]"
    env_id = "rov_envs/PathFollowingStraight-v0"
    with pytest.raises(ValueError, match=message):
        gym.make(env_id, vehicle=bad)
    with pytest.raises(ValueError, match=message):
        gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point", vehicle=bad)
    with pytest.raises(ValueError, match=message):
        RovSB3VecEnv(2, env_id, vehicle=bad)


def _run(vehicle: str, action: int, steps: int) -> dict:
    """``steps`` steps of 0.2 s of one action from the exact start pose."""
    env = gym.make(
        "rov_envs/PathFollowingStraight-v0",
        vehicle=vehicle,
        control_period=0.2,
        start_noise=(0.0, 0.0),
    )
    env.reset(seed=0)
    for _ in range(steps):
        _, _, term, trunc, info = env.step(action)
        assert not (term or trunc)
    return {**info, "state": env.unwrapped.state}


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_go_straight_cruises_at_one_metre_per_second_level(vehicle: str) -> None:
    info = _run(vehicle, 2, 150)  # 30 s
    u, v, r = info["velocity"]
    assert u == pytest.approx(1.0, abs=2e-3 if vehicle == "uuv_simulator" else 2e-2)
    assert v == 0.0 and r == 0.0 and info["heading"] == 0.0
    phi, theta = info["state"][3:5]
    assert phi == 0.0 and abs(theta) < (0.05 if vehicle == "uuv_simulator" else 0.2)


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_turning_left_turns_left_and_right_turns_right(vehicle: str) -> None:
    left, right = _run(vehicle, 1, 5), _run(vehicle, 4, 5)  # 1 s of Turn left/right 2
    assert left["heading"] > 0.05 and left["velocity"][2] > 0.0
    assert right["heading"] == pytest.approx(-left["heading"], rel=1e-12)
    np.testing.assert_allclose(right["position"], left["position"] * [1, -1], rtol=1e-12)


def test_the_vehicles_differ() -> None:
    uuv, wu = (_run(v, 1, 5) for v in VEHICLES)
    assert wu["heading"] > 3 * uuv["heading"]  # Wu's set pivots, UUV Simulator's turns slowly
