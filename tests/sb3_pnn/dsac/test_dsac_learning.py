"""DiscreteSAC learns CartPole-v1 (a quick check; bench/dsac_vs_dqn.py runs the full budget)."""

import pytest
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.evaluation import evaluate_policy

from sb3_pnn import DiscreteSAC


@pytest.mark.slow
def test_learns_cartpole_well_above_random() -> None:
    # Smaller networks and batches and one gradient step per env step (at episode ends), so that
    # 6000 steps take about 15 s on one core. A random policy averages about 22.
    model = DiscreteSAC(
        "MlpPolicy",
        make_vec_env("CartPole-v1", n_envs=1, seed=0),
        learning_starts=300,
        batch_size=64,
        learning_rate=1e-3,
        gamma=0.98,
        train_freq=(1, "episode"),
        gradient_steps=-1,
        target_entropy_ratio=0.5,
        policy_kwargs=dict(net_arch=[64, 64]),
        seed=0,
        device="cpu",
    )
    model.learn(6000)
    mean_return, _ = evaluate_policy(
        model, make_vec_env("CartPole-v1", n_envs=1, seed=123), n_eval_episodes=10
    )
    assert mean_return >= 150, mean_return
