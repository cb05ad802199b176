"""The natively batched env equals N single envs under the same seeds; SB3 adapter works."""

from __future__ import annotations

import multiprocessing

import gymnasium as gym
import numpy as np
import pytest
from rov_envs_helpers import KW, _lockstep

from rov_envs.envs.sb3 import RovSB3VecEnv
from rov_envs.envs.vector import RovVectorEnv


@pytest.mark.parametrize(
    ("env_id", "continuous", "vehicle"),
    [
        ("rov_envs/PlanningSineDense-v0", False, "uuv_simulator"),
        ("rov_envs/ObstacleAvoidance-v0", False, "uuv_simulator"),
        ("rov_envs/PlanningStraight-v0", True, "uuv_simulator"),
        ("rov_envs/PathFollowingSine-v0", False, "uuv_simulator"),
        ("rov_envs/PlanningSine-v0", False, "wu2018"),
        ("rov_envs/PathFollowingStraight-v0", True, "wu2018"),
    ],
)
def test_batched_equals_single(env_id: str, continuous: bool, vehicle: str) -> None:
    n = 3
    kw = {**KW, "continuous": continuous, "vehicle": vehicle}
    venv = gym.make_vec(env_id, num_envs=n, vectorization_mode="vector_entry_point", **kw)
    assert isinstance(venv, RovVectorEnv) and venv.vehicle == vehicle
    singles = {i: gym.make(env_id, **kw) for i in range(n)}
    vobs, _ = venv.reset(seed=7)
    for i, env in singles.items():
        obs, _ = env.reset(seed=7 + i)
        for k in obs:
            np.testing.assert_array_equal(obs[k], vobs[k][i])
    # 100 steps per episode at most: several autoresets
    assert _lockstep(venv, singles, 250, continuous) >= n


def test_threaded_batch_equals_single_envs() -> None:
    """Enough vehicles for the threaded kernel: sampled vehicles still equal single envs."""
    from rov_envs.sim.engine import PARALLEL_MIN_ENVS

    n = PARALLEL_MIN_ENVS + 6
    env_id = "rov_envs/PlanningStraightDense-v0"
    venv = gym.make_vec(env_id, num_envs=n, vectorization_mode="vector_entry_point", **KW)
    venv.reset(seed=100)
    singles = {i: gym.make(env_id, **KW) for i in (0, 17, n - 1)}
    for i, env in singles.items():
        env.reset(seed=100 + i)
    assert _lockstep(venv, singles, 120, seed=5) >= len(singles)


def test_vector_infos_are_arrays() -> None:
    venv = gym.make_vec(
        "rov_envs/PlanningStraight-v0", num_envs=4, vectorization_mode="vector_entry_point"
    )
    venv.reset(seed=0)
    obs, r, term, trunc, info = venv.step(np.full(4, 2))
    assert obs["path"].shape == (4, 2) and obs["sonar"].shape == (4, 9)
    assert r.shape == (4,) and term.dtype == bool
    assert info["position"].shape == (4, 2) and info["velocity"].shape == (4, 3)
    assert info["_position"].all()
    assert not info["_is_success"].any()
    assert venv.observation_space.contains(obs)


def test_sb3_adapter_same_step_reset() -> None:
    kw = {"max_episode_seconds": 2.0, "control_period": 0.2}  # 10 steps
    venv = RovSB3VecEnv(2, "rov_envs/PathFollowingStraight-v0", **kw)
    venv.seed(3)
    obs = venv.reset()
    single = gym.make("rov_envs/PathFollowingStraight-v0", **kw)
    sobs, _ = single.reset(seed=3)
    np.testing.assert_array_equal(obs["path"][0], sobs["path"])
    returns = 0.0
    for k in range(10):
        obs, rewards, dones, infos = venv.step(np.array([2, 2]))
        sobs, sr, st, str_, sinfo = single.step(2)
        returns += sr
        assert rewards.dtype == np.float32 and rewards[0] == np.float32(sr)
        if k < 9:
            assert not dones.any() and infos[0] == {}
    assert dones.all()
    info = infos[0]
    np.testing.assert_array_equal(info["terminal_observation"]["path"], sobs["path"])
    assert info["TimeLimit.truncated"] is True and info["is_success"] is False
    assert info["episode"]["l"] == 10
    assert info["episode"]["r"] == pytest.approx(returns, rel=1e-6)
    # the returned observation is already the next episode's first one
    sobs, _ = single.reset()
    np.testing.assert_array_equal(obs["path"][0], sobs["path"])
    assert venv.get_attr("render_mode") == [None, None]


def test_sb3_algorithm_runs_on_adapter() -> None:
    from stable_baselines3 import DQN

    venv = RovSB3VecEnv(4, "PlanningStraight", max_episode_seconds=4.0)
    model = DQN("MultiInputPolicy", venv, learning_starts=16, buffer_size=1000, seed=0)
    model.learn(total_timesteps=200)
    assert model.num_timesteps >= 200
    assert len(model.ep_info_buffer) > 0
    assert len(model.ep_success_buffer) > 0


def test_vector_bad_actions() -> None:
    venv = RovVectorEnv(2, "PlanningStraight")
    venv.reset(seed=0)
    with pytest.raises(ValueError, match="actions"):
        venv.step(np.array([0, 7]))
    with pytest.raises(ValueError, match="actions"):
        venv.step(np.array([0]))
    with pytest.raises(ValueError, match="num_envs"):
        RovVectorEnv(0, "PlanningStraight")


def _child_steps_small_batch(queue) -> None:
    # eq. 18 at the exact start, without progress weighting: every reward 1.0
    venv = RovVectorEnv(4, "PlanningStraightDense", start_noise=(0.0, 0.0), progress_weighted=False)
    venv.reset(seed=1)
    queue.put(venv.step(np.full(4, 2))[1].tolist())


@pytest.mark.skipif(
    "fork" not in multiprocessing.get_all_start_methods(), reason="needs the fork start method"
)
def test_small_batches_work_in_forked_processes() -> None:
    """Below PARALLEL_MIN_ENVS no numba thread pool is used (GNU OpenMP aborts a forked child
    that touches a pool its parent had started)."""
    venv = RovVectorEnv(4, "PlanningStraight")
    venv.reset(seed=0)
    venv.step(np.full(4, 2))
    ctx = multiprocessing.get_context("fork")
    queue = ctx.Queue()
    child = ctx.Process(target=_child_steps_small_batch, args=(queue,))
    child.start()
    child.join(120)
    assert child.exitcode == 0
    assert queue.get(timeout=5) == pytest.approx([1.0] * 4)


def test_engine_refuses_bad_vehicle_indices() -> None:
    """The kernels do not check indices, so the engine must (no silent memory writes)."""
    from rov_envs.sim.engine import RovBatch

    batch = RovBatch(3, "PlanningStraight")
    for bad in (3, -1, 1.0, True):
        with pytest.raises(ValueError, match="vehicle index"):
            batch.reset_index(bad)
    with pytest.raises(ValueError, match="vehicle index"):
        batch.set_pose(7, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="pose"):
        batch.set_pose(0, float("nan"), 0.0, 0.0)
    with pytest.raises(ValueError, match="seeds"):
        batch.reset_all([0, 1])
    with pytest.raises(ValueError, match="together with config"):
        RovBatch(2, config=batch.config, sonar_noise=1.0)
