"""Evaluation statistics (sb3_pnn.evaluation) on scripted policies with known outcomes."""

from __future__ import annotations

import json
import math

import gymnasium as gym
import numpy as np
import pytest

import rov_envs  # noqa: F401
from rov_envs.sim.config import CONTROL_PERIOD
from sb3_pnn.baselines import PIDController, make_baseline
from sb3_pnn.evaluation import EvaluationResult, evaluate_policy_on_task, wilson_interval


class Constant:
    """Scripted policy: always the same Discrete(5) action."""

    def __init__(self, action: int) -> None:
        self.action = action

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        n = np.asarray(obs["path"]).reshape(-1, 2).shape[0]
        return np.full(n, self.action, dtype=np.int64), state


def test_wilson_interval_matches_hand_computed_values():
    # k = 8, n = 10, z = 1.96: p = 0.8, denom = 1.38416, centre = 0.716738, half = 0.226581
    lo, hi = wilson_interval(8, 10)
    assert lo == pytest.approx(0.490157, abs=1e-6) and hi == pytest.approx(0.943319, abs=1e-6)
    # k = 0: (0, z^2 / (n + z^2)) = (0, 3.8416 / 13.8416)
    assert wilson_interval(0, 10) == pytest.approx((0.0, 0.277540), abs=1e-6)
    assert wilson_interval(10, 10) == pytest.approx((0.722460, 1.0), abs=1e-6)
    for bad in ((-1, 10), (11, 10), (0, 0), (1.5, 10)):
        with pytest.raises(ValueError):
            wilson_interval(*bad)


@pytest.mark.parametrize(("vehicle", "max_steps"), [("uuv_simulator", 40), ("wu2018", 20)])
def test_always_turning_left_fails_every_episode_by_heading_deviation(vehicle, max_steps):
    res = evaluate_policy_on_task(
        Constant(1), "PathFollowingStraight-v0", n_episodes=6, env_kwargs={"vehicle": vehicle}
    )
    assert res.successes == 0 and res.success_rate == 0.0 and res.vehicle == vehicle
    assert res.end_reasons == {"heading": 6} and res.collisions == 0
    assert res.success_ci95 == pytest.approx(wilson_interval(0, 6))
    assert res.mean_time_to_target is None
    assert [e.seed for e in res.episodes] == list(range(6))
    for e in res.episodes:  # |a_c| >= pi/2 within a few seconds of turning (Wu: on the spot)
        assert not e.success and e.steps < max_steps and e.time_to_target is None


def test_pid_on_the_obstacle_free_task_succeeds_every_time():
    res = evaluate_policy_on_task(PIDController(), "PathFollowingStraight-v0", n_episodes=4, seed=7)
    assert res.successes == 4 and res.success_rate == 1.0
    assert res.success_ci95 == pytest.approx(wilson_interval(4, 4))
    assert [e.seed for e in res.episodes] == [7, 8, 9, 10]
    times = [e.time_to_target for e in res.episodes]
    assert all(t == pytest.approx(e.steps * CONTROL_PERIOD) for t, e in zip(times, res.episodes))
    assert res.mean_time_to_target == pytest.approx(np.mean(times))
    # 200 m at no more than about 1 m/s
    assert 190.0 < res.mean_time_to_target < 400.0


def test_collisions_are_counted_for_a_policy_driving_into_an_obstacle_dead_ahead():
    res = evaluate_policy_on_task(
        Constant(2),
        "PlanningStraight-v0",
        n_episodes=3,
        start_noise=(0.0, 0.0),
        env_kwargs={"obstacles": [(30.0, 0.0, 1.5)]},
        record_trajectories=1,
    )
    assert res.collisions == 3 and res.collision_rate == 1.0 and res.successes == 0
    assert res.end_reasons == {"collision": 3}
    tr = res.trajectories[0]
    assert tr.obstacles == [[30.0, 0.0, 1.5]]
    assert 26.0 < tr.x[-1] < 27.0  # stopped 2 m before the surface at x = 28.5 (eq. 21)


def test_metrics_match_a_hand_rolled_loop_over_single_envs():
    """The batched run equals gymnasium.make + reset(seed=seed + i) with the same controller."""
    res = evaluate_policy_on_task("adaptive_pid", "PlanningSine-v0", n_episodes=3, seed=4)
    env = gym.make("rov_envs/PlanningSine-v0", start_noise=(1.0, math.radians(5.0)))
    ctrl = make_baseline("adaptive_pid", env=env)
    for i, rec in enumerate(res.episodes):
        obs, _ = env.reset(seed=4 + i)
        ctrl.reset()
        g, ac, ret, steps = [], [], 0.0, 0
        while True:
            action, _ = ctrl.predict(obs)
            obs, r, term, trunc, info = env.step(action)
            g.append(abs(info["cross_track"]))
            ac.append(abs(info["heading_error"]))
            ret += r
            steps += 1
            if term or trunc:
                break
        assert rec.steps == steps and rec.end_reason == info["end_reason"]
        assert rec.success == info["is_success"]
        assert rec.episode_return == pytest.approx(ret)
        assert rec.mean_abs_cross_track == pytest.approx(np.mean(g))
        assert rec.max_abs_cross_track == pytest.approx(np.max(g))
        assert rec.mean_abs_heading_error == pytest.approx(np.mean(ac))


