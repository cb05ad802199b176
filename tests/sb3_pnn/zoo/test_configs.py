"""The shipped zoo_configs: every task each algo applies to, both set-ups, valid entries."""

from __future__ import annotations

from pathlib import Path

import pytest

import rov_envs
from sb3_pnn import DiscreteSAC
from sb3_pnn.reproduce.planning.plan import PRIOR_ENVS
from sb3_pnn.reproduce.planning.setups import SETUPS, path_of_env
from sb3_pnn.zoo.configs import (
    CONFIG_ENV_VAR,
    default_config_path,
    load_config_file,
    validate_entry,
)
from sb3_pnn.zoo.errors import ZooUsageError
from sb3_pnn.zoo.priors import PriorRef, parse_prior
from sb3_pnn.zoo.registry import OUR_ALGOS

PLANNING = [e for e in rov_envs.ENV_IDS if "/Planning" in e]
APPLIES = {"dsac": list(rov_envs.ENV_IDS), "sac_multi": PLANNING, "pnn": PLANNING, "spnn": PLANNING}
#: Tables 2-3 of the paper, the same in both shipped set-ups.
TABLES_2_3 = {
    "learning_rate": 3e-4,
    "tau": 0.005,
    "gamma": 0.99,
    "ent_coef": "auto_0.2",
    "buffer_size": 1_000_000,
    "batch_size": 256,
}


def _policy_defaults(algo: str) -> dict:
    """The keyword defaults of the policy class an algo's entries name."""
    import inspect

    from sb3_pnn import ProgressivePolicy, SelectivePolicy

    cls = {"pnn": ProgressivePolicy, "spnn": SelectivePolicy}.get(algo)
    if cls is None:
        return {}
    return {
        name: p.default
        for name, p in inspect.signature(cls.__init__).parameters.items()
        if p.default is not inspect.Parameter.empty
    }


def entries(algo: str, setup: str = "ours") -> dict:
    return load_config_file(default_config_path(algo, setup))


def as_zoo_train_freq(train_freq: list) -> object:
    """rl_zoo3 writes ``[1, episode]`` for a tuple and a plain ``K`` for ``(K, "step")``."""
    return train_freq[0] if train_freq[1] == "step" else list(train_freq)


@pytest.mark.parametrize("setup", list(SETUPS))
@pytest.mark.parametrize("algo", list(OUR_ALGOS))
def test_shipped_entries_are_the_studys_setups(algo: str, setup: str) -> None:
    """zoo_configs/<algo>.yml is the study's ``ours``, zoo_configs/paper/<algo>.yml its ``paper``:
    the update schedule, network, learning_starts and every env keyword come from setups.py."""
    training = SETUPS[setup]
    config = entries(algo, setup)
    path = default_config_path(algo, setup)
    assert path.parent.name == ("zoo_configs" if setup == "ours" else "paper")
    for env_id in APPLIES[algo]:
        source = env_id not in PLANNING  # dsac on a source task trains a prior column
        column = {v: k for k, v in PRIOR_ENVS.items()}.get(env_id, "")  # oa: oa_updates
        sac = training.sac_kwargs(prior=source, agent=algo, path=path_of_env(env_id), column=column)
        entry = validate_entry(
            config[env_id], name=env_id, path=path, algo=algo, algo_class=OUR_ALGOS[algo]
        )
        for key, value in TABLES_2_3.items():
            assert entry[key] == value, (algo, env_id, key)
        assert entry["train_freq"] == as_zoo_train_freq(sac["train_freq"]), (setup, env_id)
        assert entry["gradient_steps"] == sac["gradient_steps"]
        assert entry["learning_starts"] == sac["learning_starts"]
        assert entry.get("n_steps", 1) == sac.get("n_steps", 1), (setup, algo, env_id)
        epsilon = sac.get("exploration_epsilon", 0.0)
        assert entry.get("exploration_epsilon", 0.0) == epsilon, (setup, algo, env_id)
        env_kwargs = dict(entry["env_kwargs"])
        expected = training.train_env_kwargs(env_id)  # the path followers' wider start included
        assert env_kwargs.pop("start_noise") == pytest.approx(expected.pop("start_noise"))
        assert env_kwargs == expected, (setup, algo, env_id)
        if algo != "sac_multi":  # SAC-Multi takes its architecture from the prior
            defaults = _policy_defaults(algo)
            for key, value in sac["policy_kwargs"].items():
                # an entry may leave out a value that is the policy class's own default
                given = entry["policy_kwargs"].get(key, defaults.get(key))
                assert given == value, (setup, algo, env_id, key)
        assert entry["n_timesteps"] > 0


def test_setup_picks_the_folder_and_refuses_an_unknown_one() -> None:
    assert default_config_path("dsac", "paper").parent.name == "paper"
    with pytest.raises(ZooUsageError, match="--setup 'papr': did you mean 'paper'"):
        default_config_path("dsac", "papr")


@pytest.mark.parametrize("setup", list(SETUPS))
@pytest.mark.parametrize("algo", ["pnn", "spnn", "sac_multi"])
def test_priors_match_the_task(algo: str, setup: str) -> None:
    for env_id, entry in entries(algo, setup).items():
        if env_id not in PLANNING:
            continue
        priors = [parse_prior(item, env_id) for item in entry["priors"]]
        assert all(isinstance(p, PriorRef) and p.algo == "dsac" for p in priors)
        sine = "Sine" in env_id
        expected = "rov_envs/PathFollowingSine-v0" if sine else "rov_envs/PathFollowingStraight-v0"
        assert priors[0].env == expected
        if algo == "spnn":
            assert [p.env for p in priors[1:]] == ["rov_envs/ObstacleAvoidance-v0"]
            pk = entry["policy_kwargs"]
            training = SETUPS[setup]  # the set-up's eq. 15 switch and weights
            assert (pk["d_th"], pk["sigma"], pk["own_weight"], pk["gate"]) == (
                training.spnn_d_th,
                training.spnn_sigma,
                training.spnn_own_weight,
                training.spnn_gate_of("sine" if sine else "straight"),
            )
        elif algo == "pnn" and SETUPS[setup].pnn_reads_avoidance("sine" if sine else "straight"):
            assert [p.env for p in priors[1:]] == ["rov_envs/ObstacleAvoidance-v0"]
        else:
            assert len(priors) == 1


def test_config_folder_override(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "dsac.yml").write_text("default:\n  n_timesteps: 10\n")
    monkeypatch.setenv(CONFIG_ENV_VAR, str(tmp_path))
    assert default_config_path("dsac") == tmp_path / "dsac.yml"
    assert default_config_path("spnn").parent.name == "zoo_configs"  # falls back
    with pytest.raises(ZooUsageError, match="no configuration file for algo 'nope'"):
        default_config_path("nope")


def test_unknown_key_lists_the_accepted_ones() -> None:
    with pytest.raises(ZooUsageError, match="unknown hyperparameter 'lr'.*learning_rate") as info:
        validate_entry(
            {"n_timesteps": 1, "lr": 1}, name="x", path="f.yml", algo="dsac", algo_class=DiscreteSAC
        )
    assert "_init_setup_model" not in str(info.value)  # SB3's internal argument


def test_mistyped_key_gets_a_suggestion() -> None:
    with pytest.raises(ZooUsageError) as info:
        validate_entry(
            {"n_timesteps": 1, "learning_rat": 0.1},
            name="x",
            path="f.yml",
            algo="dsac",
            algo_class=DiscreteSAC,
        )
    assert str(info.value).endswith(
        "unknown hyperparameter 'learning_rat' for dsac; did you mean 'learning_rate'?"
    )
