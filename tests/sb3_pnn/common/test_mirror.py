"""Mirrored minibatches (``DiscreteSAC(mirror=...)``): half of each sampled batch is replaced by
its mirror image (parts negated or reversed, actions swapped, rewards and ends kept), the map
is checked against the spaces with errors that name the bad value, and it survives a save."""

from __future__ import annotations

import json
import zipfile

import gymnasium as gym
import numpy as np
import pytest
import torch as th
from gymnasium import spaces
from stable_baselines3.common.type_aliases import DictReplayBufferSamples

import rov_envs
from sb3_pnn import DiscreteSAC
from sb3_pnn.common.buffers import DictNStepReplayBufferSamples
from sb3_pnn.common.mirror import MirroredBatches, check_mirror_map
from sb3_pnn.safe_io.checkpoint import JSON_MEMBER

OBS = spaces.Dict(
    {
        "path": spaces.Box(-1, 1, (2,)),
        "sonar": spaces.Box(0, 1, (3,)),
        "goal": spaces.Box(-1, 1, (1,)),
    }
)
MIRROR = {
    "actions": [3, 4, 2, 0, 1],
    "observations": {"path": "negate", "sonar": "reverse", "goal": "keep"},
}


def _observations(rng: np.random.Generator, n: int) -> dict[str, th.Tensor]:
    return {
        key: th.as_tensor(rng.random((n, *space.shape)), dtype=th.float32)
        for key, space in OBS.spaces.items()
    }


def _samples(n: int = 6) -> DictReplayBufferSamples:
    rng = np.random.default_rng(0)
    return DictReplayBufferSamples(
        observations=_observations(rng, n),
        actions=th.as_tensor(rng.integers(0, 5, (n, 1))),
        next_observations=_observations(rng, n),
        dones=th.as_tensor(rng.integers(0, 2, (n, 1)), dtype=th.float32),
        rewards=th.as_tensor(rng.random((n, 1)), dtype=th.float32),
    )


def _mirrored_part(key: str, value: th.Tensor) -> th.Tensor:
    return {"negate": -value, "reverse": value.flip(-1), "keep": value}[MIRROR["observations"][key]]


def test_the_first_half_is_mirrored_and_the_rest_kept() -> None:
    samples = _samples()
    out = MirroredBatches(check_mirror_map(MIRROR, OBS, spaces.Discrete(5)))(samples)
    for field in ("observations", "next_observations"):
        for key, value in getattr(samples, field).items():
            got = getattr(out, field)[key]
            assert th.equal(got[:3], _mirrored_part(key, value[:3])), (field, key)
            assert th.equal(got[3:], value[3:]), (field, key)
    swap = th.as_tensor(MIRROR["actions"])
    assert th.equal(out.actions[:3], swap[samples.actions[:3]])
    assert th.equal(out.actions[3:], samples.actions[3:])
    assert out.actions.dtype == samples.actions.dtype
    assert th.equal(out.rewards, samples.rewards) and th.equal(out.dones, samples.dones)
    # mirroring the mirrored rows again gives back the sample
    twice = MirroredBatches(MIRROR)(out)
    for key, value in samples.observations.items():
        assert th.equal(twice.observations[key], value)
    assert th.equal(twice.actions, samples.actions)


def test_the_one_step_successors_of_n_step_samples_are_mirrored_too() -> None:
    base = _samples()
    samples = DictNStepReplayBufferSamples(
        *base[:5], discounts=th.full((6, 1), 0.9), step_next_observations=base.observations
    )
    out = MirroredBatches(MIRROR)(samples)
    assert th.equal(
        out.step_next_observations["sonar"][:3], base.observations["sonar"][:3].flip(-1)
    )
    assert th.equal(out.discounts, samples.discounts)


@pytest.mark.parametrize(
    ("mirror", "match"),
    [
        ([3, 4, 2, 0, 1], "expected a dict with the keys 'actions' and 'observations'"),
        ({"actions": [1, 2, 3, 4, 0], "observations": MIRROR["observations"]},
         r"\[1, 2, 3, 4, 0\] is not allowed: .* its own inverse"),
        ({"actions": [3, 4, 2, 0], "observations": MIRROR["observations"]},
         r"mirror\['actions'\]=\[3, 4, 2, 0\] is not allowed: .* each of the 5"),
        ({"actions": MIRROR["actions"],
          "observations": {"path": "negate", "sonar": "flip", "goal": "keep"}},
         r"'flip'.* is not allowed: expected one of \['negate', 'reverse', 'keep'\]"),
        ({"actions": MIRROR["actions"], "observations": {"path": "negate"}},
         r"for each observation part \['goal', 'path', 'sonar'\]"),
    ],
)  # fmt: skip
def test_a_bad_map_is_refused_naming_the_value(mirror, match) -> None:
    with pytest.raises(ValueError, match=match):
        check_mirror_map(mirror, OBS, spaces.Discrete(5))


