"""Rewards equal eq. (18)-(21) at hand-computed states; every episode end triggers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from rov_envs_helpers import paper_env

from rov_envs.sim.rewards import failure_code, reward_obstacle, reward_sine, reward_straight


def test_eq18_hand_values() -> None:
    # a_c = 0.5 rad, g = 6 m, d_L = 30: -0.5 / 3.14 + |1 - 0.2| = 0.640764...
    assert reward_straight(0.5, 6.0, 30.0) == pytest.approx(-0.5 / 3.14 + 0.8, abs=1e-12)
    # the distance |g| is used: the same reward on both sides of the path
    assert reward_straight(0.2, -6.0, 30.0) == reward_straight(0.2, 6.0, 30.0)
    assert reward_straight(0.0, 0.0, 30.0) == 1.0


def test_eq19_hand_values() -> None:
    # |g| <= 1.8 branch: -0.175 * 0.3 + 2 ** (2 - 1.5 / 15) * 0.325
    assert reward_sine(0.3, -1.5, 15.0) == pytest.approx(-0.0525 + 2**1.9 * 0.325, abs=1e-12)
    # else branch: -0.0875 * 0.3 + 2 ** (2 - 6 / 15) * 0.1625
    assert reward_sine(-0.3, 6.0, 15.0) == pytest.approx(-0.02625 + 2**1.6 * 0.1625, abs=1e-12)
    assert reward_sine(0.0, 1.8, 15.0) == pytest.approx(2 ** (2 - 0.12) * 0.325)


@pytest.mark.parametrize(
    ("d", "expected"),
    [
        (math.inf, 0.0),
        (8.01, 0.0),
        (8.0, -2.0),
        (5.01, -2.0),
        (5.0, -4.0),
        (2.01, -4.0),
        (2.0, 0.0),
    ],
)
def test_eq20(d: float, expected: float) -> None:
    assert reward_obstacle(d) == expected


def test_eq21_conditions() -> None:
    assert failure_code(0.0, 29.99, 10.0, 30.0) == 0
    assert failure_code(0.0, -30.0, 10.0, 30.0) == 1
    assert failure_code(math.pi / 2, 0.0, 10.0, 30.0) == 2
    assert failure_code(0.0, 0.0, 2.0, 30.0) == 3


def _place(env_id: str, x: float, y: float, psi: float, action: int = 2, **kw):
    env = paper_env(env_id, **kw)
    env.reset(seed=0)
    env.unwrapped.set_pose(x, y, psi)
    return env, env.step(action)


def test_step_reward_matches_eq18_at_state() -> None:
    env, (obs, r, term, trunc, info) = _place("rov_envs/PathFollowingStraight-v0", 20.0, 6.0, 0.3)
    a_c, g = info["heading_error"], info["cross_track"]
    # independent LOS (lookahead 5 m) on the line y = 0 and eq. 18
    x, y = info["position"]
    expected_ac = (info["heading"] + math.atan(y / 5.0) + math.pi) % (2 * math.pi) - math.pi
    assert a_c == pytest.approx(expected_ac, abs=1e-12)
    assert g == pytest.approx(y, abs=1e-12)
    assert r == pytest.approx(-abs(a_c) / 3.14 + abs(1 - abs(g) / 30.0), abs=1e-12)
    assert info["r_v"] == 0.0 and info["r_terminal"] == 0.0 and not term


def test_step_reward_matches_eq19_eq20_at_state() -> None:
    # PlanningSine: stand 6.5 m from the (30, 17.5, r=1.5) obstacle's centre -> d = 5.0 +- motion
    env, (obs, r, term, trunc, info) = _place("rov_envs/PlanningSine-v0", 30.0, 11.0, 0.0)
    d = info["obstacle_distance"]
    x, y = info["position"]
    assert d == pytest.approx(math.hypot(x - 30.0, y - 17.5) - 1.5, abs=1e-12)
    a_c, g = info["heading_error"], info["cross_track"]
    ag = abs(g)
    if ag <= 1.8:
        rc = -abs(a_c) * 0.175 + 2 ** (2 - ag / 15) * 0.325
    else:
        rc = -abs(a_c) * 0.0875 + 2 ** (2 - ag / 15) * 0.1625
    rv = -2.0 if 5 < d <= 8 else (-4.0 if 2 < d <= 5 else 0.0)
    assert rv != 0.0
    assert info["r_c"] == pytest.approx(rc, abs=1e-12)
    assert info["r_v"] == rv
    assert r == pytest.approx(rc + rv, abs=1e-12)


@pytest.mark.parametrize("weight", [0.0, 0.5, 3.0])
def test_obstacle_penalty_weights_eq20_only(weight: float) -> None:
    # the same placement as above: eq. 20's r_v scaled, r_c untouched, the sum still r
    _, (_, r1, _, _, paper) = _place("rov_envs/PlanningSine-v0", 30.0, 11.0, 0.0)
    _, (_, r, _, _, info) = _place(
        "rov_envs/PlanningSine-v0", 30.0, 11.0, 0.0, obstacle_penalty=weight
    )
    assert paper["r_v"] in (-2.0, -4.0)
    assert info["r_v"] == weight * paper["r_v"]
    assert info["r_c"] == paper["r_c"]
    assert r == pytest.approx(r1 + (weight - 1.0) * paper["r_v"], abs=1e-12)


@pytest.mark.parametrize("bad", [-0.5, float("inf"), "1"])
def test_obstacle_penalty_refuses_bad_weights(bad) -> None:
    import gymnasium as gym

    with pytest.raises(ValueError, match=r"obstacle_penalty=.* is not allowed: expected a finite"):
        gym.make("rov_envs/PlanningSine-v0", obstacle_penalty=bad)


def _check_failure(info, r, term, trunc, reason: str) -> None:
    assert term and not trunc
    assert info["end_reason"] == reason
    assert info["r_terminal"] == -200.0
    assert r == pytest.approx(info["r_c"] + info["r_v"] - 200.0)
    assert info["is_success"] is False


def test_end_off_path() -> None:
    _, (_, r, term, trunc, info) = _place("rov_envs/PathFollowingStraight-v0", 50.0, 30.5, 0.0)
    _check_failure(info, r, term, trunc, "off_path")
    _, (_, r, term, trunc, info) = _place("rov_envs/PathFollowingSine-v0", 30.0, -0.5, 0.0)
    assert abs(info["cross_track"]) >= 15.0
    _check_failure(info, r, term, trunc, "off_path")


def test_corridor_argument_narrows_the_corridor() -> None:
    # 20 m off the line: inside the task's 30 m corridor, outside a 15 m one
    _, (_, r, term, _, info) = _place("rov_envs/ObstacleAvoidance-v0", 30.0, 20.0, 0.0)
    assert info["end_reason"] != "off_path" and not term
    _, (_, r, term, trunc, info) = _place(
        "rov_envs/ObstacleAvoidance-v0", 30.0, 20.0, 0.0, corridor=15.0
    )
    _check_failure(info, r, term, trunc, "off_path")
    # eq. 18's distance term and the path part's g / d_L read the corridor too
    env, (obs, r, term, _, info) = _place(
        "rov_envs/PathFollowingStraight-v0", 20.0, 6.0, 0.3, corridor=12.0
    )
    g = info["cross_track"]
    assert r == pytest.approx(-abs(info["heading_error"]) / 3.14 + abs(1 - abs(g) / 12.0))
    assert obs["path"][1] == pytest.approx(g / 12.0, abs=1e-6)


def test_end_heading() -> None:
    _, (_, r, term, trunc, info) = _place("rov_envs/PathFollowingStraight-v0", 50.0, 0.0, math.pi)
    assert abs(info["heading_error"]) >= math.pi / 2
    _check_failure(info, r, term, trunc, "heading")


def test_end_collision() -> None:
    _, (_, r, term, trunc, info) = _place("rov_envs/PlanningStraight-v0", 63.0, -2.5, 0.0)
    assert info["obstacle_distance"] <= 2.0
    assert info["collision"] is True
    _check_failure(info, r, term, trunc, "collision")


@pytest.mark.parametrize("bonus", [None, 0.0, 50.0])
def test_end_success(bonus) -> None:
    kwargs = {} if bonus is None else {"success_reward": bonus}
    env = paper_env("rov_envs/PathFollowingStraight-v0", **kwargs)
    env.reset(seed=0)
    env.unwrapped.set_pose(197.0, 0.0, 0.0)
    for _ in range(100):
        obs, r, term, trunc, info = env.step(2)
        if term or trunc:
            break
    assert term and not trunc
    assert info["end_reason"] == "success" and info["is_success"] is True
    expected_bonus = 200.0 if bonus is None else bonus
    assert info["r_terminal"] == expected_bonus
    assert r == pytest.approx(info["r_c"] + info["r_v"] + expected_bonus, abs=1e-12)
    assert info["progress"] >= 198.0 - 1e-9


def test_end_time_limit() -> None:
    env = paper_env("rov_envs/PathFollowingStraight-v0", max_episode_seconds=1.0)
    env.reset(seed=0)
    for k in range(5):
        obs, r, term, trunc, info = env.step(2)
        assert term is False
        assert trunc is (k == 4)
    assert info["end_reason"] == "time_limit" and info["is_success"] is False
    with pytest.raises(RuntimeError):
        env.step(2)


def test_default_time_limit_is_twice_nominal() -> None:
    env = paper_env("rov_envs/PathFollowingStraight-v0")
    assert env.unwrapped.config.max_steps == int(round(2 * 200 / 1.0 / 0.2))


def test_progress_reward_obstacle_avoidance() -> None:
    env = paper_env("rov_envs/ObstacleAvoidance-v0", obstacles=[(50.0, 20.0, 1.0)])
    env.reset(seed=0)
    prev = np.hypot(60.0, 0.0)
    for _ in range(30):
        obs, r, term, trunc, info = env.step(2)
        x, y = info["position"]
        now = math.hypot(60.0 - x, y)
        assert info["r_c"] == pytest.approx((prev - now) / 0.2, abs=1e-9)
        prev = now