def test_discounted_return_matches_a_hand_rolled_sum_and_stays_out_unless_asked():
    """With a discount each episode records sum_t gamma^t r_t of its own rewards (as SAC's
    objective counts them from the start state); without one the results read as before."""
    gamma = 0.9
    res = evaluate_policy_on_task(
        "adaptive_pid", "PlanningSine-v0", n_episodes=2, seed=4, discount=gamma
    )
    env = gym.make("rov_envs/PlanningSine-v0", start_noise=(1.0, math.radians(5.0)))
    ctrl = make_baseline("adaptive_pid", env=env)
    sums = []
    for i in range(2):
        obs, _ = env.reset(seed=4 + i)
        ctrl.reset()
        total, t, done = 0.0, 0, False
        while not done:
            obs, r, term, trunc, _ = env.step(ctrl.predict(obs)[0])
            total += gamma**t * r
            t, done = t + 1, term or trunc
        sums.append(total)
    assert [e.discounted_return for e in res.episodes] == pytest.approx(sums)
    assert res.mean_discounted_return == pytest.approx(np.mean(sums))
    # gamma = 1 is the plain return; the discount changes nothing else
    plain = evaluate_policy_on_task("adaptive_pid", "PlanningSine-v0", n_episodes=2, seed=4)
    assert plain.mean_discounted_return is None
    assert "mean_discounted_return" not in plain.to_dict()
    assert "discounted_return" not in plain.to_dict()["episodes"][0]
    one = evaluate_policy_on_task(
        "adaptive_pid", "PlanningSine-v0", n_episodes=2, seed=4, discount=1.0
    )
    assert one.mean_discounted_return == pytest.approx(plain.mean_return)
    assert one.to_dict()["mean_return"] == plain.to_dict()["mean_return"]
    back = EvaluationResult.from_dict(json.loads(json.dumps(res.to_dict())))
    assert back.mean_discounted_return == res.mean_discounted_return
    assert "mean discounted return" in res.format_table()


def test_results_do_not_depend_on_the_batch_size():
    a = evaluate_policy_on_task("adaptive_pid", "PlanningStraightUniform-v0", 5, n_envs=1)
    b = evaluate_policy_on_task("adaptive_pid", "PlanningStraightUniform-v0", 5, n_envs=3)
    assert [e.__dict__ for e in a.episodes] == [e.__dict__ for e in b.episodes]


def test_trajectories_and_json_round_trip(tmp_path):
    res = evaluate_policy_on_task(
        "pid", "PathFollowingSine-v0", n_episodes=3, record_trajectories=2
    )
    assert [t.index for t in res.trajectories] == [0, 1]
    for tr, rec in zip(res.trajectories, res.episodes):
        assert len(tr.t) == rec.steps + 1 and len(tr.actions) == rec.steps
        assert tr.t[0] == 0.0 and tr.t[-1] == pytest.approx(rec.duration_s)
        assert len(tr.x) == len(tr.y) == len(tr.heading_error) == len(tr.cross_track) == len(tr.t)
    d = json.loads(json.dumps(res.to_dict()))
    back = EvaluationResult.from_dict(d)
    assert back.to_dict() == d
    path = res.save_json(tmp_path / "sub" / "r.json")
    assert json.loads(path.read_text())["successes"] == res.successes
    assert "success rate" in res.format_table()


def test_sb3_model_is_evaluated_with_batched_predict():
    from sb3_pnn import DiscreteSAC

    env = gym.make("rov_envs/PathFollowingStraight-v0")
    model = DiscreteSAC("MultiInputPolicy", env, policy_kwargs={"net_arch": [8]}, seed=0)
    res = evaluate_policy_on_task(model, "PathFollowingStraight-v0", n_episodes=3, n_envs=3)
    assert res.n_episodes == 3 and res.policy_name == "DiscreteSAC"
    assert sum(res.end_reasons.values()) == 3


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"n_episodes": 0}, "n_episodes"),
        ({"env_id": "rov_envs/Nope-v0"}, "env_id"),
        ({"env_kwargs": {"start_noise": (1, 0)}}, "start_noise"),
        ({"start_noise": (-1.0, 0.0)}, "start_noise"),
        ({"record_trajectories": 5, "n_episodes": 2}, "record_trajectories"),
        ({"policy": object()}, "predict"),
        ({"policy": "lqr"}, "policy"),
        ({"seed": -1}, "seed"),
        ({"discount": 0.0}, r"discount=0.0 is not allowed: expected a number in \(0, 1\]"),
        ({"discount": 1.5}, "discount=1.5"),
        ({"discount": True}, "discount=True"),
    ],
)
def test_bad_input_is_refused(kwargs, match):
    args = {"policy": "pid", "env_id": "PathFollowingStraight-v0", "n_episodes": 2, **kwargs}
    with pytest.raises(ValueError, match=match):
        evaluate_policy_on_task(**args)


def test_a_models_training_layout_stays_with_its_own_task():
    """A column trained among random fields within a 15 m corridor keeps those on its own task
    and leaves them behind on another: evaluated on the dense layout, it meets the dense
    layout's obstacles, not random fields."""
    from types import SimpleNamespace

    from sb3_pnn.evaluation.evaluate import trained_env_kwargs

    kwargs = {"layout": "scatter", "corridor": 15.0, "goal_offset": True, "start_noise": [1, 0]}
    policy = SimpleNamespace(trained_env={"id": "rov_envs/ObstacleAvoidance-v0", "kwargs": kwargs})
    own = trained_env_kwargs(policy, "rov_envs/ObstacleAvoidance-v0")
    assert own == {"layout": "scatter", "corridor": 15.0, "goal_offset": True}
    other = trained_env_kwargs(policy, "rov_envs/PlanningStraightDense-v0")
    assert other == {"goal_offset": True}
