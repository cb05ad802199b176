"""A source column that passes no validation check is trained again from another seed
(``prior_retries``)."""

from __future__ import annotations

import json

import pytest

from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import OURS, PAPER
from sb3_pnn.reproduce.running import work
from sb3_pnn.reproduce.running.work import RETRY_SEED_STEP, run_work


def _plan(retries: int, seeds: int = 2) -> dict:
    config = StudyConfig(
        budget_name="tiny", seeds=seeds, setup_changes=(("prior_retries", retries),)
    )
    return {s.run_id: s for s in build_plan(config)}


def test_no_retries_plans_the_study_as_before() -> None:
    before = {
        s.run_id: s.config_hash() for s in build_plan(StudyConfig(budget_name="tiny", seeds=2))
    }
    assert {i: s.config_hash() for i, s in _plan(0).items()} == before


def test_retries_reach_the_columns_and_no_learner() -> None:
    plan = _plan(2)
    for run_id, spec in plan.items():
        if spec.kind == "prior":
            assert spec.validation["retries"] == 2, run_id
        else:
            assert "retries" not in spec.validation, run_id
    with pytest.raises(ValueError, match="prior_retries=1 is not allowed with keep_best off"):
        PAPER.with_(prior_retries=1)
    with pytest.raises(ValueError, match="prior_retries=-1 is not allowed: expected an integer"):
        OURS.with_(prior_retries=-1)


def _fake_train(successes: dict[int, float], trained: list[int]):
    """A train() whose kept check passes ``successes[seed]`` of its episodes."""

    def fake(spec, tmp, deps):
        trained.append(spec.seed)
        check = {"episode": 25, "success_rate": successes[spec.seed], "mean_return": 1.0}
        (tmp / "validation.json").write_text(json.dumps({"history": [check], "best_episode": 25}))
        for name in ("model.zip", "episodes.json", "trajectories.npz"):
            (tmp / name).write_text(f"{name} of seed {spec.seed}")
        return f"model {spec.seed}", {"kept_episode": 25}

    return fake


@pytest.mark.parametrize(
    ("successes", "trained_seeds", "kept_seed"),
    [
        ({3: 0.5}, [3], 3),  # passed a check: kept as it is, never retrained
        ({3: 0.0, 1003: 0.9}, [3, 1003], 1003),  # failed, the retry passes
        ({3: 0.0, 1003: 0.0, 2003: 0.0}, [3, 1003, 2003], 3),  # all fail: the first of equals
        ({3: 0.0, 1003: 0.0, 2003: 1.0}, [3, 1003, 2003], 2003),
    ],
)
def test_a_column_is_retrained_only_while_no_check_passes(
    tmp_path, monkeypatch, successes, trained_seeds, kept_seed
) -> None:
    spec = _plan(2, seeds=4)["prior-oa-s3"]
    trained: list[int] = []
    monkeypatch.setattr(work, "train", _fake_train(successes, trained))
    model, info = work.train_with_retries(spec, tmp_path, {})
    assert trained == trained_seeds
    assert model == f"model {kept_seed}"
    assert (tmp_path / "model.zip").read_text() == f"model.zip of seed {kept_seed}"
    assert [a["seed"] for a in info["attempts"]] == trained_seeds
    assert [a["kept_success"] for a in info["attempts"]] == [successes[s] for s in trained_seeds]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["model.zip", "validation.json", "episodes.json", "trajectories.npz"]
    )


def test_a_real_column_that_passes_no_check_trains_again(tmp_path) -> None:
    # the tiny budget's column ends before its first check (none passes, so it is retried):
    # both attempts train, and the run's records are one attempt's
    spec = _plan(1, seeds=1)["prior-pf_straight-s0"]
    info = run_work(spec, tmp_path, {})
    assert [a["seed"] for a in info["attempts"]] == [0, RETRY_SEED_STEP]
    assert [a["kept_success"] for a in info["attempts"]] == [None, None]
    assert (tmp_path / "model.zip").is_file() and (tmp_path / "eval.json").is_file()
    assert not any(p.name.startswith("attempt-") for p in tmp_path.iterdir())
