"""``clear_kl``: a PNN's (or an SPNN's) prior KL term over copies of each minibatch whose sonar
reads clear.

The copies keep every part but the sonar (cleared) and a latch (zeroed); with
``prior_kl_clearance`` the reference on them is the path-following prior, also for a PNN whose
near samples refer to an avoidance column; training with a strong term keeps the policy closer to
the path follower on clear states; the weight is saved, and an observation without a sonar is
refused by name. An SPNN's gate selects its path-following prior on the copies, so the term
there is the KL to that prior too.
"""

from __future__ import annotations

import numpy as np
import pytest
import torch as th
import torch.nn.functional as F
from gymnasium import spaces
from progressive_helpers import (
    batch,
    kl_to_path_checkpoint,
    near_reference_pnn,
    obs_tensor,
    toy_model,
)

from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy
from sb3_pnn.progressive.off_path import off_path_copies


def _near_states(space, n=128, seed=7):
    obs = batch(space, n, seed=seed)
    obs["sonar"] = np.minimum(obs["sonar"], 0.3).astype(np.float32)  # every state within 7.5 m
    return obs


def test_clear_copies_keep_the_path_and_clear_the_sonar():
    gen = th.Generator().manual_seed(0)
    obs = {"path": th.rand(50, 2, generator=gen), "sonar": th.rand(50, 9, generator=gen) * 0.3}
    obs["latch"] = th.ones(50, 1)
    copies = off_path_copies(obs, "sonar", ("latch",), redraw_path=False)
    assert copies["path"] is obs["path"]
    assert th.equal(copies["sonar"], th.ones(50, 9)) and th.equal(copies["latch"], th.zeros(50, 1))
    assert not th.equal(obs["sonar"], copies["sonar"])  # the batch itself is left alone


def test_the_term_is_the_kl_to_the_path_prior_on_the_cleared_states(priors):
    model = near_reference_pnn(priors, clear_kl=1.0)
    policy = model.policy
    obs = _near_states(model.observation_space, 32)
    term = policy.off_path_kl_term(obs_tensor(policy, obs), redraw_path=False)
    cleared = dict(obs, sonar=np.ones_like(obs["sonar"]))
    pf = DiscreteSAC.load(priors["pf_dsac"], device="cpu").policy
    with th.no_grad():
        log_pi = F.log_softmax(policy.actor(obs_tensor(policy, cleared)), dim=1)
        log_pf = F.log_softmax(pf.actor(obs_tensor(pf, cleared, ("path",))), dim=1)
    expected = (log_pi.exp() * (log_pi - log_pf)).sum(dim=1).mean()
    assert term.item() == pytest.approx(expected.item(), rel=1e-5)
    assert term.requires_grad


def test_a_strong_term_keeps_the_policy_near_the_path_prior_in_open_water(priors):
    """The toy task pays for action 2 only; its states read the sonar at random, near and far.
    With a strong clear-sonar term the run ends closer to the path follower on cleared states
    than the same run without it; the frozen columns keep every bit."""
    space = near_reference_pnn(priors).observation_space
    probe = _near_states(space, 256)
    kls = {}
    for weight in (0.0, 10.0):
        model = near_reference_pnn(priors, clear_kl=weight)
        frozen = {k: v.clone() for k, v in model.policy.state_dict().items() if "priors" in k}
        model.learn(400)
        with th.no_grad():
            term = model.policy.off_path_kl_term(obs_tensor(model.policy, probe), False)
        kls[weight] = float(term)
        after = model.policy.state_dict()
        assert all(th.equal(after[k], v) for k, v in frozen.items())
    assert kls[10.0] < 0.5 * kls[0.0], kls


def test_the_weight_is_saved_and_earlier_models_are_unchanged(priors, tmp_path):
    """(With both copy terms at 0 no copy term is computed: test_off_path_kl.py.)"""
    model = near_reference_pnn(priors, clear_kl=2.0)
    model.learn(40)
    model.save(tmp_path / "pnn.zip")
    assert DiscreteSAC.load(tmp_path / "pnn.zip", device="cpu").policy.clear_kl == 2.0
    plain = near_reference_pnn(priors)
    assert "clear_kl" not in plain.policy._get_constructor_parameters()  # earlier zips alike


def test_bad_weights_and_a_missing_sonar_are_refused(priors):
    for bad in (-1.0, float("inf")):
        with pytest.raises(ValueError, match=r"clear_kl must be a finite number >= 0"):
            near_reference_pnn(priors, clear_kl=bad)
    path_only = spaces.Dict({"path": spaces.Box(-1.0, 1.0, (2,), np.float32)})
    for term, verb in (("clear_kl", "clears"), ("obstacle_kl", "draws obstacles into")):
        with pytest.raises(ValueError, match=rf"{term}=1.0 {verb} the observation's 'sonar'"):
            ProgressivePolicy(
                path_only,
                spaces.Discrete(5),
                lambda _: 3e-4,
                priors=[priors["pf_dsac"]],
                **{term: 1.0},
            )


def test_an_spnns_term_is_the_kl_to_its_path_prior_and_is_saved(priors, tmp_path):
    """SelectivePolicy(clear_kl=...): on the cleared copies the hard gate hands the laterals to
    the path-following prior, and the term equals mean KL(pi || pi_pf) there; the weight travels
    with the saved model."""
    kwargs = dict(priors=[priors["pf_dsac"], priors["oa_dsac"]], net_arch=[16, 16])
    model = toy_model(SelectivePolicy, {**kwargs, "start_as_prior": False, "clear_kl": 1.5})
    policy = model.policy
    obs = _near_states(model.observation_space, 32)
    term = policy.off_path_kl_term(obs_tensor(policy, obs), redraw_path=False)
    cleared = obs_tensor(policy, dict(obs, sonar=np.ones_like(obs["sonar"])))
    assert th.equal(policy.gate_weights(cleared), th.tensor([[1.0, 0.0]]).expand(32, 2))
    assert th.equal(policy.gate_weights(obs_tensor(policy, obs))[:, 1], th.ones(32))
    expected = kl_to_path_checkpoint(policy, cleared, priors["pf_dsac"])
    assert term.item() == pytest.approx(expected, rel=1e-5)
    model.learn(40)
    model.save(tmp_path / "spnn.zip")
    assert DiscreteSAC.load(tmp_path / "spnn.zip", device="cpu").policy.clear_kl == 1.5
    with pytest.raises(ValueError, match=r"clear_kl must be a finite number >= 0"):
        toy_model(SelectivePolicy, {**kwargs, "clear_kl": -1.0})
