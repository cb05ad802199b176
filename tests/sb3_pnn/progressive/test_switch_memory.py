"""SwitchMemory: eq. 15's hard gate that, once it has selected the avoidance column, keeps it
until the nearest obstacle is beyond d_th + H."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import torch as th

from sb3_pnn.progressive.gates import DistanceGate
from sb3_pnn.progressive.switch_memory import SwitchMemory


class GateOnly:
    """A stand-in SPNN whose action is the column its actor's gate selects (0 path, 1 avoid)."""

    def __init__(self) -> None:
        gate = DistanceGate("hard", d_th=12.5, sonar_range=25.0)
        self.policy = SimpleNamespace(actor=SimpleNamespace(gate=gate))

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        weights = self.policy.actor.gate({"sonar": th.as_tensor(obs["sonar"])})
        return weights.argmax(dim=1).numpy(), None


def _play(policy, nearest_m, starts):
    actions = []
    for d, start in zip(nearest_m, starts):
        obs = {"sonar": np.full((1, 9), d / 25.0, np.float32)}
        action, _ = policy.predict(obs, episode_start=np.array([start]))
        actions.append(int(action[0]))
    return actions


def test_memory_keeps_avoidance_until_beyond_d_th_plus_h_and_restores_d_th() -> None:
    model = GateOnly()
    policy = SwitchMemory(model, hysteresis=5.0)
    nearest = [20.0, 12.0, 14.0, 17.5, 17.6, 14.0, 10.0]
    assert _play(policy, nearest, [True] + [False] * 6) == [0, 1, 1, 1, 0, 0, 1]
    assert model.policy.actor.gate.d_th == 12.5  # the trained gate is left as it was
    # without memory, the same readings switch on every crossing of d_th
    assert _play(model, nearest, [True] * 7) == [0, 1, 0, 0, 0, 0, 1]


def test_each_episode_and_each_vehicle_has_its_own_memory() -> None:
    policy = SwitchMemory(GateOnly(), hysteresis=5.0)
    assert _play(policy, [10.0, 14.0, 14.0], [True, False, True]) == [1, 1, 0]
    two = {"sonar": np.array([[10.0 / 25] * 9, [20.0 / 25] * 9], np.float32)}
    policy.predict(two, episode_start=np.array([True, True]))
    two["sonar"][:] = 14.0 / 25
    action, _ = policy.predict(two, episode_start=np.array([False, False]))
    assert action.tolist() == [1, 0]


def test_only_a_distance_gate_without_a_latch_and_a_distance_are_accepted() -> None:
    latched = GateOnly()
    latched.policy.actor.gate = DistanceGate("hard", 12.5, 25.0, latch_key="latch")
    for model in (latched, SimpleNamespace()):
        with pytest.raises(ValueError, match="needs an SPNN whose gate is eq. 15's hard switch"):
            SwitchMemory(model, hysteresis=5.0)
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="hysteresis=.* is not allowed"):
            SwitchMemory(GateOnly(), hysteresis=bad)
    assert SwitchMemory(GateOnly(), hysteresis=0.0, d_th=8.0).d_th == 8.0


def test_the_models_spaces_and_training_keywords_show_through() -> None:
    """An evaluation reads ``trained_env`` and the spaces of the policy it is given: the memory
    passes on the model's (a missing one stays missing)."""
    model = GateOnly()
    model.trained_env = {"control_period": 1.0}
    policy = SwitchMemory(model, hysteresis=10.0)
    assert policy.trained_env is model.trained_env
    assert not hasattr(policy, "observation_space")


class SoftWeight(GateOnly):
    """A stand-in SPNN with the soft gate (T = 2 m) that returns the avoidance column's weight."""

    def __init__(self, corridor: float | None = None) -> None:
        super().__init__()
        gate = DistanceGate("soft", 12.5, 25.0, temperature=2.0, corridor=corridor)
        self.policy.actor.gate = gate

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        tensors = {k: th.as_tensor(v) for k, v in obs.items()}
        return self.policy.actor.gate(tensors)[:, 1].numpy(), None


def _weights(policy, nearest_m, starts, off_path=0.0):
    weights = []
    for d, start in zip(nearest_m, starts):
        obs = {
            "sonar": np.full((1, 9), d / 25.0, np.float32),
            "path": np.array([[0.0, off_path]], np.float32),
        }
        weights.append(float(policy.predict(obs, episode_start=np.array([start]))[0][0]))
    return weights


def _sigmoid(x: float) -> float:
    return 1.0 / (1.0 + np.exp(-x))


def test_soft_gate_holds_the_avoidance_weight_until_beyond_d_th_plus_h() -> None:
    model = SoftWeight()
    nearest = [20.0, 10.0, 14.0, 22.0, 23.0, 10.0, 14.0]
    starts = [True, False, False, False, False, True, False]
    held = _weights(SwitchMemory(model, hysteresis=10.0), nearest, starts)
    at_10 = _sigmoid((12.5 - 10.0) / 2.0)
    expected = [_sigmoid(-3.75), at_10, at_10, at_10, _sigmoid(-5.25), at_10, at_10]
    np.testing.assert_allclose(held, expected, atol=1e-5)
    np.testing.assert_allclose(  # without memory: the gate's own weight on every step
        _weights(model, nearest, [True] * 7), [_sigmoid((12.5 - d) / 2.0) for d in nearest], 1e-6
    )
    assert model.policy.actor.gate.d_th == 12.5
    # a new episode starts without memory, and the corridor bound still hands back
    assert _weights(SwitchMemory(model, 10.0), [10.0, 14.0], [False, True])[1] < 0.33
    bounded = SwitchMemory(SoftWeight(corridor=0.9), hysteresis=10.0)
    assert _weights(bounded, [10.0, 14.0], [True, False], off_path=0.95) == [0.0, 0.0]
