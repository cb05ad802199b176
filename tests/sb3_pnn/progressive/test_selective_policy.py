"""SPNN (eq. 15): a per-sample gate on the sonar distance in actor and critics; other gates."""

from __future__ import annotations

import numpy as np
import pytest
import torch as th
from gymnasium import spaces
from progressive_helpers import SONAR_RANGE, ToyRovEnv, batch, toy_model
from stable_baselines3.common.logger import KVWriter, Logger

from sb3_pnn import DiscreteSAC, SelectivePolicy

D_TH = 12.5
# nearest obstacle of each sample, metres: far, near, exactly d_th (near: d <= d_th), far, near
DISTANCES = np.array([13.0, 12.0, D_TH, 24.0, 0.5])
NEAR = th.tensor([False, True, True, False, True])


def _model(paths, **kwargs):
    kw = dict(priors=[paths["pf_dsac"], paths["oa_dsac"]], net_arch=[16, 16])
    kw.update(kwargs)
    return toy_model(SelectivePolicy, kw)


def _obs(policy):
    obs = batch(policy.observation_space, len(DISTANCES), seed=3)
    sonar = np.ones_like(obs["sonar"])
    sonar[np.arange(len(DISTANCES)), np.arange(len(DISTANCES)) % 9] = DISTANCES / SONAR_RANGE
    obs["sonar"] = sonar.astype(np.float32)
    return policy.obs_to_tensor(obs)[0]


def _perturb(column):
    with th.no_grad():
        for buf in column.buffers():
            buf.add_(0.3)


def test_hard_gate_picks_the_column_by_distance_within_one_batch(priors):
    policy = _model(priors).policy
    obs = _obs(policy)
    expected = th.stack([(~NEAR).float(), NEAR.float()], dim=1)
    assert th.equal(policy.gate_weights(obs), expected)
    with th.no_grad():
        logits, q = policy.actor(obs), policy.critic(obs)
        for j, rows_of_column in ((0, ~NEAR), (1, NEAR)):
            saved = {k: v.clone() for k, v in policy.state_dict().items()}
            _perturb(policy.actor.net.priors[j])
            for q_net in policy.critic.q_networks:
                _perturb(q_net.priors[j])
            changed = (policy.actor(obs) != logits).any(dim=1)
            assert th.equal(changed, rows_of_column), (j, changed)
            for q_new, q_old in zip(policy.critic(obs), q, strict=True):
                assert th.equal((q_new != q_old).any(dim=1), rows_of_column)
            policy.load_state_dict(saved)


def test_soft_gate_tends_to_the_hard_gate(priors):
    hard = _model(priors).policy
    obs = _obs(hard)
    with th.no_grad():
        ref = hard.actor(obs)
        ref_q = hard.critic(obs)
        for temperature, close in ((1e-3, True), (5.0, False)):
            soft = _model(priors, gate="soft", temperature=temperature).policy
            soft.load_state_dict(hard.state_dict())
            out = soft.actor(obs)
            off = th.from_numpy(~np.isclose(DISTANCES, D_TH))  # at d_th soft gives 0.5
            assert th.allclose(out[off], ref[off], atol=1e-5) is close
            if close:
                assert th.allclose(soft.critic(obs)[0][off], ref_q[0][off], atol=1e-5)
                g = soft.gate_weights(obs)
                assert th.allclose(g[~off], th.full((1, 2), 0.5))


