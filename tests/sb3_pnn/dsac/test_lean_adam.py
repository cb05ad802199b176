"""LeanFusedAdam is torch.optim.Adam(fused=True) bit for bit: parameters, state and state dict."""

import copy

import pytest
import torch as th
from torch import nn

from sb3_pnn import DiscreteSAC
from sb3_pnn.dsac import lean_adam
from sb3_pnn.dsac.lean_adam import LeanFusedAdam


def _net() -> nn.Module:
    th.manual_seed(0)
    return nn.Sequential(nn.Linear(6, 16), nn.ReLU(), nn.Linear(16, 3), nn.Linear(3, 2))


def _train(net: nn.Module, optimizer: th.optim.Optimizer, steps: int, frozen_last: int) -> None:
    """``steps`` updates; the last layer gets no gradient in the first ``frozen_last`` steps
    (its .grad stays None, so Adam skips it and its step count lags the others')."""
    g = th.Generator().manual_seed(1)
    for step in range(steps):
        x = th.randn(32, 6, generator=g)
        out = net[:3](x) if step < frozen_last else net(x)
        loss = (out**2).mean()
        optimizer.zero_grad()
        loss.backward()
        optimizer.step()
        if step == 7:  # SB3 sets the learning rate of every group before each train() call
            for group in optimizer.param_groups:
                group["lr"] = 1e-3


ADAM_VARIANTS = [
    {},
    {"weight_decay": 0.1},
    {"weight_decay": 0.1, "decoupled_weight_decay": True},
    {"maximize": True},
]


@pytest.mark.parametrize("kwargs", ADAM_VARIANTS)
def test_same_bits_as_fused_adam(kwargs: dict, monkeypatch: pytest.MonkeyPatch) -> None:
    fallbacks = []
    adam_step = lean_adam._ADAM_STEP
    monkeypatch.setattr(lean_adam, "_ADAM_STEP", lambda *a: fallbacks.append(1) or adam_step(*a))
    reference, lean = _net(), _net()
    ref_opt = th.optim.Adam(reference.parameters(), lr=3e-3, fused=True, **kwargs)
    lean_opt = LeanFusedAdam(lean.parameters(), lr=3e-3, fused=True, **kwargs)
    _train(reference, ref_opt, 20, frozen_last=5)
    _train(lean, lean_opt, 20, frozen_last=5)
    # Adam's own step only where state is created: the first step, and the last layer's first
    assert len(fallbacks) == 2
    for p, q in zip(reference.parameters(), lean.parameters(), strict=True):
        assert th.equal(p, q)
    ref_state, lean_state = ref_opt.state_dict(), lean_opt.state_dict()
    assert ref_state["param_groups"] == lean_state["param_groups"]
    for i, state in ref_state["state"].items():
        for key, value in state.items():
            assert th.equal(value, lean_state["state"][i][key]), (i, key)
    # the last layer really was skipped while it had no gradient
    assert int(lean_state["state"][4]["step"]) == 15 and int(lean_state["state"][0]["step"]) == 20


def test_state_dict_round_trip_continues_identically() -> None:
    net = _net()
    opt = LeanFusedAdam(net.parameters(), lr=3e-3, fused=True)
    _train(net, opt, 5, frozen_last=0)
    net2 = copy.deepcopy(net)
    opt2 = LeanFusedAdam(net2.parameters(), lr=3e-3, fused=True)
    opt2.load_state_dict(copy.deepcopy(opt.state_dict()))  # load_state_dict may alias
    _train(net, opt, 5, frozen_last=0)
    _train(net2, opt2, 5, frozen_last=0)
    for p, q in zip(net.parameters(), net2.parameters(), strict=True):
        assert th.equal(p, q)


def test_hooks_and_closures_take_adams_own_step() -> None:
    net = _net()
    opt = LeanFusedAdam(net.parameters(), lr=3e-3, fused=True)
    calls = []
    opt.register_step_pre_hook(lambda *args: calls.append("pre"))
    opt.register_step_post_hook(lambda *args: calls.append("post"))
    _train(net, opt, 2, frozen_last=0)
    assert calls == ["pre", "post", "pre", "post"]

    def closure() -> th.Tensor:
        opt.zero_grad()
        loss = net(th.ones(4, 6)).sum()
        loss.backward()
        return loss

    assert isinstance(opt.step(closure), th.Tensor)


def test_needs_fused() -> None:
    with pytest.raises(ValueError, match="fused=True"):
        LeanFusedAdam(_net().parameters(), lr=1e-3)


def test_discrete_sac_uses_it_for_a_fused_adam_only() -> None:
    model = DiscreteSAC("MlpPolicy", "CartPole-v1", policy_kwargs={"net_arch": [8]}, device="cpu")
    assert isinstance(model.actor.optimizer, LeanFusedAdam)
    assert isinstance(model.critic.optimizer, LeanFusedAdam)
    assert model.policy.optimizer_class is th.optim.Adam  # what is saved with the model
    plain = DiscreteSAC(
        "MlpPolicy",
        "CartPole-v1",
        device="cpu",
        policy_kwargs={"net_arch": [8], "optimizer_kwargs": {"fused": False}},
    )
    assert type(plain.actor.optimizer) is th.optim.Adam
