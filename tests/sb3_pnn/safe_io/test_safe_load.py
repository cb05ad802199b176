"""Loading a checkpoint never runs code from it: DiscreteSAC.load reads only the sb3_pnn.json
member and the weights, replay buffers are .npz archives, pickles are refused."""

from __future__ import annotations

import base64
import io
import json
import pickle
import zipfile
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
import torch as th
from gymnasium import spaces
from stable_baselines3.common.off_policy_algorithm import OffPolicyAlgorithm
from stable_baselines3.common.utils import LinearSchedule

from sb3_pnn import DiscreteSAC
from sb3_pnn.dsac.policies import DiscreteSACPolicy
from sb3_pnn.safe_io import register_policy_class
from sb3_pnn.safe_io.checkpoint import JSON_MEMBER, UnsafeCheckpointError


class MarkerPayload:
    """Unpickling this creates ``path`` (stands in for arbitrary code)."""

    def __init__(self, path: Path) -> None:
        self.path = str(path)

    def __reduce__(self) -> tuple[Any, ...]:
        return (open, (self.path, "w"))


def payload_b64(marker: Path) -> str:
    return base64.b64encode(pickle.dumps(MarkerPayload(marker))).decode()


def small_model(env: Any = "CartPole-v1", **kwargs: Any) -> DiscreteSAC:
    defaults = dict(
        learning_starts=30,
        batch_size=16,
        buffer_size=500,
        policy_kwargs=dict(net_arch=[8, 8]),
        seed=3,
        device="cpu",
    )
    defaults.update(kwargs)
    return DiscreteSAC("MlpPolicy", env, **defaults)  # type: ignore[arg-type]


def replace_member(zip_path: Path, member: str, content: bytes | None) -> None:
    """Rewrite ``zip_path`` with ``member`` replaced (or removed when ``content`` is None)."""
    with zipfile.ZipFile(zip_path) as archive:
        items = {n: archive.read(n) for n in archive.namelist()}
    if content is None:
        del items[member]
    else:
        items[member] = content
    with zipfile.ZipFile(zip_path, "w") as archive:
        for name, data in items.items():
            archive.writestr(name, data)


def same_predictions(a: DiscreteSAC, b: DiscreteSAC, obs: Any) -> None:
    np.testing.assert_array_equal(
        a.predict(obs, deterministic=True)[0], b.predict(obs, deterministic=True)[0]
    )


OBS = np.random.default_rng(0).normal(size=(32, 4)).astype(np.float32)


def test_malicious_data_part_is_never_unpickled(tmp_path: Path) -> None:
    model = small_model()
    model.learn(100)
    path, live = tmp_path / "evil.zip", tmp_path / "live.zip"
    model.save(path)
    model.save(live)
    marker = tmp_path / "pwned"
    with zipfile.ZipFile(path) as archive:
        data = json.loads(archive.read("data"))
    evil = {":type:": "<class 'object'>", ":serialized:": payload_b64(marker)}
    replace_member(live, "data", json.dumps({**data, "lr_schedule": evil}).encode())
    for key in ("policy_class", "observation_space", "action_space", "lr_schedule"):
        data[key] = evil
    replace_member(path, "data", json.dumps(data).encode())

    loaded = DiscreteSAC.load(path, device="cpu")
    assert not marker.exists()
    same_predictions(model, loaded, OBS)
    assert loaded.num_timesteps == model.num_timesteps

    # The payload is live: SB3's pickle-based load (trust_pickle=True) does run it.
    DiscreteSAC.load(live, device="cpu", trust_pickle=True)
    assert marker.exists()


def test_plain_sb3_zip_is_refused_unless_trusted(tmp_path: Path) -> None:
    model = small_model()
    OffPolicyAlgorithm.save(model, tmp_path / "plain.zip")  # SB3's own save: no JSON member
    with pytest.raises(UnsafeCheckpointError, match=r"plain\.zip.*trust_pickle=True"):
        DiscreteSAC.load(tmp_path / "plain.zip")
    trusted = DiscreteSAC.load(tmp_path / "plain.zip", device="cpu", trust_pickle=True)
    same_predictions(model, trusted, OBS)
    trusted.save(tmp_path / "converted.zip")  # re-saving gives a safe checkpoint
    same_predictions(model, DiscreteSAC.load(tmp_path / "converted.zip"), OBS)