@pytest.mark.parametrize("gate", ["hard", "soft"])
def test_corridor_hands_the_laterals_back_to_the_path_column_near_the_edge(priors, gate, tmp_path):
    plain = _model(priors, gate=gate, temperature=2.0).policy
    model = _model(priors, gate=gate, temperature=2.0, gate_corridor=0.9)
    bounded = model.policy
    bounded.load_state_dict(plain.state_dict())
    obs = _obs(plain)
    # g / d_L of each sample: inside, at the bound (outside), outside, inside, outside
    obs["path"][:, 1] = th.tensor([0.2, 0.9, -0.95, -0.5, 1.0])
    outside = th.tensor([False, True, True, False, True])
    g_plain, g_bounded = plain.gate_weights(obs), bounded.gate_weights(obs)
    assert th.equal(g_bounded[~outside], g_plain[~outside])
    assert th.equal(g_bounded[outside], th.tensor([[1.0, 0.0]]).expand(3, 2))
    assert g_plain[outside, 1].min() > 0.4  # the sonar alone would give the avoidance column
    with th.no_grad():  # actor and critics follow the same gate
        assert th.equal(bounded.actor(obs)[~outside], plain.actor(obs)[~outside])
        assert not th.allclose(bounded.critic(obs)[0][outside], plain.critic(obs)[0][outside])
    model.save(tmp_path / "spnn.zip")  # the bound is part of the saved policy
    loaded = DiscreteSAC.load(tmp_path / "spnn.zip", device="cpu").policy
    assert loaded.actor.gate.corridor == 0.9
    assert th.equal(loaded.gate_weights(obs), g_bounded)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"gate_corridor": 0.0},
            r"gate_corridor must be a fraction of d_L in \(0, 1\] or None, got 0.0",
        ),
        ({"gate_corridor": 1.5}, r"got 1.5"),
        ({"gate_corridor": 0.9, "gate": "learned"}, r"needs a distance gate .* got gate='learned'"),
    ],
)
def test_corridor_refuses_bad_values(priors, kwargs, message):
    with pytest.raises(ValueError, match=message):
        _model(priors, **kwargs)


def test_latch_gate_switches_on_the_remembered_obstacle_not_the_reading(priors, tmp_path):
    """gate_latch_key: the avoidance column has control exactly where the observation's latch
    reads 1, whatever the sonar reads now (actor and critics alike), and the key is saved."""
    latch_space = spaces.Box(0.0, 1.0, (1,), np.float32)
    env = ToyRovEnv(("path", "sonar", "latch"), extra={"latch": latch_space})
    kw = dict(priors=[priors["pf_dsac"], priors["oa_dsac"]], net_arch=[16, 16])
    model = DiscreteSAC(
        SelectivePolicy, env, policy_kwargs={**kw, "gate_latch_key": "latch"}, seed=0
    )
    policy = model.policy
    obs = batch(policy.observation_space, len(DISTANCES), seed=3)
    sonar = np.ones_like(obs["sonar"])
    sonar[np.arange(len(DISTANCES)), 0] = DISTANCES / SONAR_RANGE
    obs["sonar"] = sonar.astype(np.float32)
    latched = th.tensor([True, False, True, True, False])  # unlike NEAR on rows 1, 3 and 4
    obs["latch"] = latched.float().numpy()[:, None]
    obs = policy.obs_to_tensor(obs)[0]
    expected = th.stack([(~latched).float(), latched.float()], dim=1)
    assert th.equal(policy.gate_weights(obs), expected)
    with th.no_grad():
        logits, q = policy.actor(obs), policy.critic(obs)
        _perturb(policy.actor.net.priors[1])
        for q_net in policy.critic.q_networks:
            _perturb(q_net.priors[1])
        assert th.equal((policy.actor(obs) != logits).any(dim=1), latched)
        assert th.equal((policy.critic(obs)[0] != q[0]).any(dim=1), latched)
    model.save(tmp_path / "spnn.zip")
    loaded = DiscreteSAC.load(tmp_path / "spnn.zip", device="cpu").policy
    assert loaded.actor.gate.latch_key == "latch"
    with pytest.raises(
        ValueError, match=r"gate_latch_key='latch' is not allowed: .* \(got 'soft'\)"
    ):
        DiscreteSAC(
            SelectivePolicy, env, policy_kwargs={**kw, "gate": "soft", "gate_latch_key": "latch"}
        )
    with pytest.raises(
        ValueError, match=r"gate_latch_key='memory' is not allowed: .*\['latch', 'path'"
    ):
        DiscreteSAC(SelectivePolicy, env, policy_kwargs={**kw, "gate_latch_key": "memory"})


def test_learned_gate_is_a_trained_softmax(priors):
    model = _model(priors, gate="learned")
    policy = model.policy
    g = policy.gate_weights(_obs(policy))
    assert th.all(g > 0) and th.allclose(g.sum(dim=1), th.ones(len(DISTANCES)))
    gate_params = list(policy.actor.gate.parameters())
    optimized = {id(p) for grp in policy.actor.optimizer.param_groups for p in grp["params"]}
    assert gate_params and all(id(p) in optimized for p in gate_params)
    before = [p.detach().clone() for p in gate_params]
    model.learn(60)
    assert any(not th.equal(a, b) for a, b in zip(before, gate_params, strict=True))


