"""``control_period`` changes only how often the agent acts; ``progress_weighted`` scales r_c."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from rov_envs_helpers import paper_env

from rov_envs.physics.guidance import SINE_AMPLITUDE, SINE_WAVELENGTH
from rov_envs.sim.rewards import reward_sine, reward_straight


def _run_straight(control_period: float, seconds: float) -> np.ndarray:
    env = gym.make("rov_envs/PathFollowingStraight-v0", control_period=control_period)
    env.reset(seed=0)
    for _ in range(int(round(seconds / control_period))):
        _, _, _, _, info = env.step(2)
    return np.asarray(info["position"])


def test_control_period_same_trajectory_and_time_limit() -> None:
    # the same 0.05 s substeps either way: "Go straight" for 20 s ends at the same point
    fast, slow = _run_straight(0.2, 20.0), _run_straight(0.5, 20.0)
    assert slow == pytest.approx(fast, abs=1e-6)
    assert 17.0 < fast[0] < 21.0  # about 1 m/s after the start transient
    env = gym.make("rov_envs/PathFollowingStraight-v0", control_period=0.5)
    assert env.unwrapped.config.n_substeps == 10
    assert env.unwrapped.config.max_steps == int(round(2 * 200 / 1.0 / 0.5))


@pytest.mark.parametrize("bad", [0.01, 2.0, "fast", math.nan])
def test_bad_control_period_refused(bad) -> None:
    with pytest.raises(ValueError, match="control_period") as err:
        gym.make("rov_envs/PathFollowingStraight-v0", control_period=bad)
    assert "expected a float in [0.05, 1.0]" in str(err.value)


def _tangent(env_id: str, path_x: float) -> np.ndarray:
    if env_id.endswith("Straight-v0"):
        return np.array([1.0, 0.0])
    k = 2.0 * math.pi / SINE_WAVELENGTH  # y = A sin(k x): tangent (1, A k cos(k x)), normalised
    slope = SINE_AMPLITUDE * k * math.cos(k * path_x)
    return np.array([1.0, slope]) / math.hypot(1.0, slope)


def _eq18(a_c: float, g: float) -> float:
    return reward_straight(a_c, g, 30.0)


def _eq19(a_c: float, g: float) -> float:
    return reward_sine(a_c, g, 15.0)


@pytest.mark.parametrize(
    ("env_id", "pose", "reward"),
    [
        ("rov_envs/PathFollowingStraight-v0", (50.0, 3.0, 0.1), _eq18),
        ("rov_envs/PathFollowingSine-v0", (20.0, 1.0, 0.3), _eq19),
    ],
)
def test_progress_weighted_r_c(env_id, pose, reward) -> None:
    """r_c = eq. 18/19 times the step's advance along the path tangent / (1 m/s * dt), in [0, 1];
    without ``progress_weighted`` r_c is eq. 18/19 itself."""
    weighted = paper_env(env_id, progress_weighted=True, control_period=0.5)
    plain = paper_env(env_id, control_period=0.5)
    for env in (weighted, plain):
        env.reset(seed=0)
        env.unwrapped.set_pose(*pose)
    position = np.array(pose[:2])
    weights = []
    for _ in range(8):  # from rest the vehicle speeds up: the weight grows towards 1
        _, _, _, _, info_plain = plain.step(2)
        _, _, _, _, info = weighted.step(2)
        eq = reward(info["heading_error"], info["cross_track"])
        assert info_plain["r_c"] == pytest.approx(eq, abs=1e-12)
        advance = float(np.dot(info["position"] - position, _tangent(env_id, info["progress"])))
        weight = min(1.0, max(0.0, advance / (1.0 * 0.5)))
        assert eq > 0
        assert info["r_c"] == pytest.approx(eq * weight, abs=1e-9)
        position = info["position"]
        weights.append(weight)
    assert weights[0] < 0.6 and weights[-1] > 0.8  # the weight does change along the run


def test_progress_weighted_keeps_penalties() -> None:
    """A negative r_c (near the d_L limit, off the guidance heading) is paid whatever the
    progress."""
    env = gym.make("rov_envs/PathFollowingStraight-v0", progress_weighted=True)
    env.reset(seed=0)
    env.unwrapped.set_pose(50.0, 28.0, 0.0)
    _, _, _, _, info = env.step(2)
    eq = reward_straight(info["heading_error"], info["cross_track"], 30.0)
    assert eq < 0 and info["r_c"] == pytest.approx(eq, abs=1e-12)
