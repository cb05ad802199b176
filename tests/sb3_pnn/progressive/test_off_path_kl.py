"""``off_path_kl``: the prior KL term over off-path copies of each minibatch.

The copies keep every observation part but the path (redrawn 0.3-1 corridor half-widths off the
path, within +-90 deg of course error) and the sonar (clear), so SPNN's gate selects the
path-following prior on them; the term is the KL divergence to that prior's policy there; it
pulls a trained policy toward the prior off the path, leaves the frozen columns as they were, is
saved with the model, and is refused where the observation has no path part.
"""

from __future__ import annotations

import numpy as np
import pytest
import torch as th
from gymnasium import spaces
from progressive_helpers import batch, kl_to_path_checkpoint, obs_tensor, toy_model

from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy
from sb3_pnn.progressive.off_path import HEADING_BOUND, OFF_PATH_BAND, off_path_copies


def _spnn(paths, **kwargs):
    kw = dict(priors=[paths["pf_dsac"], paths["oa_dsac"]], net_arch=[16, 16], prior_kl=0.0)
    kw.update(kwargs)
    return toy_model(SelectivePolicy, kw)


def test_copies_lie_off_the_path_with_a_clear_sonar_and_keep_the_other_parts():
    gen = th.Generator().manual_seed(0)
    n = 4000
    obs = {
        "path": th.zeros(n, 2),
        "sonar": th.rand(n, 9, generator=gen) * 0.3,
        "motion": th.randn(n, 2, generator=gen),
        "latch": th.ones(n, 1),
    }
    before = {k: v.clone() for k, v in obs.items()}
    copies = off_path_copies(obs, "sonar", ("latch",), generator=gen)
    heading, offset = copies["path"][:, 0], copies["path"][:, 1]
    low, high = OFF_PATH_BAND
    assert float(offset.abs().min()) >= low and float(offset.abs().max()) <= high
    assert float(heading.abs().max()) <= HEADING_BOUND
    assert 0.45 < float((offset > 0).float().mean()) < 0.55  # either side of the path
    assert float(heading.abs().max()) > 0.95 * HEADING_BOUND  # the whole band is drawn
    assert th.equal(copies["sonar"], th.ones(n, 9))
    assert th.equal(copies["latch"], th.zeros(n, 1))
    assert copies["motion"] is obs["motion"]
    for key, value in before.items():  # the replayed batch itself is left alone
        assert th.equal(obs[key], value)


def test_the_term_is_the_kl_to_the_path_following_prior_on_the_copies(priors):
    """On the copies the hard gate hands the laterals to the path-following prior (the sonar is
    clear), and the term equals mean KL(pi || pi_pf) there, recomputed by hand from the same
    draws and the path-following checkpoint itself."""
    model = _spnn(priors, start_as_prior=False, off_path_kl=1.0)
    policy = model.policy
    obs = obs_tensor(policy, batch(model.observation_space, 64, seed=5))
    th.manual_seed(11)
    term = policy.off_path_kl_term(obs)
    th.manual_seed(11)
    copies = off_path_copies(obs, "sonar")
    assert th.equal(policy.gate_weights(copies), th.tensor([[1.0, 0.0]]).expand(64, 2))
    expected = kl_to_path_checkpoint(policy, copies, priors["pf_dsac"])
    assert term.item() == pytest.approx(expected, rel=1e-5)
    assert term.requires_grad
    assert int(policy.actor.lead_counts.sum()) == 0  # made-up states are not counted as leads


def test_it_pulls_the_policy_toward_the_prior_off_the_path(priors):
    """The toy task pays for action 2 only, which the priors do not prefer. Trained from the
    prior's policy, the run with a strong off-path term stays closer to the path-following
    prior on off-path states than the same run without it, and its frozen columns keep every
    bit."""
    probe = obs_tensor(_spnn(priors).policy, batch(_spnn(priors).observation_space, 256, seed=7))
    kls = {}
    for weight in (0.0, 10.0):
        model = _spnn(priors, start_as_prior=True, off_path_kl=weight)
        frozen = {k: v.clone() for k, v in model.policy.state_dict().items() if "priors" in k}
        model.learn(400)
        th.manual_seed(3)
        with th.no_grad():
            kls[weight] = float(model.policy.off_path_kl_term(probe))
        after = model.policy.state_dict()
        assert all(th.equal(after[k], v) for k, v in frozen.items())
    assert kls[10.0] < 0.5 * kls[0.0], kls


def test_the_weight_is_saved_and_off_is_the_plain_update(priors, tmp_path, monkeypatch):
    model = _spnn(priors, off_path_kl=2.0)
    model.learn(40)
    model.save(tmp_path / "spnn.zip")
    assert DiscreteSAC.load(tmp_path / "spnn.zip", device="cpu").policy.off_path_kl == 2.0
    plain = _spnn(priors)
    assert plain.policy.off_path_kl == 0.0
    assert "off_path_kl" not in plain.policy._get_constructor_parameters()  # earlier zips alike

    def refuse(*args, **kwargs):
        raise AssertionError("the off-path term was computed with off_path_kl = 0")

    monkeypatch.setattr(plain.policy, "off_path_kl_term", refuse)
    plain.learn(60)


def test_a_pnn_reads_it_too_and_bad_values_are_refused(priors):
    pnn = toy_model(ProgressivePolicy, dict(priors=[priors["pf_dsac"]], off_path_kl=1.0))
    pnn.learn(40)
    assert pnn.policy.off_path_kl == 1.0
    for bad in (-1.0, float("nan")):
        with pytest.raises(ValueError, match=r"off_path_kl must be a finite number >= 0"):
            _spnn(priors, off_path_kl=bad)
    no_path = {"sonar": spaces.Box(0.0, 1.0, (9,), np.float32)}
    with pytest.raises(ValueError, match=r"off_path_kl=1.0 redraws the observation's 'path' part"):
        ProgressivePolicy(
            spaces.Dict(no_path),
            spaces.Discrete(5),
            lambda _: 3e-4,
            priors=[priors["oa_dsac"]],
            off_path_kl=1.0,
        )
