"""The prior-agreement diagnostic: an SPNN started as its selected prior agrees on every step."""

from __future__ import annotations

from progressive_helpers import ToyRovEnv, toy_model

from sb3_pnn import SelectivePolicy
from sb3_pnn.reproduce.tools.prior_agreement import REGIMES, step_counts, table


def _spnn(paths, **kwargs):
    return toy_model(
        SelectivePolicy,
        dict(priors=[paths["pf_dsac"], paths["oa_dsac"]], net_arch=[16, 16], **kwargs),
    )


def test_untrained_spnn_started_as_prior_agrees_everywhere(priors):
    counts, ends = step_counts(_spnn(priors, start_as_prior=True), ToyRovEnv(), 3, seed=5)
    steps = {r: counts[(r, "steps")] for r in REGIMES}
    assert sum(steps.values()) == 3 * 20 and sum(ends.values()) == 3
    for regime in REGIMES:
        assert counts[(regime, "agree")] == steps[regime]
        assert sum(counts[(regime, ("own", a))] for a in range(5)) == steps[regime]
    assert "| 0 | avoidance | " in "\n".join(table([(0, counts, ends)]))


def test_a_fresh_column_departs_from_the_prior(priors):
    counts, _ = step_counts(_spnn(priors, start_as_prior=False), ToyRovEnv(), 3, seed=5)
    assert sum(counts[(r, "agree")] for r in REGIMES) < 3 * 20
