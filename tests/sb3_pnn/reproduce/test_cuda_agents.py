"""The study's agents, built as ``python -m sb3_pnn.reproduce`` builds them, train on a CUDA
device: SB3's default ``device="auto"`` puts a user's model there whenever a GPU is present.

Skipped without a GPU (CI has none); run on a GPU machine with
``pytest tests/sb3_pnn/reproduce/test_cuda_agents.py tests/sb3_pnn/dsac/test_cuda.py``.
"""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch as th

from sb3_pnn import DiscreteSAC
from sb3_pnn.evaluation import evaluate_policy_on_task
from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.running.work import build_model
from sb3_pnn.reproduce.tools.prior_agreement import step_counts

pytestmark = [
    pytest.mark.cuda,
    pytest.mark.skipif(not th.cuda.is_available(), reason="needs a CUDA device"),
]

LEARNERS = [
    "spnn-straight-s0",
    "spnn-sine-s0",
    "pnn-straight-s0",
    "pnn-sine-s0",
    "sac_multi-straight-s0",
    "sac_single-sine-s0",
]


@pytest.fixture(scope="module")
def plan_and_priors(tmp_path_factory) -> tuple[dict, dict[str, Path]]:
    """The quick study's specs and its three source columns, built on the GPU (untrained: the
    transfer only needs their shapes and frozen weights) and saved as the study saves them."""
    plan = {s.run_id: s for s in build_plan(StudyConfig(budget_name="quick", seeds=1))}
    folders = {}
    for run_id in ("prior-pf_straight-s0", "prior-pf_sine-s0", "prior-oa-s0"):
        folder = tmp_path_factory.mktemp(run_id)
        build_model(plan[run_id], {}, device="cuda").save(folder / "model.zip")
        folders[run_id] = folder
    return plan, folders


def _observations(env_id: str, env_kwargs: dict, n: int = 64) -> dict[str, np.ndarray]:
    """``n`` observations of the task under random actions, stacked per key."""
    env = gym.make(env_id, **env_kwargs)
    env.action_space.seed(0)
    obs, _ = env.reset(seed=0)
    rows = []
    for _ in range(n):
        rows.append(obs)
        obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            obs, _ = env.reset()
    return {k: np.stack([r[k] for r in rows]) for k in rows[0]}


def _frozen(policy) -> dict[str, th.Tensor]:
    """The prior columns' weights and buffers (every state entry under a ``priors`` module)."""
    return {k: v.detach().clone() for k, v in policy.state_dict().items() if ".priors." in f".{k}"}


@pytest.mark.parametrize("run_id", LEARNERS)
def test_study_agent_trains_on_cuda_and_loads_on_cpu(run_id, plan_and_priors, tmp_path):
    plan, priors = plan_and_priors
    spec = plan[run_id]
    model = build_model(spec, {d: priors[d] for d in spec.deps}, device="cuda")
    assert model.device.type == "cuda"
    assert all(p.device.type == "cuda" for p in model.policy.parameters())
    frozen = _frozen(model.policy)
    assert bool(frozen) == (spec.agent in ("pnn", "spnn"))  # SAC-Multi fine-tunes its prior
    model.learning_starts = 64
    model.learn(total_timesteps=400)
    assert model.actor.optimizer.state_dict()["state"], "no update ran"
    for key, before in frozen.items():  # frozen columns stay bit-identical on the GPU too
        assert th.equal(model.policy.state_dict()[key], before), key
    if hasattr(model.policy, "extra_logs"):
        assert all(np.isfinite(v) for v in model.policy.extra_logs().values())

    model.save(tmp_path / "model.zip")
    on_cpu = DiscreteSAC.load(tmp_path / "model.zip", device="cpu")
    assert all(p.device.type == "cpu" for p in on_cpu.policy.parameters())
    obs = _observations(str(spec.env_id), dict(spec.env_kwargs))
    with th.no_grad():
        gpu_logits = model.policy.actor(model.policy.obs_to_tensor(obs)[0]).cpu()
        cpu_logits = on_cpu.policy.actor(on_cpu.policy.obs_to_tensor(obs)[0])
    assert th.allclose(gpu_logits, cpu_logits, atol=1e-4, rtol=1e-4)

    env_kwargs = {k: v for k, v in spec.env_kwargs.items() if k != "start_noise"}
    result = evaluate_policy_on_task(model, str(spec.env_id), 2, seed=10_000, env_kwargs=env_kwargs)
    assert result.n_episodes == 2 and len(result.episodes) == 2


def test_prior_agreement_reads_a_model_on_the_gpu(plan_and_priors):
    plan, priors = plan_and_priors
    spec = plan["spnn-straight-s0"]
    model = build_model(spec, {d: priors[d] for d in spec.deps}, device="cuda")
    env = gym.make(str(spec.env_id), **spec.env_kwargs)
    counts, ends = step_counts(model, env, episodes=1, seed=20_000)
    steps = sum(v for (_, what), v in counts.items() if what == "steps")
    assert steps > 0 and sum(ends.values()) == 1
