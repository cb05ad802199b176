"""KeepBestOnValidation: checks on schedule, keeps the best weights, and the study uses it."""

from __future__ import annotations

import json
from types import SimpleNamespace

import gymnasium as gym
import pytest
import torch as th

import rov_envs  # noqa: F401
import sb3_pnn.evaluation
from sb3_pnn import DiscreteSAC
from sb3_pnn.common.callbacks import VALIDATION_SEED, KeepBestOnValidation
from sb3_pnn.reproduce.planning.plan import RunSpec
from sb3_pnn.reproduce.planning.setups import OURS, PAPER, VALIDATION_EPISODES, VALIDATION_EVERY
from sb3_pnn.reproduce.running.work import run_work

ENV = "rov_envs/PathFollowingStraight-v0"


def _model() -> DiscreteSAC:
    env = gym.make(ENV)
    return DiscreteSAC("MultiInputPolicy", env, policy_kwargs={"net_arch": [8]}, seed=0)


def _first_weight(model: DiscreteSAC) -> th.Tensor:
    return next(iter(model.policy.state_dict().values())).clone()


def test_restore_brings_back_the_weights_of_the_best_check(monkeypatch) -> None:
    scores = iter([(0.2, 5.0), (0.6, -1.0), (0.6, -3.0), (0.4, 9.0)])
    calls = []

    def fake_evaluate(policy, env_id, n_episodes, seed, env_kwargs):
        calls.append((env_id, n_episodes, seed, env_kwargs))
        rate, ret = next(scores)
        return SimpleNamespace(success_rate=rate, mean_return=ret)

    monkeypatch.setattr(sb3_pnn.evaluation, "evaluate_policy_on_task", fake_evaluate)
    model = _model()
    keeper = KeepBestOnValidation(ENV, every=2, n_episodes=7, env_kwargs={"motion_obs": True})
    keeper.init_callback(model)
    snapshots = []
    for _ in range(4):
        with th.no_grad():
            for p in model.policy.parameters():
                p.add_(1.0)  # every check sees different weights
        snapshots.append(_first_weight(model))
        keeper.check()
    assert calls[0] == (ENV, 7, VALIDATION_SEED, {"motion_obs": True})
    # 0.6 beats 0.2; the later 0.6 has a lower mean return; 0.4 is worse: the second is kept
    assert [h["success_rate"] for h in keeper.history] == [0.2, 0.6, 0.6, 0.4]
    assert keeper.restore()
    assert th.equal(_first_weight(model), snapshots[1])
    assert keeper.to_dict()["history"][1]["mean_return"] == -1.0


def test_checks_every_n_episodes_during_learn() -> None:
    model = _model()
    keeper = KeepBestOnValidation(ENV, every=1, n_episodes=2)
    assert not keeper.restore()  # nothing kept yet: nothing changes
    model.learn(600, callback=keeper)  # the untrained policy ends episodes early
    assert keeper.episodes >= 1
    assert [h["episode"] for h in keeper.history] == list(range(1, keeper.episodes + 1))
    assert keeper.best_episode in {h["episode"] for h in keeper.history}


@pytest.mark.parametrize("bad", [0, -1, 1.5, True])
def test_bad_schedule_refused(bad) -> None:
    with pytest.raises(ValueError, match=f"every={bad!r} is not allowed"):
        KeepBestOnValidation(ENV, every=bad, n_episodes=3)


def test_setups_and_specs() -> None:
    assert PAPER.validation() == {}  # the paper: the policy at the end of the budget
    assert OURS.validation() == {"every": VALIDATION_EVERY, "episodes": VALIDATION_EPISODES}
    spec = RunSpec("r", "prior", "dsac", None, ENV, 0, 3)
    assert "validation" not in spec.to_dict()  # old runs keep their hash
    kept = RunSpec("r", "prior", "dsac", None, ENV, 0, 3, validation={"every": 1, "episodes": 2})
    assert RunSpec.from_dict(kept.to_dict()) == kept
    assert kept.config_hash() != spec.config_hash()


def test_study_run_saves_the_kept_policy(tmp_path) -> None:
    spec = RunSpec(
        "prior-pf_straight-s0", "prior", "dsac", None, ENV, seed=0, episodes=3,
        eval_tasks=(("own", ENV, {}),), eval_episodes=2,
        sac_kwargs={"learning_starts": 50, "policy_kwargs": {"net_arch": [8]}},
        env_kwargs={"start_noise": [1.0, 0.1]}, validation={"every": 1, "episodes": 2},
    )  # fmt: skip
    info = run_work(spec, tmp_path, {})
    record = json.loads((tmp_path / "validation.json").read_text())
    assert len(record["history"]) == 3 and record["every"] == 1
    assert info["kept_episode"] == record["best_episode"]
    best = max(record["history"], key=lambda h: (h["success_rate"], h["mean_return"]))
    assert record["best_episode"] == best["episode"]
    # the saved model replays the kept policy's validation score exactly
    saved = DiscreteSAC.load(tmp_path / "model.zip", device="cpu")
    again = sb3_pnn.evaluation.evaluate_policy_on_task(
        saved, ENV, n_episodes=2, seed=VALIDATION_SEED
    )
    assert again.mean_return == pytest.approx(best["mean_return"])
