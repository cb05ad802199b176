"""The weaving diagnostic: reversals, straight steps and reading jumps by nearest-obstacle band."""

from __future__ import annotations

from collections import Counter

import pytest
from progressive_helpers import ToyRovEnv, toy_model

from sb3_pnn import SelectivePolicy
from sb3_pnn.reproduce.tools.action_reversals import (
    action_shares,
    band_names,
    main,
    run_episodes,
    step_counts,
)


def test_counts_by_band_match_a_hand_count():
    # sides: left, right, left, straight, right, left; readings in 0-5, 5-8 and out of view
    actions = [0, 4, 0, 2, 3, 1]
    nearest = [4.0, 4.0, 6.0, 6.0, 25.0, 25.0]
    surge = [0.5, 0.6, 0.7, 1.0, 0.6, 0.5]  # m/s after each step
    counts = step_counts(actions, nearest, sonar_range=25.0, jump=3.0, surge=surge)
    near, penalty, none = band_names(25.0)[0], band_names(25.0)[1], band_names(25.0)[-1]
    assert (near, penalty, none) == ("0-5 m", "5-8 m", "nothing in view")
    expected = {
        near: dict(steps=2, reversals=1, straight=0, jumps=0),
        penalty: dict(steps=2, reversals=1, straight=1, jumps=0),
        none: dict(steps=2, reversals=1, straight=0, jumps=1),  # 6 m -> out of view: a jump
    }
    for band, what in expected.items():
        assert {w: counts[(band, w)] for w in what} == what, band
    assert counts[(near, "surge")] == pytest.approx(1.1)  # summed per band: 0.5 + 0.6
    assert counts[(penalty, "surge")] == pytest.approx(1.7)
    assert sum(counts[(b, "steps")] for b in band_names(25.0)) == len(actions)
    assert [counts[("action", a)] for a in range(5)] == [2, 1, 1, 1, 1]
    lines = action_shares([(7, counts, Counter())]).splitlines()
    assert lines[1] == "  seed 7: 33 / 17 / 17 / 17 / 17 %"  # 2, 1, 1, 1, 1 of 6 steps
    with pytest.raises(ValueError, match=r"\(3,\) actions but \(2,\) readings"):
        step_counts([0, 1, 2], [1.0, 2.0], 25.0, 3.0)
    with pytest.raises(ValueError, match=r"\(3,\) actions but \(1,\) surge speeds"):
        step_counts([0, 1, 2], [1.0, 2.0, 3.0], 25.0, 3.0, surge=[1.0])


def test_episodes_are_counted_step_by_step(priors):
    model = toy_model(
        SelectivePolicy, dict(priors=[priors["pf_dsac"], priors["oa_dsac"]], net_arch=[16, 16])
    )
    counts, ends = run_episodes(model, ToyRovEnv(), 3, seed=5, sonar_range=25.0, jump=3.0)
    assert sum(counts[(b, "steps")] for b in band_names(25.0)) == 3 * 20
    assert sum(ends.values()) == 3


def test_bad_arguments_stop_with_a_message(tmp_path, capsys):
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), "--env", "rov_envs/Nope-v0"])
    assert stop.value.code == 2
    assert "--env 'rov_envs/Nope-v0' is not a registered task" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main([str(tmp_path), "--seeds", "0"])
    assert "model.zip does not exist" in capsys.readouterr().err


def test_a_pid_baseline_run_replays_without_a_model(tmp_path, capsys):
    """A study's PID run folder (no model.zip, no training seed) replays its baseline."""
    import json

    run = tmp_path / "runs" / "adaptive_pid-straight"
    run.mkdir(parents=True)
    (run / "manifest.json").write_text(json.dumps({"agent": "adaptive_pid"}))
    (run / "eval.json").write_text(json.dumps({"original": {"env_kwargs": {}}}))
    args = [str(tmp_path), "--agent", "adaptive_pid", "--episodes", "1"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "adaptive_pid on rov_envs/PlanningStraight-v0" in out and "| 0 | " in out