def test_one_map_serves_every_task_of_a_family() -> None:
    """rov_envs.LEFT_RIGHT_MIRROR names every part the tasks observe; a task observing fewer
    keeps the operations of its own parts."""
    env = gym.make("rov_envs/PathFollowingStraight-v0")
    checked = check_mirror_map(rov_envs.LEFT_RIGHT_MIRROR, env.observation_space, env.action_space)
    assert checked["observations"] == {"path": "negate", "motion": "negate"}


def test_a_map_needs_discrete_actions_and_named_parts() -> None:
    with pytest.raises(ValueError, match="needs discrete actions"):
        check_mirror_map(MIRROR, OBS, spaces.Box(-1, 1, (2,)))
    with pytest.raises(ValueError, match="needs a Dict observation space"):
        check_mirror_map(MIRROR, spaces.Box(-1, 1, (4,)), spaces.Discrete(5))
    with pytest.raises(ValueError, match=r"mirror\['actions'\]"):
        DiscreteSAC("MlpPolicy", gym.make("CartPole-v1"), mirror=MIRROR)


def test_training_reads_the_mirrored_batches_and_a_checkpoint_keeps_the_map(tmp_path) -> None:
    env = gym.make("rov_envs/PlanningStraight-v0")
    model = DiscreteSAC(
        "MultiInputPolicy", env, mirror=rov_envs.LEFT_RIGHT_MIRROR, learning_starts=32,
        batch_size=16, policy_kwargs={"net_arch": [8]}, seed=0,
    )  # fmt: skip
    seen = []
    forward = model.critic.forward
    model.critic.forward = lambda obs, *a: seen.append(obs) or forward(obs, *a)
    sample = model.replay_buffer.sample
    drawn = []
    model.replay_buffer.sample = lambda *a, **k: drawn.append(sample(*a, **k)) or drawn[-1]
    model.learn(40)
    assert drawn and len(seen) == len(drawn)
    path = drawn[0].observations["path"]
    assert not th.equal(-path[:8], path[:8])  # so that the check below can fail
    assert th.equal(seen[0]["path"][:8], -path[:8])
    assert th.equal(seen[0]["path"][8:], path[8:])
    model.save(tmp_path / "m.zip")
    loaded = DiscreteSAC.load(tmp_path / "m.zip", device="cpu")
    assert loaded.mirror == rov_envs.LEFT_RIGHT_MIRROR
    assert (
        DiscreteSAC.upgrade_checkpoint({"hyperparameters": {}})["hyperparameters"]["mirror"] is None
    )


@pytest.mark.parametrize(
    ("stored", "match"),
    [
        ("left-right", r"mirror='left-right' is not allowed: expected a dict or null"),
        (
            {"actions": [3, 4, 2, 0], "observations": rov_envs.LEFT_RIGHT_MIRROR["observations"]},
            r"mirror\['actions'\]=\[3, 4, 2, 0\] is not allowed",
        ),
    ],
)
def test_a_checkpoint_with_a_bad_map_is_refused(stored, match, tmp_path) -> None:
    env = gym.make("rov_envs/PathFollowingStraight-v0")
    model = DiscreteSAC(
        "MultiInputPolicy", env, mirror=rov_envs.LEFT_RIGHT_MIRROR, policy_kwargs={"net_arch": [8]}
    )
    model.save(tmp_path / "m.zip")
    with zipfile.ZipFile(tmp_path / "m.zip") as old:
        members = {info.filename: old.read(info) for info in old.infolist()}
    meta = json.loads(members[JSON_MEMBER])
    meta["hyperparameters"]["mirror"] = stored
    members[JSON_MEMBER] = json.dumps(meta).encode()
    with zipfile.ZipFile(tmp_path / "bad.zip", "w") as new:
        for name, data in members.items():
            new.writestr(name, data)
    with pytest.raises(ValueError, match=match):
        DiscreteSAC.load(tmp_path / "bad.zip", device="cpu")
