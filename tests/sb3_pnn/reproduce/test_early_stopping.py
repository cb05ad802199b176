"""sb3_pnn/reproduce/tools/early_stopping.py: a patience stop read off a run's validation record
ends where it should, keeps the check KeepBestOnValidation would have kept by then, and counts
the training steps it ran."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import pytest

import sb3_pnn.evaluation
from sb3_pnn.common.callbacks import KeepBestOnValidation
from sb3_pnn.reproduce.tools.early_stopping import main, stop_point, stopped_run, summarize

SCORES = [(0.2, 5.0), (0.6, -1.0), (0.6, -3.0), (0.4, 9.0), (0.6, -1.0), (1.0, 0.0), (0.9, 50.0)]


def _kept_by_callback(scores, monkeypatch) -> int:
    """The index of the check KeepBestOnValidation keeps among ``scores``."""
    it = iter(scores)

    def fake_evaluate(policy, env_id, n_episodes, seed, env_kwargs):
        rate, ret = next(it)
        return SimpleNamespace(
            success_rate=rate,
            mean_return=ret,
            mean_abs_cross_track=1.0,
            mean_abs_heading_error=0.1,
            mean_time_to_target=100.0,
        )

    monkeypatch.setattr(sb3_pnn.evaluation, "evaluate_policy_on_task", fake_evaluate)
    keeper = KeepBestOnValidation("rov_envs/PathFollowingStraight-v0", every=1, n_episodes=1)
    keeper.model = SimpleNamespace(policy=SimpleNamespace(state_dict=lambda: {}))
    for i in range(len(scores)):
        keeper.episodes = i + 1
        keeper.check()
    return keeper.best_episode - 1


def test_without_a_stop_the_kept_check_is_the_callbacks(monkeypatch) -> None:
    # ties (the second 0.6 / -1.0) go to the earlier check, as in the callback
    assert stop_point(SCORES, 100) == (6, 5)
    assert _kept_by_callback(SCORES, monkeypatch) == 5
    assert _kept_by_callback(SCORES[:3], monkeypatch) == stop_point(SCORES[:3], 100)[1] == 1


def test_patience_counts_checks_since_the_best() -> None:
    # best at 1; checks 2 and 3 are not better: patience 2 stops at 3, keeping 1
    assert stop_point(SCORES, 2) == (3, 1)
    # patience 3: check 4 equals the best (not better), so the stop comes at 4
    assert stop_point(SCORES, 3) == (4, 1)
    assert stop_point(SCORES, 4) == (6, 5)


@pytest.mark.parametrize("bad", [0, -2, 1.5, True])
def test_bad_patience_is_refused(bad) -> None:
    with pytest.raises(ValueError, match=f"patience={bad!r}"):
        stop_point(SCORES, bad)


def _study(tmp_path: Path) -> Path:
    study = tmp_path / "study"
    # the runs' records as KeepBestOnValidation writes them: it kept checks 5 and 1
    for name, scores, kept in (("spnn-sine-s0", SCORES, 5), ("spnn-sine-s1", SCORES[:2], 1)):
        run = study / "runs" / name
        run.mkdir(parents=True)
        history = [
            {"episode": 25 * (i + 1), "success_rate": s, "mean_return": r}
            for i, (s, r) in enumerate(scores)
        ]
        record = {"history": history, "best_episode": 25 * (kept + 1)}
        (run / "validation.json").write_text(json.dumps(record))
        lengths = [10] * 25 * len(scores)
        (run / "episodes.json").write_text(json.dumps({"lengths": lengths}))
    (study / "runs" / "pid-sine").mkdir()  # no validation record: left out
    return study


def test_a_stopped_runs_steps_and_kept_check(tmp_path: Path) -> None:
    run = _study(tmp_path) / "runs" / "spnn-sine-s0"
    outcome = stopped_run(run, 2)
    # stops at the check of episode 100 (index 3), keeps episode 50's (0.6) against 1.0
    assert outcome["steps_run"] == 100 * 10 and outcome["steps"] == 175 * 10
    assert not outcome["same_check"]
    assert outcome["success_change"] == pytest.approx(-0.4)
    assert stopped_run(tmp_path / "study" / "runs" / "pid-sine", 2) is None


def test_summary_rows_and_the_command(tmp_path: Path, capsys) -> None:
    study = _study(tmp_path)
    rows = {(r["runs"], r["patience"]): r for r in summarize(study, [2])}
    assert set(rows) == {("spnn-sine", 2), ("all", 2)}
    assert rows["spnn-sine", 2]["n"] == 2 and rows["spnn-sine", 2]["same_check"] == 1
    # the study's share weighs each run by its steps: (1000 + 500) of (1750 + 500)
    assert rows["all", 2]["steps_share"] == pytest.approx(1500 / 2250)
    main([str(study), "--patience", "2"])
    assert "| all | 2 | 2 | 1 of 2 |" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main([str(tmp_path / "nowhere")])


def test_bad_patience_and_a_corrupt_record_are_refused_by_name(tmp_path: Path, capsys) -> None:
    study = _study(tmp_path)
    with pytest.raises(SystemExit):
        main([str(study), "--patience", "0"])
    assert "--patience 0 is not allowed: expected integers >= 1" in capsys.readouterr().err
    (study / "runs" / "spnn-sine-s1" / "validation.json").write_text("{not json")
    with pytest.raises(SystemExit):
        main([str(study)])
    err = capsys.readouterr().err
    assert "spnn-sine-s1" in err and "not a readable JSON record" in err
    (study / "runs" / "spnn-sine-s1" / "validation.json").write_text(
        '{"history": [{"episode": 25}], "best_episode": 25}'
    )
    with pytest.raises(SystemExit):
        main([str(study)])
    assert "another shape" in capsys.readouterr().err


def test_a_record_with_a_route_bound_is_ranked_by_it(tmp_path: Path) -> None:
    run = tmp_path / "runs" / "pnn-sine-s0"
    run.mkdir(parents=True)
    # (success, return, mean abs(g)): with the 2 m bound the callback keeps check 2 (within 2 m)
    checks = [(1.0, 90.0, 3.0), (1.0, 60.0, 1.5), (1.0, 95.0, 2.5)]
    history = [
        {"episode": 25 * (i + 1), "success_rate": s, "mean_return": r, "mean_abs_cross_track": g}
        for i, (s, r, g) in enumerate(checks)
    ]
    record = {"history": history, "best_episode": 50, "route_bound": 2.0}
    (run / "validation.json").write_text(json.dumps(record))
    (run / "episodes.json").write_text(json.dumps({"lengths": [10] * 75}))
    # without a stop the bounded ranking keeps the run's own check; by return alone (the
    # record read without its bound) check 3 would be kept instead
    assert stopped_run(run, 5)["same_check"]
    record.pop("route_bound")
    (run / "validation.json").write_text(json.dumps(record))
    assert not stopped_run(run, 5)["same_check"]
