"""DiscreteSACPolicy.predict gives SB3's BasePolicy.predict answers, with SB3's errors."""

import gymnasium as gym
import numpy as np
import pytest
import torch as th
from gymnasium import spaces
from stable_baselines3.common.policies import BasePolicy

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC
from sb3_pnn.dsac.lean_predict import lean_obs_to_tensor, lean_space_shapes


def _both(policy, obs, deterministic: bool) -> tuple[np.ndarray, np.ndarray]:
    """(ours, SB3's) actions from the same observation and the same torch random state."""
    th.manual_seed(3)
    ours, _ = policy.predict(obs, deterministic=deterministic)
    th.manual_seed(3)
    sb3, _ = BasePolicy.predict(policy, obs, deterministic=deterministic)
    return ours, sb3


@pytest.mark.parametrize("env_id", ["CartPole-v1", "rov_envs/PlanningStraight-v0"])
def test_same_actions_as_sb3(env_id: str) -> None:
    env = gym.make(env_id)
    is_dict = isinstance(env.observation_space, spaces.Dict)
    policy_name = "MultiInputPolicy" if is_dict else "MlpPolicy"
    model = DiscreteSAC(policy_name, env, policy_kwargs={"net_arch": [16]}, device="cpu", seed=0)
    obs, _ = env.reset(seed=0)
    batch = [env.observation_space.sample() for _ in range(7)]
    if isinstance(obs, dict):
        stacked = {k: np.stack([o[k] for o in batch]) for k in obs}
    else:
        stacked = np.stack(batch)
    shapes = lean_space_shapes(env.observation_space)
    for observation, shape in ((obs, ()), (stacked, (7,))):
        assert lean_obs_to_tensor(shapes, observation, th.device("cpu")) is not None
        for deterministic in (True, False):
            ours, sb3 = _both(model.policy, observation, deterministic)
            assert ours.shape == sb3.shape == shape
            assert ours.dtype == sb3.dtype
            np.testing.assert_array_equal(ours, sb3)


def test_bad_shapes_get_sb3s_error() -> None:
    model = DiscreteSAC("MlpPolicy", "CartPole-v1", policy_kwargs={"net_arch": [8]}, device="cpu")
    with pytest.raises(ValueError, match=r"Unexpected observation shape \(3,\)"):
        model.predict(np.zeros(3, dtype=np.float32))


def test_what_the_lean_path_leaves_to_sb3() -> None:
    box = spaces.Box(-1, 1, (3,), np.float32)
    image = spaces.Box(0, 255, (8, 8, 3), np.uint8)
    assert lean_space_shapes(spaces.Discrete(4)) is None
    assert lean_space_shapes(image) is None
    assert lean_space_shapes(spaces.Dict({"a": box, "img": image})) is None
    shapes = lean_space_shapes(spaces.Dict({"a": box, "b": spaces.Box(0, 1, (2, 2))}))
    assert shapes == {"a": (3,), "b": (2, 2)}
    cpu = th.device("cpu")
    ok = {"a": np.zeros(3, np.float32), "b": np.zeros((2, 2), np.float32)}
    tensors, vectorized = lean_obs_to_tensor(shapes, ok, cpu)
    assert not vectorized and tensors["a"].shape == (1, 3) and tensors["b"].shape == (1, 2, 2)
    # not handled here (SB3 decides): lists, missing keys, mixed batch / no batch, bad shapes
    assert lean_obs_to_tensor(shapes, {"a": [0, 0, 0], "b": ok["b"]}, cpu) is None
    assert lean_obs_to_tensor(shapes, {"a": ok["a"]}, cpu) is None
    assert lean_obs_to_tensor(shapes, {"a": np.zeros((5, 3)), "b": ok["b"]}, cpu) is None
    assert lean_obs_to_tensor({None: (3,)}, np.zeros(4), cpu) is None


def test_tensor_does_not_share_the_callers_array() -> None:
    array = np.zeros((2, 3), np.float32)
    tensor, vectorized = lean_obs_to_tensor({None: (3,)}, array, th.device("cpu"))
    assert vectorized
    array[:] = 1.0
    assert float(tensor.sum()) == 0.0


def test_a_replaced_actor_is_the_one_that_predicts() -> None:
    model = DiscreteSAC("MlpPolicy", "CartPole-v1", policy_kwargs={"net_arch": [8]}, device="cpu")
    obs = np.stack([model.observation_space.sample() for _ in range(16)])
    model.predict(obs)  # the lean path keeps the actor it read the device from
    model.policy.actor = model.policy.make_actor()
    with th.no_grad():
        expected = model.policy.actor(th.as_tensor(obs)).argmax(dim=1).numpy()
    np.testing.assert_array_equal(model.predict(obs, deterministic=True)[0], expected)
