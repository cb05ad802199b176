"""Median decoding on Table 1's ordered turns, and the tool that replays a study both ways."""

from __future__ import annotations

import json
import math
import shutil

import gymnasium as gym
import numpy as np
import pytest
import torch as th

import rov_envs  # noqa: F401 - registers the tasks
from rov_envs.physics.thrusters import ACTION_NAMES
from sb3_pnn import DiscreteSAC
from sb3_pnn.evaluation.evaluate import evaluate_policy_on_task
from sb3_pnn.reproduce.tools.greedy_decoding import (
    TURN_ORDER,
    MedianDecoded,
    main,
    median_actions,
)

L2, L1, S, R1, R2 = TURN_ORDER


def _logits(*rows: dict[int, float]) -> th.Tensor:
    """Logits whose softmax puts the given probabilities on the given actions (rest ~0)."""
    out = th.full((len(rows), 5), -30.0)
    for i, probs in enumerate(rows):
        for action, p in probs.items():
            out[i, action] = math.log(p)
    return out


def test_the_order_is_table_1s_turns_from_left_to_right():
    names = [ACTION_NAMES[a] for a in TURN_ORDER]
    assert names == ["Turn left 2", "Turn left 1", "Go straight", "Turn right 1", "Turn right 2"]


def test_median_plays_straight_between_balanced_turns_and_else_the_ordered_median():
    logits = _logits(
        {L1: 0.4, R1: 0.4, S: 0.2},  # mode: a turn (either); median: straight
        {R2: 1.0},  # one action: it
        {L2: 0.3, R1: 0.35, R2: 0.35},  # mode: a right turn; median: Turn right 1
        {L2: 0.6, R2: 0.4},  # the side with more than half
        {L1: 0.1, S: 0.1, R1: 0.8},
    )
    assert median_actions(logits).tolist() == [S, R2, R1, L2, R1]
    assert logits.argmax(dim=1)[0].item() in (L1, R1)  # where the two decoders differ


def test_median_decoded_predict(tmp_path):
    env = gym.make("rov_envs/PlanningStraight-v0")
    model = DiscreteSAC("MultiInputPolicy", env, seed=0, device="cpu")
    decoded = MedianDecoded(model)
    obs, _ = env.reset(seed=0)
    batch = {k: np.stack([v, v * 0.5]) for k, v in obs.items()}
    with th.no_grad():
        logits = model.policy.actor(model.policy.obs_to_tensor(batch)[0])
    actions, _ = decoded.predict(batch, deterministic=True)
    assert actions.tolist() == median_actions(logits).tolist()
    single, _ = decoded.predict(obs, deterministic=True)
    assert np.ndim(single) == 0 and single == actions[0]
    th.manual_seed(3)
    sampled, _ = decoded.predict(batch, deterministic=False)
    th.manual_seed(3)
    assert sampled.tolist() == model.predict(batch, deterministic=False)[0].tolist()


def test_the_tool_replays_a_run_both_ways_on_validation_seeds(tmp_path, capsys):
    run = tmp_path / "runs" / "spnn-straight-s0"
    run.mkdir(parents=True)
    kwargs = {"control_period": 0.5}
    model = DiscreteSAC(
        "MultiInputPolicy", gym.make("rov_envs/PlanningStraight-v0", **kwargs), seed=1
    )
    model.save(run / "model.zip")
    (run / "eval.json").write_text(json.dumps({"original": {"env_kwargs": kwargs}}))
    shutil.copytree(run, tmp_path / "runs" / "spnn-straight-s2")
    (tmp_path / "runs" / "spnn-straight-sx").mkdir()  # not a run of a training seed
    assert main([str(tmp_path), "--episodes", "2"]) == 0  # every run of the agent and path
    out = capsys.readouterr().out
    assert out.count("| mode |") == 2 and "| 2 | mode |" in out
    plan = evaluate_policy_on_task(
        DiscreteSAC.load(run / "model.zip"),
        "rov_envs/PlanningStraight-v0",
        2,
        20000,
        env_kwargs=kwargs,
    )
    assert f"| 0 | mode | {100 * plan.success_rate:.0f} %, {plan.mean_return:.0f}, " in out
    assert "| 0 | median | " in out and "mean, median: planning task" in out
    assert "| 0 | no reversal | " in out and "mean, no reversal: planning task" in out


def test_a_pid_run_is_refused(tmp_path, capsys):
    run = tmp_path / "runs" / "adaptive_pid-straight"
    run.mkdir(parents=True)
    (run / "manifest.json").write_text(json.dumps({"agent": "adaptive_pid"}))
    (run / "eval.json").write_text(json.dumps({"original": {"env_kwargs": {}}}))
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), "--agent", "adaptive_pid", "--seeds", "0"])
    assert stop.value.code == 2
    assert "is a PID baseline's run: expected a trained agent's" in capsys.readouterr().err


def test_a_study_without_such_runs_is_refused(tmp_path, capsys):
    (tmp_path / "runs").mkdir()
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), "--agent", "pnn", "--path", "sine"])
    assert stop.value.code == 2
    assert "holds no run of pnn on the sine path" in capsys.readouterr().err