def test_trusted_zip_of_another_algorithm_gives_a_clear_error(tmp_path: Path) -> None:
    from stable_baselines3 import DQN

    DQN("MlpPolicy", "CartPole-v1", policy_kwargs=dict(net_arch=[8])).save(tmp_path / "dqn.zip")
    with pytest.raises(UnsafeCheckpointError, match="trust_pickle=True"):
        DiscreteSAC.load(tmp_path / "dqn.zip")
    with pytest.raises(ValueError) as info:
        DiscreteSAC.load(tmp_path / "dqn.zip", device="cpu", trust_pickle=True)
    message = str(info.value)
    assert "dqn.zip' is not a DiscreteSAC checkpoint" in message
    assert "its policy is stable_baselines3.dqn.policies.DQNPolicy" in message
    assert "stable_baselines3.DQN.load" in message and "priors=[path]" in message


def test_constructor_refuses_a_policy_without_actor_and_critics() -> None:
    from stable_baselines3.dqn.policies import DQNPolicy

    with pytest.raises(TypeError, match="needs a DiscreteSACPolicy.*DQNPolicy"):
        DiscreteSAC(DQNPolicy, "CartPole-v1")


def test_saved_zip_keeps_sb3_parts_and_a_json_member(tmp_path: Path) -> None:
    small_model().save(tmp_path / "m")  # SB3 naming: .zip added
    with zipfile.ZipFile(tmp_path / "m.zip") as archive:
        names = set(archive.namelist())
        meta = json.loads(archive.read(JSON_MEMBER))
    assert {"data", "policy.pth", "pytorch_variables.pth", JSON_MEMBER} <= names
    assert meta["policy_class"] == "DiscreteSACPolicy"
    assert meta["observation_space"]["type"] == "Box"
    assert meta["hyperparameters"]["policy_kwargs"] == {"net_arch": [8, 8]}
    assert DiscreteSAC.load(tmp_path / "m").policy_kwargs == {"net_arch": [8, 8]}


