"""Safe prior loading: weights and spaces read without unpickling, clear errors, malicious zips."""

from __future__ import annotations

import base64
import io
import json
import pickle
import zipfile
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch as th
from gymnasium import spaces
from stable_baselines3 import DQN, SAC
from stable_baselines3.common.save_util import load_from_zip_file

from sb3_pnn import DiscreteSAC
from sb3_pnn.progressive.obs_spec import obs_spec_from_space
from sb3_pnn.progressive.prior_loading import load_prior


def test_dqn_prior_columns_match_the_model(priors):
    prior = load_prior(priors["pf_dqn"])
    model = DQN.load(priors["pf_dqn"])  # trusted here: only to compare weights
    assert prior.spec.algo == "dqn"
    assert prior.spec.obs == obs_spec_from_space(model.observation_space)
    assert prior.spec.actor.hidden == (16, 12) and prior.spec.n_actions == 5
    linears = [m for m in model.q_net.q_net if isinstance(m, th.nn.Linear)]
    for (w, b), lin in zip(prior.actor_layers, linears, strict=True):
        assert th.equal(w, lin.weight) and th.equal(b, lin.bias)
    assert len(prior.critic_layers) == 1


def test_dsac_prior_columns_match_the_model(priors):
    prior = load_prior(priors["oa_dsac"])
    model = DiscreteSAC.load(priors["oa_dsac"])
    assert prior.spec.algo == "dsac"
    assert prior.spec.obs.keys == ("path", "sonar") and prior.spec.obs.flat_dim == 11
    assert th.equal(prior.actor_layers[-1][0], model.actor.action_logits.weight)
    assert len(prior.critic_layers) == 2
    q1 = [m for m in model.critic.q_networks[1] if isinstance(m, th.nn.Linear)]
    assert th.equal(prior.critic_layers[1][0][0], q1[0].weight)


def test_box_prior_bounds_and_activation_read(tmp_path):
    env = gym.make("CartPole-v1")
    DQN("MlpPolicy", env, policy_kwargs=dict(net_arch=[8], activation_fn=th.nn.Tanh)).save(
        tmp_path / "cp.zip"
    )
    prior = load_prior(tmp_path / "cp.zip")
    assert prior.spec.actor.activation == "Tanh"
    (saved,) = prior.spec.obs.parts
    (live,) = obs_spec_from_space(env.observation_space).parts
    assert saved.same_space(live)  # bounds parsed from the repr, float32-rounded
    assert saved.low[1] == -np.inf and saved.high[0] == pytest.approx(4.8)


class _Payload:
    """Unpickling this creates the marker file (stands for arbitrary code in a checkpoint)."""

    def __init__(self, marker: Path):
        self.marker = str(marker)

    def __reduce__(self):
        return (exec, (f"open({self.marker!r}, 'w').write('pwned')",))


def _malicious_copy(src: Path, dst: Path, marker: Path, poison_policy: bool = False) -> None:
    blob = base64.b64encode(pickle.dumps(_Payload(marker))).decode()
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w") as zout:
        for name in zin.namelist():
            content = zin.read(name)
            if name == "data":
                data = json.loads(content)
                for key in ("observation_space", "action_space", "policy_kwargs"):
                    if isinstance(data[key], dict):
                        data[key][":serialized:"] = blob
                    else:
                        data[key] = {":type:": "<class 'dict'>", ":serialized:": blob}
                content = json.dumps(data).encode()
            if name == "policy.pth" and poison_policy:
                buf = io.BytesIO()
                th.save({"q_net.q_net.0.weight": _Payload(marker)}, buf)
                content = buf.getvalue()
            zout.writestr(name, content)


def test_malicious_data_part_runs_nothing(priors, tmp_path):
    marker = tmp_path / "marker"
    bad = tmp_path / "bad.zip"
    _malicious_copy(priors["pf_dqn"], bad, marker)
    prior = load_prior(bad)
    assert not marker.exists()
    assert prior.spec.actor.hidden == (16, 12)
    # The payload is live: SB3's ordinary loading of the data part runs it.
    load_from_zip_file(bad, load_data=True)
    assert marker.exists()


def test_malicious_weights_refused_without_running(priors, tmp_path):
    marker = tmp_path / "marker"
    bad = tmp_path / "bad_pth.zip"
    _malicious_copy(priors["pf_dqn"], bad, marker, poison_policy=True)
    with pytest.raises(ValueError, match="bad_pth.zip"):
        load_prior(bad)
    assert not marker.exists()


def test_missing_and_non_sb3_files(tmp_path):
    with pytest.raises(FileNotFoundError, match="nope.zip"):
        load_prior(tmp_path / "nope.zip")
    (tmp_path / "text.zip").write_text("not a zip")
    with pytest.raises(ValueError, match="text.zip.*not a zip"):
        load_prior(tmp_path / "text.zip")
    with zipfile.ZipFile(tmp_path / "other.zip", "w") as z:
        z.writestr("hello.txt", "hi")
    with pytest.raises(ValueError, match=r"other.zip.*missing \['data', 'policy.pth'\]"):
        load_prior(tmp_path / "other.zip")


def test_continuous_policy_refused(tmp_path):
    env = gym.make("Pendulum-v1")
    SAC("MlpPolicy", env, policy_kwargs=dict(net_arch=[8])).save(tmp_path / "sac.zip")
    with pytest.raises(ValueError, match="sac.zip.*Discrete action space"):
        load_prior(tmp_path / "sac.zip")


def test_space_and_weights_cross_checked(priors, tmp_path):
    bad = tmp_path / "lying.zip"
    with zipfile.ZipFile(priors["pf_dqn"]) as zin, zipfile.ZipFile(bad, "w") as zout:
        for name in zin.namelist():
            content = zin.read(name)
            if name == "data":
                data = json.loads(content)
                data["observation_space"]["spaces"] = "{'path': Box(-1.0, 1.0, (3,), float32)}"
                content = json.dumps(data).encode()
            zout.writestr(name, content)
    with pytest.raises(ValueError, match="lying.zip.*takes 2 inputs.*flattens to 3"):
        load_prior(bad)


def test_unsupported_dict_part_refused(tmp_path):
    class DiscreteObsEnv(gym.Env):
        observation_space = spaces.Dict({"a": spaces.Discrete(3), "b": spaces.Box(0, 1, (2,))})
        action_space = spaces.Discrete(2)

        def reset(self, seed=None, options=None):
            return self.observation_space.sample(), {}

        def step(self, a):
            return self.observation_space.sample(), 0.0, True, False, {}

    DQN("MultiInputPolicy", DiscreteObsEnv()).save(tmp_path / "disc.zip")
    with pytest.raises(ValueError, match="disc.zip.*'a'.*only Box parts"):
        load_prior(tmp_path / "disc.zip")
