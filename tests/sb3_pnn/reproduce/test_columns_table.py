"""The report's table of source columns names a column that fails its own task."""

from __future__ import annotations

from sb3_pnn.reproduce.planning.plan import PRIOR_ENVS, RunSpec
from sb3_pnn.reproduce.reporting.report import columns_table
from sb3_pnn.reproduce.running.results import RunResult, StudyResults


def _column(
    name: str, seed: int, rate: float, kind: str = "prior", manifest: dict | None = None
) -> RunResult:
    run_id = f"prior-{name}-s{seed}" if kind == "prior" else f"prior-{name}-best2-s{seed}"
    spec = RunSpec(run_id, kind, "dsac", None, PRIOR_ENVS[name], seed, 10)
    return RunResult(spec=spec, manifest=manifest or {}, evals={"own": {"success_rate": rate}})


def _results(*runs: RunResult) -> StudyResults:
    return StudyResults(runs={r.spec.run_id: r for r in runs}, missing=[], failures={})


def test_each_column_set_is_listed_and_a_failed_column_named() -> None:
    lines = columns_table(
        _results(
            _column("pf_sine", 1, 0.0),
            _column("pf_sine", 0, 1.0),
            _column("oa", 0, 0.9),
            _column("oa", 1, 0.5),
        )
    )
    assert "| pf_sine | 50 % (100 0) |" in lines  # column sets in seed order
    assert "| oa | 70 % (90 50) |" in lines
    named = [line for line in lines if line.startswith("- ")]
    assert len(named) == 1 and "`prior-pf_sine-s1` passes 0 %" in named[0]
    assert not any("pf_straight" in line for line in lines)  # no such column in the study


def test_the_kept_candidate_is_what_the_learners_read() -> None:
    # with columns the best of two runs, the select run is the column; a failed candidate that
    # was not kept is not named
    lines = columns_table(
        _results(
            _column("pf_sine", 0, 0.0),
            _column("pf_sine", 1, 1.0),
            _column("pf_sine", 0, 1.0, "select"),
        )
    )
    assert "| pf_sine | 100 % (100) |" in lines
    assert not any(line.startswith("- ") for line in lines)


def test_a_column_trained_again_is_named_with_its_seeds() -> None:
    attempts = [{"seed": 6, "kept_success": 0.0}, {"seed": 1006, "kept_success": 1.0}]
    lines = columns_table(_results(_column("pf_sine", 6, 1.0, manifest={"attempts": attempts})))
    named = [line for line in lines if line.startswith("- ")]
    assert named == [
        "- `prior-pf_sine-s6` was trained 2 times (seeds 6, 1006): an attempt that passes no "
        "validation check is trained again (prior_retries)."
    ]


def test_no_columns_no_table() -> None:
    assert columns_table(_results()) == []
