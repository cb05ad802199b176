"""CorridorRelease (a diagnosis of docs/ablation section 49): the corridor bound, once it has
cut the avoidance column, cuts it until abs(g) / d_L falls below the release, per vehicle; the
gate it plays gives the avoidance column no weight while cut and its own weight otherwise."""

from __future__ import annotations

import numpy as np
import pytest
import torch as th

from sb3_pnn.progressive.gates import DistanceGate
from sb3_pnn.reproduce.tools.corridor_release import CorridorRelease


class GateReader:
    """Records the avoidance column's weight the gate gives the observation on each call."""

    def __init__(self, gate: DistanceGate):
        self.gate, self.weights = gate, []

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        batch = {k: th.as_tensor(np.atleast_2d(v), dtype=th.float32) for k, v in obs.items()}
        self.weights.append(self.gate(batch)[:, 1].tolist())
        return np.zeros(len(self.weights[-1]), dtype=np.int64), state


def test_the_cut_holds_until_the_release_per_vehicle() -> None:
    gate = DistanceGate("hard", d_th=12.5, sonar_range=25.0, corridor=0.9)
    policy = CorridorRelease(GateReader(gate), gate, release=0.6)
    sonar = np.full((2, 9), 0.2, dtype=np.float32)
    seen = []
    for g in (0.5, 0.92, 0.85, 0.7, 0.55, 0.8, 0.95):
        path = np.array([[0.0, g], [0.0, -0.3]], dtype=np.float32)  # the sign of g is the side
        policy.predict({"sonar": sonar, "path": path})
        seen.append(policy.cut.tolist())
    assert [cut[0] for cut in seen] == [False, True, True, True, False, False, True]
    assert not any(cut[1] for cut in seen)  # the other vehicle never reached the bound
    # a vehicle starting an episode forgets the cut; reset forgets every vehicle's
    start = np.array([True, False])
    path = np.array([[0.0, 0.7], [0.0, 0.7]], dtype=np.float32)
    policy.cut = np.array([True, True])
    policy.predict({"sonar": sonar, "path": path}, episode_start=start)
    assert policy.cut.tolist() == [False, True]
    policy.reset()
    assert policy.cut is None


def test_the_gate_gives_no_avoidance_weight_while_cut_and_is_restored() -> None:
    gate = DistanceGate("hard", d_th=12.5, sonar_range=25.0, corridor=0.9)
    reader = GateReader(gate)
    policy = CorridorRelease(reader, gate, release=0.6)
    near = np.full(9, 0.2, dtype=np.float32)  # every sector 5 m: within d_th
    for g in (0.5, 0.95, 0.8, 0.5):
        obs = {"sonar": near[None], "path": np.array([[0.0, g]], dtype=np.float32)}
        policy.predict(obs)
    # inside: avoidance; beyond the bound: cut; back at 0.8 < 0.9 but above 0.6: still cut
    assert reader.weights == [[1.0], [0.0], [0.0], [1.0]]
    assert gate.corridor == 0.9  # the trained bound is put back after every call


def test_a_gate_without_a_bound_or_a_release_above_it_is_refused() -> None:
    with pytest.raises(ValueError, match="needs an SPNN gate with a corridor bound"):
        CorridorRelease(None, DistanceGate("hard"), 0.6)
    with pytest.raises(ValueError, match=r"release=0.95 is not allowed: expected a fraction"):
        CorridorRelease(None, DistanceGate("hard", corridor=0.9), 0.95)
