"""The per-path factor ``pnn_critic_priors``: which planning path's PNN critics read the prior's
critic, and that a per-path choice reproduces, run for run, the specs of the studies that chose
it (so their runs can be adopted instead of retrained)."""

from __future__ import annotations

import pytest

from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.planning.setups import (
    OURS,
    PAPER,
    describe_value,
    parse_setup_changes,
    path_of_env,
)

STUDY_SCHEDULE = ("updates=step:4", "prior_updates=step:1")


def pnn_specs(*changes: str) -> dict[str, object]:
    """PNN's run specs of a one-seed ``ours`` study with ``--set`` ``changes``: path -> spec."""
    config = StudyConfig(
        budget_name="quick", seeds=1, setup_changes=tuple(parse_setup_changes(changes).items())
    )
    return {s.path: s for s in build_plan(config) if s.agent == "pnn"}


def test_each_value_names_the_paths_whose_critics_read_the_prior() -> None:
    expected = {
        "both": (True, True),
        "straight": (True, False),
        "sine": (False, True),
        "neither": (False, False),
    }
    for value, (on_straight, on_sine) in expected.items():
        setup = PAPER.with_(pnn_critic_priors=value)
        for path, on in (("straight", on_straight), ("sine", on_sine)):
            kwargs = setup.sac_kwargs(agent="pnn", path=path)["policy_kwargs"]
            assert kwargs["critic_priors"] is on, (value, path)
        # no other agent reads it
        assert "critic_priors" not in setup.sac_kwargs(agent="spnn", path="sine")["policy_kwargs"]


def test_booleans_of_earlier_commands_still_work() -> None:
    """``--set pnn_critic_priors=false`` (the commands in docs/ablation) means neither path."""
    assert PAPER.with_(**parse_setup_changes(["pnn_critic_priors=false"])).pnn_critic_priors == (
        "neither"
    )
    assert PAPER.with_(**parse_setup_changes(["pnn_critic_priors=true"])).pnn_critic_priors == (
        "both"
    )
    assert parse_setup_changes(["pnn_critic_priors=straight"]) == {"pnn_critic_priors": "straight"}
    assert describe_value("pnn_critic_priors", "straight") == "on the straight path only"
    assert describe_value("pnn_critic_priors", "neither") == "off"


def test_bad_values_are_refused_by_name() -> None:
    with pytest.raises(ValueError, match=r"pnn_critic_priors='curvy' is not allowed: expected one"):
        PAPER.with_(pnn_critic_priors="curvy")
    with pytest.raises(ValueError, match=r"--set 'pnn_critic_priors=3' is not allowed"):
        parse_setup_changes(["pnn_critic_priors=3"])
    # a per-path value needs the path
    with pytest.raises(ValueError, match="depends on the path: expected path='straight' or 'sine'"):
        PAPER.with_(pnn_critic_priors="straight").sac_kwargs(agent="pnn")
    with pytest.raises(ValueError, match=r"path='spiral' is not allowed"):
        PAPER.on_path("pnn_critic_priors", "spiral")


def test_path_of_env() -> None:
    assert path_of_env("rov_envs/PlanningSineDense-v0") == "sine"
    assert path_of_env("rov_envs/PathFollowingSine-v0") == "sine"
    assert path_of_env("rov_envs/PlanningStraightUniform-v0") == "straight"
    assert path_of_env("ObstacleAvoidance-v0") == "straight"
    with pytest.raises(ValueError, match="env 'rov_envs/Nope-v0' is not an rov_envs task"):
        path_of_env("rov_envs/Nope-v0")


def test_a_per_path_choice_reproduces_each_paths_runs_of_the_uniform_studies() -> None:
    """Q-columns on the straight path only: the straight PNN run is the one of the study with
    them everywhere, the sine run the one of the study with them nowhere, hash for hash."""
    per_path = pnn_specs(*STUDY_SCHEDULE, "pnn_critic_priors=straight")
    on = pnn_specs(*STUDY_SCHEDULE, "pnn_critic_priors=true")
    off = pnn_specs(*STUDY_SCHEDULE, "pnn_critic_priors=false")
    assert per_path["straight"].config_hash() == on["straight"].config_hash()
    assert per_path["sine"].config_hash() == off["sine"].config_hash()
    assert per_path["sine"].config_hash() != on["sine"].config_hash()
    assert OURS.sac_kwargs(agent="pnn", path="straight")["policy_kwargs"].get(
        "critic_priors", True
    ) is OURS.on_path("pnn_critic_priors", "straight")


