"""The policy module: documented module names, output shapes, argmax and sampled actions."""

import gymnasium as gym
import numpy as np
import torch as th
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor

from sb3_pnn import DiscreteSAC
from sb3_pnn.dsac.policies import actions_from_logits


def test_module_names_and_shapes() -> None:
    model = DiscreteSAC(
        "MlpPolicy",
        "CartPole-v1",
        policy_kwargs=dict(net_arch=dict(pi=[7, 5], qf=[6]), n_critics=3),
    )
    keys = set(model.policy.state_dict())
    for key in (
        "actor.latent_pi.0.weight",
        "actor.latent_pi.2.bias",
        "actor.action_logits.weight",
        "critic.q_networks.0.0.weight",
        "critic.q_networks.2.2.bias",
        "critic_target.q_networks.1.2.weight",
    ):
        assert key in keys, key
    assert model.actor.action_logits.weight.shape == (2, 5)
    assert model.critic.q_networks[1][2].weight.shape == (2, 6)
    obs = th.zeros(4, 4)
    assert model.actor(obs).shape == (4, 2)
    q_values = model.critic(obs)
    assert isinstance(q_values, tuple) and len(q_values) == 3
    assert all(q.shape == (4, 2) for q in q_values)


def test_deterministic_predict_is_argmax_of_logits() -> None:
    model = DiscreteSAC("MlpPolicy", "CartPole-v1", seed=3)
    obs = np.random.default_rng(3).normal(size=(50, 4)).astype(np.float32)
    with th.no_grad():
        expected = model.actor(th.as_tensor(obs)).argmax(dim=1).numpy()
    np.testing.assert_array_equal(model.predict(obs, deterministic=True)[0], expected)


def test_sampled_actions_follow_the_softmax() -> None:
    th.manual_seed(0)
    logits = th.tensor([[0.0, 1.0, -1.0, 2.0, 0.5]]).repeat(40_000, 1)
    counts = np.bincount(actions_from_logits(logits).numpy(), minlength=5) / 40_000
    np.testing.assert_allclose(counts, th.softmax(logits[0], 0).numpy(), atol=0.01)


def test_discrete_action_space_sizes() -> None:
    env = gym.make("Acrobot-v1")  # Discrete(3)
    model = DiscreteSAC("MlpPolicy", env, policy_kwargs=dict(net_arch=[8]))
    assert model.actor.action_logits.out_features == 3
    assert abs(model.target_entropy - model.target_entropy_ratio * np.log(3)) < 1e-9


def test_training_mode_switches_actor_and_critic_only() -> None:
    model = DiscreteSAC("MlpPolicy", "CartPole-v1", policy_kwargs=dict(net_arch=[8]))
    policy = model.policy
    for mode in (False, True, True, False, False):
        policy.set_training_mode(mode)
        assert policy.training == mode
        assert all(m.training == mode for m in policy.actor.modules())
        assert all(m.training == mode for m in policy.critic.modules())
        assert not any(m.training for m in policy.critic_target.modules())
    # A mode changed by hand underneath is put right by the next switch
    policy.actor.latent_pi.train()
    policy.set_training_mode(False)
    assert not any(m.training for m in policy.actor.modules())


def test_shared_features_extractor_is_trained_by_the_actor_only() -> None:
    class LinearExtractor(BaseFeaturesExtractor):
        """A features extractor with parameters, to see who optimizes them."""

        def __init__(self, observation_space: gym.spaces.Box) -> None:
            super().__init__(observation_space, features_dim=6)
            self.linear = th.nn.Linear(4, 6)

        def forward(self, obs: th.Tensor) -> th.Tensor:
            return th.relu(self.linear(obs))

    model = DiscreteSAC(
        "MlpPolicy",
        "CartPole-v1",
        learning_starts=0,
        batch_size=8,
        buffer_size=1000,
        policy_kwargs=dict(
            net_arch=[8], share_features_extractor=True, features_extractor_class=LinearExtractor
        ),
    )
    extractor = model.actor.features_extractor
    assert model.critic.features_extractor is extractor
    assert model.critic_target.features_extractor is not extractor
    critic_params = {id(p) for g in model.critic.optimizer.param_groups for p in g["params"]}
    actor_params = {id(p) for g in model.actor.optimizer.param_groups for p in g["params"]}
    assert id(extractor.linear.weight) in actor_params - critic_params
    model.learn(30)
    assert model._n_updates > 0
