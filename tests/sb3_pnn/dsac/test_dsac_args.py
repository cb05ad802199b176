"""Bad arguments and non-Discrete action spaces are refused with a clear error."""

import gymnasium as gym
import pytest

from sb3_pnn import DiscreteSAC


def test_refuses_box_action_space() -> None:
    with pytest.raises(ValueError, match=r"Discrete.*Box"):
        DiscreteSAC("MlpPolicy", "Pendulum-v1")


@pytest.mark.parametrize("ratio", [0.0, -0.1, 1.5, "0.9", None])
def test_refuses_target_entropy_ratio_outside_unit_interval(ratio) -> None:
    with pytest.raises(ValueError, match=r"target_entropy_ratio must be in \(0, 1\]"):
        DiscreteSAC("MlpPolicy", "CartPole-v1", target_entropy_ratio=ratio)


@pytest.mark.parametrize(
    "ent_coef", ["autox", "auto_", "auto_-1", "auto_abc", "auto_0", -0.5, "0.1", None]
)
def test_refuses_bad_ent_coef(ent_coef) -> None:
    with pytest.raises(ValueError, match="ent_coef must be"):
        DiscreteSAC("MlpPolicy", "CartPole-v1", ent_coef=ent_coef)


@pytest.mark.parametrize("n_critics", [0, -1, 1.5])
def test_refuses_bad_n_critics(n_critics) -> None:
    with pytest.raises(ValueError, match="n_critics"):
        DiscreteSAC("MlpPolicy", "CartPole-v1", policy_kwargs=dict(n_critics=n_critics))


def test_refuses_bad_tau_and_target_update_interval() -> None:
    with pytest.raises(ValueError, match="tau"):
        DiscreteSAC("MlpPolicy", "CartPole-v1", tau=1.5)
    with pytest.raises(ValueError, match="target_update_interval"):
        DiscreteSAC("MlpPolicy", "CartPole-v1", target_update_interval=0)


def test_accepted_ent_coef_forms_and_defaults() -> None:
    model = DiscreteSAC("MlpPolicy", "CartPole-v1", device="cpu")
    assert model.log_ent_coef.exp().item() == pytest.approx(0.2)  # paper Table 3
    assert model.target_entropy == pytest.approx(model.target_entropy_ratio * 0.6931471805599453)
    assert [
        layer.out_features for layer in model.actor.latent_pi if hasattr(layer, "out_features")
    ] == [64, 64]  # the recommended set-up's; the paper's is [255, 255]
    assert model.critic.n_critics == 2 and len(model.critic.q_networks) == 2
    assert model.critic.q_networks[0][-1].out_features == 2
    assert model.actor.action_logits.out_features == 2
    assert model.actor.features_extractor is not model.critic.features_extractor
    assert (model.learning_rate, model.tau, model.gamma, model.batch_size) == (
        3e-4,
        0.005,
        0.99,
        256,
    )
    # one update per step (section 3.2's text); the paper's Table 3: 10 after each episode
    assert model.buffer_size == 1_000_000 and model.gradient_steps == 1
    assert (model.train_freq.frequency, model.train_freq.unit.value) == (1, "step")
    assert model.learning_starts == 256
    auto = DiscreteSAC("MlpPolicy", "CartPole-v1", ent_coef="auto", buffer_size=1000)
    assert auto.log_ent_coef.item() == 0.0
    fixed = DiscreteSAC(
        "MlpPolicy", "CartPole-v1", ent_coef=0.0, buffer_size=1000, policy_kwargs=dict(n_critics=1)
    )
    assert fixed.ent_coef_optimizer is None and fixed.ent_coef_tensor.item() == 0.0
    assert len(fixed.critic.q_networks) == 1


def test_policy_refuses_non_discrete_space_directly() -> None:
    from sb3_pnn import DiscreteSACPolicy

    box = gym.spaces.Box(-1, 1, (2,))
    with pytest.raises(ValueError, match="Discrete"):
        DiscreteSACPolicy(box, box, lambda _: 1e-3)


@pytest.mark.parametrize("steps", [0, -100, 0.5, float("nan"), "100", True])
def test_learn_refuses_a_budget_that_would_do_nothing(steps) -> None:
    model = DiscreteSAC("MlpPolicy", "CartPole-v1", policy_kwargs=dict(net_arch=[8]))
    with pytest.raises(ValueError, match="total_timesteps must be a positive number"):
        model.learn(steps)
    assert model.num_timesteps == 0
