"""n-step returns for Dict observations: sums, bootstrap discounts, episode ends, save/load."""

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch as th
from gymnasium import spaces

from sb3_pnn import DiscreteSAC
from sb3_pnn.common.buffers import DictNStepReplayBuffer

OBS = spaces.Dict({"x": spaces.Box(-100, 100, (1,), np.float32)})


def filled_buffer(n_steps: int = 3, gamma: float = 0.5) -> DictNStepReplayBuffer:
    """Rewards r_t = t for t = 0..9: the first episode ends terminal at t = 4, the second is
    truncated at t = 7, the third is still running at t = 9 (the newest row)."""
    buffer = DictNStepReplayBuffer(100, OBS, spaces.Discrete(5), n_steps=n_steps, gamma=gamma)
    ends = {4: (True, False), 7: (True, True)}
    for t in range(10):
        done, truncated = ends.get(t, (False, False))
        buffer.add(
            {"x": np.array([[t]], np.float32)},
            {"x": np.array([[t + 1]], np.float32)},
            np.array([[0]]),
            np.array([float(t)]),
            np.array([done]),
            [{"TimeLimit.truncated": truncated}],
        )
    return buffer


def test_returns_stop_at_episode_ends_and_at_the_newest_row() -> None:
    samples = filled_buffer()._get_samples(np.array([0, 3, 4, 5, 6, 8, 9]))
    # by hand, gamma = 0.5: 0 + .5*1 + .25*2; 3 + .5*4 (terminal); 4; 5 + .5*6 + .25*7
    # (truncated: bootstraps); 6 + .5*7; 8 + .5*9 (row 9 is the newest); 9
    assert samples.rewards.flatten().tolist() == [1.0, 5.0, 4.0, 9.75, 9.5, 12.5, 9.0]
    assert samples.discounts.flatten().tolist() == [0.125, 0.25, 0.5, 0.125, 0.25, 0.25, 0.5]
    assert samples.next_observations["x"].flatten().tolist() == [3, 5, 5, 8, 8, 10, 10]
    # terminal only where the episode ended by itself; a truncation bootstraps
    assert samples.dones.flatten().tolist() == [0, 1, 1, 0, 0, 0, 0]
    assert samples.observations["x"].flatten().tolist() == [0, 3, 4, 5, 6, 8, 9]


def test_one_step_is_the_dict_buffer() -> None:
    samples = filled_buffer(n_steps=1)._get_samples(np.arange(10))
    assert samples.rewards.flatten().tolist() == [float(t) for t in range(10)]
    assert samples.next_observations["x"].flatten().tolist() == [t + 1 for t in range(10)]
    assert samples.dones.flatten().tolist() == [0, 0, 0, 0, 1, 0, 0, 0, 0, 0]


@pytest.mark.parametrize(
    ("kwargs", "word"), [({"n_steps": 0}, "n_steps"), ({"gamma": 1.5}, "gamma")]
)
def test_bad_arguments_are_named(kwargs: dict, word: str) -> None:
    with pytest.raises(ValueError, match=word):
        DictNStepReplayBuffer(10, OBS, spaces.Discrete(5), **kwargs)


class DictCartPole(gym.ObservationWrapper):
    def __init__(self) -> None:
        super().__init__(gym.make("CartPole-v1"))
        self.observation_space = spaces.Dict({"x": self.env.observation_space})

    def observation(self, observation):
        return {"x": observation}


def test_discrete_sac_picks_it_for_dict_observations_and_round_trips(tmp_path: Path) -> None:
    model = DiscreteSAC(
        "MultiInputPolicy",
        DictCartPole(),
        n_steps=4,
        learning_starts=50,
        batch_size=16,
        buffer_size=1000,
        policy_kwargs=dict(net_arch=[16, 16]),
        seed=0,
        device="cpu",
    )
    assert isinstance(model.replay_buffer, DictNStepReplayBuffer)
    assert (model.replay_buffer.n_steps, model.replay_buffer.gamma) == (4, model.gamma)
    model.learn(200)
    model.save(tmp_path / "model.zip")
    model.save_replay_buffer(tmp_path / "buffer.pkl")
    loaded = DiscreteSAC.load(tmp_path / "model.zip", env=DictCartPole(), device="cpu")
    assert loaded.n_steps == 4 and isinstance(loaded.replay_buffer, DictNStepReplayBuffer)
    loaded.load_replay_buffer(tmp_path / "buffer.pkl")
    assert isinstance(loaded.replay_buffer, DictNStepReplayBuffer)
    assert loaded.replay_buffer.n_steps == 4 and loaded.replay_buffer.pos == model.replay_buffer.pos
    np.testing.assert_array_equal(loaded.replay_buffer.rewards, model.replay_buffer.rewards)
    for key, value in model.policy.state_dict().items():
        th.testing.assert_close(loaded.policy.state_dict()[key], value, rtol=0, atol=0)
    loaded.learn(100)  # resumes with n-step samples
