"""DiscreteSAC on a CUDA device: SB3's ``device="auto"`` picks it, training runs there, and a
checkpoint moves between the GPU and the CPU with its weights, optimizers and buffer.

Skipped without a GPU (CI has none); see tests/sb3_pnn/reproduce/test_cuda_agents.py.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import torch as th
from test_dsac_save_load import train_small

from sb3_pnn import DiscreteSAC

pytestmark = [
    pytest.mark.cuda,
    pytest.mark.skipif(not th.cuda.is_available(), reason="needs a CUDA device"),
]


def test_auto_device_is_the_gpu_and_training_stays_there() -> None:
    model = train_small("auto")
    assert model.device.type == "cuda"
    tensors = [*model.policy.parameters(), *model.policy.buffers(), model.log_ent_coef]
    assert all(t.device.type == "cuda" for t in tensors)
    for optimizer in (model.actor.optimizer, model.critic.optimizer):
        for state in optimizer.state_dict()["state"].values():
            assert all(v.device.type == "cuda" for v in state.values() if th.is_tensor(v))


def test_checkpoint_moves_between_gpu_and_cpu(tmp_path: Path) -> None:
    model = train_small("cuda")
    model.save(tmp_path / "gpu.zip")
    model.save_replay_buffer(tmp_path / "buffer.pkl")
    on_cpu = DiscreteSAC.load(tmp_path / "gpu.zip", device="cpu")
    for key, value in model.policy.state_dict().items():  # saved exactly
        assert th.equal(on_cpu.policy.state_dict()[key], value.cpu()), key
    obs = np.random.default_rng(0).normal(size=(64, 4)).astype(np.float32)
    with th.no_grad():
        gpu = model.policy.actor(th.as_tensor(obs, device="cuda")).cpu()
        cpu = on_cpu.policy.actor(th.as_tensor(obs))
    assert th.allclose(gpu, cpu, atol=1e-5, rtol=1e-5)

    on_cpu.save(tmp_path / "cpu.zip")  # and back to the GPU, where it resumes training
    back = DiscreteSAC.load(tmp_path / "cpu.zip", env=model.get_env(), device="cuda")
    back.load_replay_buffer(tmp_path / "buffer.pkl")
    assert back.replay_buffer.size() == model.replay_buffer.size()
    steps = back.num_timesteps
    back.learn(100, reset_num_timesteps=False)
    assert back.num_timesteps == steps + 100
    assert all(p.device.type == "cuda" for p in back.policy.parameters())
