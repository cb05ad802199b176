"""RovMetricsCallback: per-episode mean |cross track| and success share, for TensorBoard."""

from __future__ import annotations

import numpy as np
import pytest
from stable_baselines3.common.env_util import make_vec_env

from sb3_pnn import DiscreteSAC
from sb3_pnn.zoo.callbacks import RovMetricsCallback


def step(callback: RovMetricsCallback, infos: list[dict], dones: list[bool]) -> None:
    callback.update_locals({"infos": infos, "dones": np.array(dones)})
    assert callback.on_step()


def test_records_episode_means_of_abs_cross_track_and_success() -> None:
    env = make_vec_env("rov_envs/PathFollowingStraight-v0", n_envs=2, seed=0)
    model = DiscreteSAC("MultiInputPolicy", env, buffer_size=10, policy_kwargs={"net_arch": [8]})
    model.set_logger(__import__("stable_baselines3").common.logger.configure(None, []))
    callback = RovMetricsCallback(window=2)
    callback.init_callback(model)
    values = model.logger.name_to_value
    step(
        callback,
        [{"cross_track": -2.0, "heading_error": 0.5}, {"cross_track": 1.0}],
        [False, False],
    )
    assert "rollout/abs_cross_track_mean" not in values  # nothing before an episode ends
    step(
        callback,
        [{"cross_track": 4.0, "heading_error": -0.1, "is_success": True}, {"cross_track": 3.0}],
        [True, False],
    )
    assert values["rollout/abs_cross_track_mean"] == pytest.approx(3.0)  # mean(|-2|, |4|)
    assert values["rollout/abs_heading_error_mean"] == pytest.approx(0.3)
    assert values["rollout/success_rate_rov"] == 1.0
    step(
        callback, [{"cross_track": 1.0}, {"cross_track": -5.0, "is_success": False}], [False, True]
    )
    assert values["rollout/abs_cross_track_mean"] == pytest.approx((3.0 + 3.0) / 2)  # env 1: 1,3,5
    assert values["rollout/success_rate_rov"] == 0.5
    step(callback, [{"cross_track": 0.0, "is_success": False}, {}], [True, False])
    # window 2: the last two episodes are env 1's (3.0) and env 0's second (mean(1, 0) = 0.5)
    assert values["rollout/abs_cross_track_mean"] == pytest.approx((3.0 + 0.5) / 2)
    assert values["rollout/success_rate_rov"] == 0.0
    env.close()


def test_window_must_be_positive() -> None:
    with pytest.raises(ValueError, match="window"):
        RovMetricsCallback(window=0)