def test_bad_files_give_clear_errors(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="missing.zip"):
        DiscreteSAC.load(tmp_path / "missing.zip")
    (tmp_path / "text.zip").write_text("not a zip")
    with pytest.raises(ValueError, match=r"text\.zip.*not a valid zip"):
        DiscreteSAC.load(tmp_path / "text.zip")
    small_model().save(tmp_path / "ok.zip")
    raw = (tmp_path / "ok.zip").read_bytes()
    (tmp_path / "cut.zip").write_bytes(raw[: len(raw) // 2])
    with pytest.raises(ValueError, match=r"cut\.zip"):
        DiscreteSAC.load(tmp_path / "cut.zip")
    replace_member(tmp_path / "ok.zip", JSON_MEMBER, b"{not json")
    with pytest.raises(ValueError, match=r"ok\.zip.*not valid JSON"):
        DiscreteSAC.load(tmp_path / "ok.zip")


def test_env_with_other_spaces_is_refused(tmp_path: Path) -> None:
    small_model().save(tmp_path / "cp.zip")
    with pytest.raises(ValueError, match=r"observation space is Box.*checkpoint's is Box"):
        DiscreteSAC.load(tmp_path / "cp.zip", env=gym.make("Acrobot-v1"))


def test_zoo_style_custom_objects_and_kwargs(tmp_path: Path) -> None:
    model = small_model()
    model.save(tmp_path / "z.zip")
    custom_objects = {
        "learning_rate": 0.0,
        "lr_schedule": lambda _: 0.0,
        "exploration_schedule": lambda _: 0.0,
        "clip_range": lambda _: 0.0,
    }
    loaded = DiscreteSAC.load(
        tmp_path / "z.zip", custom_objects=custom_objects, device="cpu", seed=7, buffer_size=1
    )
    assert loaded.learning_rate == 0.0 and loaded.buffer_size == 1 and loaded.seed == 7
    same_predictions(model, loaded, OBS)


def test_learning_rate_schedules(tmp_path: Path) -> None:
    linear = small_model(learning_rate=LinearSchedule(1e-3, 1e-4, 0.5))
    linear.save(tmp_path / "lin.zip")
    loaded = DiscreteSAC.load(tmp_path / "lin.zip")
    assert loaded.lr_schedule(1.0) == 1e-3 and loaded.lr_schedule(0.0) == 1e-4

    small_model(learning_rate=lambda p: 1e-3 * p).save(tmp_path / "fn.zip")
    with pytest.raises(ValueError, match="custom_objects=.*learning_rate"):
        DiscreteSAC.load(tmp_path / "fn.zip")
    loaded = DiscreteSAC.load(tmp_path / "fn.zip", custom_objects={"learning_rate": 5e-4})
    assert loaded.lr_schedule(0.3) == 5e-4


class UnregisteredPolicy(DiscreteSACPolicy):
    pass


def test_policy_class_must_be_registered(tmp_path: Path) -> None:
    model = DiscreteSAC(UnregisteredPolicy, "CartPole-v1", buffer_size=100, device="cpu")
    with pytest.raises(ValueError, match="register_policy_class"):
        model.save(tmp_path / "u.zip")
    assert not (tmp_path / "u.zip").exists()
    register_policy_class("tests.UnregisteredPolicy", UnregisteredPolicy)
    model.save(tmp_path / "u.zip")
    assert type(DiscreteSAC.load(tmp_path / "u.zip").policy) is UnregisteredPolicy
    with zipfile.ZipFile(tmp_path / "u.zip") as archive:
        meta = json.loads(archive.read(JSON_MEMBER))
    meta["policy_class"] = "os.system"
    replace_member(tmp_path / "u.zip", JSON_MEMBER, json.dumps(meta).encode())
    with pytest.raises(ValueError, match="'os.system', which is not registered"):
        DiscreteSAC.load(tmp_path / "u.zip")


def test_unknown_class_in_policy_kwargs_is_refused(tmp_path: Path) -> None:
    small_model().save(tmp_path / "k.zip")
    with zipfile.ZipFile(tmp_path / "k.zip") as archive:
        meta = json.loads(archive.read(JSON_MEMBER))
    meta["hyperparameters"]["policy_kwargs"]["activation_fn"] = {"$class": "builtins.eval"}
    replace_member(tmp_path / "k.zip", JSON_MEMBER, json.dumps(meta).encode())
    with pytest.raises(ValueError, match="'builtins.eval', which is not in the allowlist"):
        DiscreteSAC.load(tmp_path / "k.zip")


class DictEnv(gym.Env):
    """Dict observation with a sonar part (as the ROV tasks), five actions."""

    def __init__(self) -> None:
        self.observation_space = spaces.Dict(
            {
                "path": spaces.Box(-1.0, 1.0, (2,), np.float32),
                "sonar": spaces.Box(0.0, 1.0, (3,), np.float32),
            }
        )
        self.action_space = spaces.Discrete(5)
        self.t = 0

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[Any, dict]:
        super().reset(seed=seed)
        self.t = 0
        return self.observation_space.sample(), {}

    def step(self, action: int) -> tuple[Any, float, bool, bool, dict]:
        self.t += 1
        return self.observation_space.sample(), float(action == 2), False, self.t >= 20, {}


def test_replay_buffer_round_trip_dict_and_partial(tmp_path: Path) -> None:
    model = DiscreteSAC(
        "MultiInputPolicy", DictEnv(), buffer_size=300, learning_starts=40, batch_size=8,
        policy_kwargs=dict(net_arch=[8]), seed=0, device="cpu",
    )  # fmt: skip
    model.learn(100)
    model.save_replay_buffer(tmp_path / "buf")  # SB3 naming: .pkl added, content is .npz
    with np.load(tmp_path / "buf.pkl", allow_pickle=False) as archive:
        assert "__meta__" in archive.files
    other = DiscreteSAC(
        "MultiInputPolicy", DictEnv(), buffer_size=10, policy_kwargs=dict(net_arch=[8]),
        device="cpu",
    )  # fmt: skip
    other.load_replay_buffer(tmp_path / "buf")
    a, b = model.replay_buffer, other.replay_buffer
    assert (b.pos, b.full, b.buffer_size) == (a.pos, a.full, a.buffer_size) and 0 < a.pos < 300
    for key in a.observations:
        np.testing.assert_array_equal(a.observations[key], b.observations[key])
        np.testing.assert_array_equal(a.next_observations[key], b.next_observations[key])
    for name in ("actions", "rewards", "dones", "timeouts"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    other.learn(50)  # trains from the loaded buffer

    cartpole = small_model()
    with pytest.raises(ValueError, match="holds observations of Dict"):
        cartpole.load_replay_buffer(tmp_path / "buf.pkl")


def test_pickled_replay_buffer_is_refused(tmp_path: Path) -> None:
    marker = tmp_path / "pwned"
    (tmp_path / "evil.pkl").write_bytes(pickle.dumps(MarkerPayload(marker)))
    model = small_model()
    with pytest.raises(UnsafeCheckpointError, match=r"evil\.pkl.*trust_pickle=True"):
        model.load_replay_buffer(tmp_path / "evil.pkl")
    assert not marker.exists()
    # a genuine SB3 pickle too, unless trusted
    model.learn(60)
    OffPolicyAlgorithm.save_replay_buffer(model, tmp_path / "sb3.pkl")
    with pytest.raises(UnsafeCheckpointError):
        model.load_replay_buffer(tmp_path / "sb3.pkl")
    model.load_replay_buffer(tmp_path / "sb3.pkl", trust_pickle=True)
    assert model.replay_buffer.pos > 0
    # file objects work as well
    stream = io.BytesIO()
    model.save_replay_buffer(stream)
    stream.seek(0)
    model.load_replay_buffer(stream)


def make_prior(tmp_path: Path, name: str) -> str:
    prior = DiscreteSAC(
        "MultiInputPolicy", DictEnv(), buffer_size=50, policy_kwargs=dict(net_arch=[8, 8]),
        seed=hash(name) % 100, device="cpu",
    )  # fmt: skip
    path = str(tmp_path / f"{name}.zip")
    prior.save(path)
    return path


@pytest.mark.parametrize("policy_name", ["ProgressivePolicy", "SelectivePolicy"])
def test_progressive_round_trip(tmp_path: Path, policy_name: str) -> None:
    progressive = pytest.importorskip("sb3_pnn.progressive")
    policy_class = getattr(progressive, policy_name)
    priors = [make_prior(tmp_path, "pf"), make_prior(tmp_path, "oa")]
    model = DiscreteSAC(
        policy_class, DictEnv(), policy_kwargs=dict(priors=priors, net_arch=[8, 8]),
        buffer_size=200, learning_starts=20, batch_size=8, seed=0, device="cpu",
    )  # fmt: skip
    model.learn(60)
    model.save(tmp_path / "model.zip")
    for p in priors:
        Path(p).unlink()
    loaded = DiscreteSAC.load(tmp_path / "model.zip", env=DictEnv())
    assert type(loaded.policy) is policy_class
    obs = {
        k: np.stack([s.sample() for _ in range(16)]) for k, s in DictEnv().observation_space.items()
    }
    same_predictions(model, loaded, obs)
    for key, value in model.policy.state_dict().items():
        assert th.equal(value, loaded.policy.state_dict()[key]), key
    loaded.learn(30)


def test_space_codec_round_trip() -> None:
    from collections import OrderedDict

    from sb3_pnn.safe_io import space_from_json, space_to_json

    cases = [
        spaces.Box(np.array([-np.inf, -1.5], np.float32), np.array([np.inf, 2.25], np.float32)),
        spaces.Box(0, 255, (3, 4), np.uint8),
        spaces.Discrete(5, start=-2),
        spaces.MultiDiscrete([3, 4]),
        spaces.MultiBinary(6),
        spaces.Dict(
            OrderedDict([("z", spaces.Discrete(2)), ("a", spaces.Box(-1, 1, (2,), np.float64))])
        ),
    ]
    for space in cases:
        encoded = json.loads(json.dumps(space_to_json(space), allow_nan=False))
        decoded = space_from_json(encoded)
        assert decoded == space and decoded.dtype == space.dtype, space
    assert list(space_from_json(space_to_json(cases[-1])).spaces) == ["z", "a"]
    with pytest.raises(ValueError, match="unsupported space type 'Tuple'"):
        space_from_json({"type": "Tuple"})
    with pytest.raises(ValueError, match="cannot store"):
        space_to_json(spaces.Text(5))