def test_start_as_prior_is_per_path_too_and_off_in_the_paper() -> None:
    """``pnn_start_as_prior`` takes the same values; the paper's is the random start, ours starts
    PNN as its prior on the straight path only, and SPNN's factor is a plain bool."""
    assert PAPER.pnn_start_as_prior == "neither" and OURS.pnn_start_as_prior == "straight"
    for path in ("straight", "sine"):
        assert PAPER.sac_kwargs(agent="pnn", path=path)["policy_kwargs"]["start_as_prior"] is False
        assert PAPER.sac_kwargs(agent="spnn", path=path)["policy_kwargs"]["start_as_prior"] is False
        # ours starts SPNN as its selected prior on both paths (with eq. 15's weights at 1)
        assert OURS.sac_kwargs(agent="spnn", path=path)["policy_kwargs"]["start_as_prior"] is True
    assert OURS.sac_kwargs(agent="pnn", path="straight")["policy_kwargs"]["start_as_prior"] is True
    assert OURS.sac_kwargs(agent="pnn", path="sine")["policy_kwargs"]["start_as_prior"] is False
    both = PAPER.with_(**parse_setup_changes(["pnn_start_as_prior=true"]))
    assert both.pnn_start_as_prior == "both" and both.on_path("pnn_start_as_prior", "sine")
    assert describe_value("pnn_start_as_prior", "straight") == "on the straight path only"
    spnn = PAPER.with_(**parse_setup_changes(["spnn_start_as_prior=true"]))
    assert spnn.sac_kwargs(agent="spnn")["policy_kwargs"]["start_as_prior"] is True
    with pytest.raises(ValueError, match=r"pnn_start_as_prior='curvy' is not allowed"):
        PAPER.with_(pnn_start_as_prior="curvy")
    with pytest.raises(ValueError, match=r"--set 'spnn_start_as_prior=straight' is not allowed"):
        parse_setup_changes(["spnn_start_as_prior=straight"])


def test_ours_per_path_start_reproduces_the_runs_it_was_chosen_on() -> None:
    """The straight PNN run of today's ``ours`` is the one of the study that started PNN as its
    prior on both paths (docs/ablation/start_as_prior), the sine run the one that started at
    random, hash for hash: so both can be adopted, not retrained."""
    today = pnn_specs(*STUDY_SCHEDULE)
    everywhere = pnn_specs(*STUDY_SCHEDULE, "pnn_start_as_prior=true")
    nowhere = pnn_specs(*STUDY_SCHEDULE, "pnn_start_as_prior=false")
    assert today["straight"].config_hash() == everywhere["straight"].config_hash()
    assert today["sine"].config_hash() == nowhere["sine"].config_hash()
    assert today["straight"].config_hash() != nowhere["straight"].config_hash()


def test_init_from_prior_is_per_path_for_both_progressive_agents() -> None:
    """``pnn_init_from_prior`` / ``spnn_init_from_prior`` take the per-path values; off is the
    paper's section 3.2."""
    assert PAPER.pnn_init_from_prior == "neither" and PAPER.spnn_init_from_prior == "neither"
    for agent in ("pnn", "spnn"):
        for path in ("straight", "sine"):
            kwargs = PAPER.sac_kwargs(agent=agent, path=path)["policy_kwargs"]
            assert kwargs["init_from_prior"] is False
    setup = PAPER.with_(
        **parse_setup_changes(["pnn_init_from_prior=sine", "spnn_init_from_prior=true"])
    )
    assert setup.sac_kwargs(agent="pnn", path="sine")["policy_kwargs"]["init_from_prior"] is True
    assert (
        setup.sac_kwargs(agent="pnn", path="straight")["policy_kwargs"]["init_from_prior"] is False
    )
    for path in ("straight", "sine"):
        assert setup.sac_kwargs(agent="spnn", path=path)["policy_kwargs"]["init_from_prior"]
    assert (
        "init_from_prior" not in setup.sac_kwargs(agent="sac_single", path="sine")["policy_kwargs"]
    )
    with pytest.raises(ValueError, match=r"spnn_init_from_prior='wavy' is not allowed"):
        PAPER.with_(spnn_init_from_prior="wavy")


def test_the_sine_path_can_have_a_lateral_scale_of_its_own() -> None:
    """``pnn_lateral_init_sine`` refines ``pnn_lateral_init`` on the sine path only; unset, the
    runs keep their hashes; bad values are refused by name."""
    changes = parse_setup_changes(["pnn_lateral_init=0", "pnn_lateral_init_sine=1"])
    setup = PAPER.with_(**changes)
    assert (
        setup.sac_kwargs(agent="pnn", path="straight")["policy_kwargs"]["lateral_scale_init"] == 0
    )
    assert setup.sac_kwargs(agent="pnn", path="sine")["policy_kwargs"]["lateral_scale_init"] == 1
    unset = PAPER.with_(pnn_lateral_init=0.0)
    assert unset.sac_kwargs(agent="pnn", path="sine")["policy_kwargs"]["lateral_scale_init"] == 0
    assert (
        pnn_specs(*STUDY_SCHEDULE)["straight"].config_hash()
        == pnn_specs(*STUDY_SCHEDULE, "pnn_lateral_init_sine=0.5")["straight"].config_hash()
    )
    with pytest.raises(ValueError, match="depends on the path"):
        setup.sac_kwargs(agent="pnn")
    with pytest.raises(ValueError, match=r"pnn_lateral_init_sine=true' is not allowed.*a number"):
        parse_setup_changes(["pnn_lateral_init_sine=true"])
    with pytest.raises(ValueError, match=r"pnn_lateral_init_sine=inf is not allowed"):
        PAPER.with_(pnn_lateral_init_sine=float("inf"))
    assert describe_value("pnn_lateral_init_sine", None) == "as on the straight path"