def test_lead_shares_are_logged_and_reset(priors):
    policy = _model(priors).policy
    obs = {k: v.cpu().numpy() for k, v in _obs(policy).items()}
    policy.predict(obs, deterministic=True)
    logs = policy.extra_logs()
    assert logs == {
        "gate/step_share_path_following": pytest.approx(2 / 5),
        "gate/step_share_obstacle_avoidance": pytest.approx(3 / 5),
    }
    assert policy.extra_logs() == {}


def test_lead_counts_of_many_predictions_are_exact(priors):
    """The counts wait for their reader, also past the pending bound: after 300 single-sample
    predictions (over PENDING_LEADS) they are the exact number of near and far samples."""
    policy = _model(priors).policy
    actor = policy.actor
    assert 300 > actor.PENDING_LEADS
    obs = {k: v.cpu().numpy() for k, v in _obs(policy).items()}
    for i in range(300):
        policy.predict({k: v[i % 5] for k, v in obs.items()}, deterministic=True)
    near = int(NEAR.sum()) * 60
    assert actor.lead_counts[0].tolist() == [300 - near, near]
    assert actor.lead_counts[1].tolist() == [0, 0]
    actor.lead_counts.zero_()
    assert actor.lead_counts.sum() == 0


def test_defaults_and_argument_names(priors):
    """The recommended set-up's eq. 15 weights (1, 1) and start as the selected prior, the
    paper's d_th; the paper's weights are one argument away."""
    policy = _model(priors).policy
    assert (policy.sigma, policy.own_weight, policy.d_th) == (1.0, 1.0, 12.5)
    assert policy.start_as_prior is True
    paper = _model(priors, sigma=0.5, own_weight=0.5, start_as_prior=False).policy
    assert (paper.sigma, paper.own_weight, paper.start_as_prior) == (0.5, 0.5, False)
    assert policy.sonar_range == 25.0 and policy.gate == "hard"
    assert not any(n.endswith("lateral_scale") for n, _ in policy.named_parameters())


def test_refuses_wrong_prior_count_and_missing_sonar(priors):
    with pytest.raises(ValueError, match="exactly two priors"):
        _model(priors, priors=[priors["pf_dsac"]])
    with pytest.raises(ValueError, match="'sonar' key"):
        DiscreteSAC(
            SelectivePolicy,
            ToyRovEnv(("path",)),
            policy_kwargs=dict(priors=[priors["pf_dsac"], priors["pf_dsac"]]),
        )
    with pytest.raises(ValueError, match="gate must be one of"):
        _model(priors, gate="fuzzy")


@pytest.mark.parametrize(
    "name, value",
    [("sigma", float("nan")), ("own_weight", float("inf")), ("d_th", -1.0), ("sigma", True)],
)
def test_refuses_eq15_weights_that_are_not_finite_numbers(priors, name, value):
    with pytest.raises(ValueError, match=f"{name} must be a finite number >= 0, got {value!r}"):
        _model(priors, **{name: value})


def test_refuses_swapped_priors_naming_which_file_is_which(priors):
    with pytest.raises(ValueError) as info:
        _model(priors, priors=[priors["oa_dsac"], priors["pf_dsac"]])
    message = str(info.value)
    assert "priors are swapped: 'oa_dsac.zip' observes 'sonar'" in message
    assert "'pf_dsac.zip' does not (a path-following column)" in message
    assert "expected [path_following_zip, obstacle_avoidance_zip], i.e. ['pf_dsac.zip'" in message


class _Capture(KVWriter):
    def __init__(self):
        self.records: list[dict] = []

    def write(self, key_values, key_excluded, step=0):
        self.records.append(dict(key_values))


def test_gate_shares_reach_the_training_logs(priors):
    model = _model(priors)
    capture = _Capture()
    model.set_logger(Logger(None, [capture]))
    model.learn(80, log_interval=1)
    keys = set().union(*capture.records)
    for name in ("path_following", "obstacle_avoidance"):
        assert f"train/gate/batch_share_{name}" in keys
        assert f"train/gate/step_share_{name}" in keys
    shares = [
        r["train/gate/batch_share_path_following"] + r["train/gate/batch_share_obstacle_avoidance"]
        for r in capture.records
        if "train/gate/batch_share_path_following" in r
    ]
    assert shares and all(s == pytest.approx(1.0) for s in shares)
