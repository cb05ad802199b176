"""``obstacle_kl``: a PNN's prior KL term over copies of each minibatch whose sonar also reads
drawn obstacles.

The drawn sector readings are the simulator's exact sonar geometry (checked against
``rov_envs.physics.sonar.sonar_scan``); the copies keep every part but the sonar, which reads
the nearer of its own and the drawn obstacles; with the near reference the term is the KL to the
avoidance prior on the copies an obstacle is near and to the path prior elsewhere; training with
a strong term brings the policy closer to those references; the weight is saved, and bad weights,
a bad span or an observation without a sonar are refused by name.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch as th
import torch.nn.functional as F
from progressive_helpers import batch, near_reference_pnn, obs_tensor

from rov_envs.physics.sonar import sonar_scan
from sb3_pnn import DiscreteSAC
from sb3_pnn.progressive.obstacle_copies import (
    NEAREST_SURFACE,
    drawn_sonar,
    obstacle_copies,
    sector_distances,
)


def test_sector_readings_are_the_simulators_sonar():
    rng = np.random.default_rng(3)
    for _ in range(300):
        m, q = int(rng.integers(1, 4)), int(rng.integers(1, 13))
        span = float(rng.uniform(0.3, 2 * math.pi))
        bearing, radius = rng.uniform(-math.pi, math.pi, m), rng.uniform(0.5, 3.0, m)
        centre = radius + rng.uniform(0.05, 30.0, m)
        circles = np.stack([centre * np.cos(bearing), centre * np.sin(bearing), radius], axis=1)
        expected = np.zeros(q)
        sonar_scan(0.0, 0.0, 0.0, circles, span, 25.0, expected)
        got = sector_distances(
            *(th.tensor(v).unsqueeze(0) for v in (bearing, centre, radius)), q, span
        )
        np.testing.assert_allclose(got[0].clamp(max=25.0).numpy(), expected, atol=1e-9)


def test_drawn_readings_lie_in_range_and_see_an_obstacle():
    gen = th.Generator().manual_seed(0)
    sonar = drawn_sonar(4000, 9, math.pi, 25.0, gen)
    assert sonar.shape == (4000, 9) and sonar.dtype == th.float32
    nearest = sonar.min(dim=1).values * 25.0
    assert nearest.min() >= NEAREST_SURFACE - 1e-5 and sonar.max() <= 1.0
    assert (nearest < 25.0).all()  # every copy sees at least one drawn obstacle
    near = (nearest < 12.5).float().mean()
    assert 0.4 < near < 0.9, near  # near and far copies both, for both references


def test_copies_keep_the_other_parts_and_take_the_nearer_reading():
    gen = th.Generator().manual_seed(1)
    obs = {"path": th.rand(64, 2, generator=gen), "sonar": th.rand(64, 9, generator=gen)}
    copies = obstacle_copies(obs, "sonar", math.pi, 25.0, th.Generator().manual_seed(2))
    drawn = drawn_sonar(64, 9, math.pi, 25.0, th.Generator().manual_seed(2))
    assert copies["path"] is obs["path"]
    assert th.equal(copies["sonar"], th.minimum(obs["sonar"], drawn))
    assert (copies["sonar"] < obs["sonar"]).any()  # the drawn obstacles are seen


def test_the_term_is_the_kl_to_the_near_or_path_reference_on_the_copies(priors, monkeypatch):
    model = near_reference_pnn(priors, obstacle_kl=1.0)
    policy = model.policy
    states = batch(model.observation_space, 64, seed=5)
    states["sonar"] = np.ones_like(states["sonar"])  # clear: the drawn obstacles alone decide
    obs = obs_tensor(policy, states)
    copies = obstacle_copies(obs, "sonar", math.pi, 25.0, th.Generator().manual_seed(9))
    monkeypatch.setattr(
        "sb3_pnn.progressive.progressive_policy.obstacle_copies", lambda *a, **k: copies
    )
    term = policy.obstacle_kl_term(obs)
    pf = DiscreteSAC.load(priors["pf_dsac"], device="cpu").policy
    oa = DiscreteSAC.load(priors["oa_dsac"], device="cpu").policy
    with th.no_grad():
        log_pi = F.log_softmax(policy.actor(copies), dim=1)
        log_pf = F.log_softmax(pf.actor({"path": copies["path"]}), dim=1)
        log_oa = F.log_softmax(oa.actor({k: copies[k] for k in oa.observation_space.spaces}), dim=1)
    near = (copies["sonar"].min(dim=1, keepdim=True).values * 25.0) < 12.5
    assert near.any() and (~near).any()
    reference = th.where(near, log_oa, log_pf)
    expected = (log_pi.exp() * (log_pi - reference)).sum(dim=1).mean()
    assert term.item() == pytest.approx(expected.item(), rel=1e-5)
    assert term.requires_grad


def test_a_strong_term_brings_the_policy_to_its_references(priors):
    """The same toy run with and without a strong term: with it, the KL to the references on
    freshly drawn copies ends smaller; the frozen columns keep every bit."""
    probe_space = near_reference_pnn(priors).observation_space
    probe = batch(probe_space, 256, seed=11)
    kls = {}
    for weight in (0.0, 10.0):
        model = near_reference_pnn(priors, obstacle_kl=weight)
        frozen = {k: v.clone() for k, v in model.policy.state_dict().items() if "priors" in k}
        model.learn(400)
        th.manual_seed(0)
        with th.no_grad():
            kls[weight] = float(model.policy.obstacle_kl_term(obs_tensor(model.policy, probe)))
        after = model.policy.state_dict()
        assert all(th.equal(after[k], v) for k, v in frozen.items())
    assert kls[10.0] < 0.5 * kls[0.0], kls


def test_the_weight_and_span_are_saved_and_earlier_models_are_unchanged(priors, tmp_path):
    model = near_reference_pnn(priors, obstacle_kl=2.0, obstacle_kl_span=math.radians(120.0))
    model.learn(40)
    model.save(tmp_path / "pnn.zip")
    loaded = DiscreteSAC.load(tmp_path / "pnn.zip", device="cpu").policy
    assert (loaded.obstacle_kl, loaded.obstacle_kl_span) == (2.0, math.radians(120.0))
    params = near_reference_pnn(priors).policy._get_constructor_parameters()
    assert "obstacle_kl" not in params and "obstacle_kl_span" not in params


def test_bad_weights_and_spans_are_refused(priors):
    for bad in (-1.0, float("nan")):
        with pytest.raises(ValueError, match=r"obstacle_kl must be a finite number >= 0"):
            near_reference_pnn(priors, obstacle_kl=bad)
    for bad in (0.0, 7.0):
        with pytest.raises(ValueError, match=rf"obstacle_kl_span={bad!r} is not allowed"):
            near_reference_pnn(priors, obstacle_kl=1.0, obstacle_kl_span=bad)
    # (an observation without a sonar is refused by name: test_clear_kl.py)
