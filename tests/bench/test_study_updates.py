"""bench/study_updates.py: it times the study's own planned runs, names their copy terms, and
leaves each model's term weights as they were after timing it without them."""

from __future__ import annotations

import runpy
from pathlib import Path

import pytest

BENCH = runpy.run_path(str(Path(__file__).parents[2] / "bench" / "study_updates.py"))


def test_unknown_run_kind_is_refused_by_name() -> None:
    with pytest.raises(SystemExit, match="'spnn-spiral'"):
        BENCH["planned_specs"](["spnn-sine", "spnn-spiral"])


def test_copy_terms_are_the_planned_ones_and_restored_after_timing(tmp_path: Path) -> None:
    specs, by_id = BENCH["planned_specs"](["spnn-sine", "sac_single-sine"])
    spnn = BENCH["build_model"](
        specs["spnn-sine"], BENCH["untrained_deps"](specs["spnn-sine"], by_id, tmp_path)
    )
    planned = specs["spnn-sine"].sac_kwargs["policy_kwargs"]
    expected = {n: planned[n] for n in BENCH["COPY_TERMS"] if planned.get(n, 0) > 0}
    assert expected and BENCH["copy_weights"](spnn) == expected
    spnn.learn(spnn.learning_starts + spnn.batch_size)
    assert BENCH["step_ms"](spnn, 2, {name: 0.0 for name in expected}) > 0
    assert BENCH["copy_weights"](spnn) == expected  # restored
    sac = BENCH["build_model"](specs["sac_single-sine"], {})
    assert BENCH["copy_weights"](sac) == {}
