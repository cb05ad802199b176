"""Bad input gives one clear line on stderr and exit status 2, never a traceback wall."""

from __future__ import annotations

from pathlib import Path

import pytest
from zoo_helpers import OA_ENV, PF_ENV, PLAN_ENV, fails, run_cli, train_fails

from sb3_pnn.zoo.cli import ENJOY_PROG, enjoy_main

DSAC_ENTRY = """\
rov_envs/PathFollowingStraight-v0:
  policy: MultiInputPolicy
  n_timesteps: 100
"""


def test_unknown_algo(capsys, in_tmp) -> None:
    line = train_fails(capsys, ["--algo", "spn", "--env", PLAN_ENV])
    assert "unknown algo 'spn'" in line and "spnn" in line


def test_missing_algo(capsys, in_tmp) -> None:
    assert "--algo is required" in train_fails(capsys, ["--env", PLAN_ENV])


def test_unknown_env(capsys, in_tmp) -> None:
    line = train_fails(capsys, ["--algo", "dsac", "--env", "rov_envs/PlaningStraight-v0"])
    assert "unknown env id 'rov_envs/PlaningStraight-v0'" in line
    assert "did you mean 'rov_envs/PlanningStraight-v0'" in line


def test_env_without_config_entry(capsys, in_tmp) -> None:
    line = train_fails(capsys, ["--algo", "dsac", "--env", "CartPole-v1"])
    assert "no entry for env 'CartPole-v1'" in line and "rov_envs/PlanningStraight-v0" in line


@pytest.mark.parametrize(
    ("yaml_text", "expected"),
    [
        (
            "rov_envs/PathFollowingStraight-v0:\n  n_timesteps: 100\n   policy: [\n",
            "malformed YAML",
        ),
        (DSAC_ENTRY + "  lerning_rate: 0.001\n", "unknown hyperparameter 'lerning_rate'"),
        ("rov_envs/PathFollowingStraight-v0: 12\n", "an entry must be a mapping"),
        (
            "rov_envs/PathFollowingStraight-v0:\n  policy: MultiInputPolicy\n",
            "missing 'n_timesteps'",
        ),
        (DSAC_ENTRY + "  policy_kwargs: [1, 2]\n", "policy_kwargs must be a mapping"),
        (DSAC_ENTRY + "  seed: 3\n", "'seed' is set by the command line"),
        ("- just\n- a list\n", "expected a mapping of env ids"),
    ],
)
def test_malformed_config(capsys, in_tmp: Path, yaml_text: str, expected: str) -> None:
    conf = in_tmp / "bad.yml"
    conf.write_text(yaml_text)
    line = train_fails(
        capsys, ["--algo", "dsac", "--env", "rov_envs/PathFollowingStraight-v0", "-conf", str(conf)]
    )
    assert expected in line and "bad.yml" in line


@pytest.mark.parametrize(
    ("algo", "bound", "expected"),
    [
        ("spnn", "d_th=0:40", "[0, 40] for d_th are out of range; allowed (0, 25] m"),
        ("spnn", "sigma=0.2:1.5", "[0.2, 1.5] for sigma are out of range; allowed [0, 1]"),
        ("spnn", "own_weight=0.9:0.1", "need low <= high"),
        ("spnn", "gate_width=1:2", "unknown tuning parameter(s) ['gate_width']"),
        ("dsac", "d_th=5:10", "d_th belong to spnn's selective policy; dsac has none"),
        ("dsac", "learning_rate=0:0.1", "for learning_rate are out of range; allowed (0, 1]"),
        ("dsac", "d_th=5:x", "bounds must be numbers"),
    ],
)
def test_out_of_range_tuning_bound(capsys, in_tmp, algo: str, bound: str, expected: str) -> None:
    env = PLAN_ENV if algo == "spnn" else "rov_envs/PathFollowingStraight-v0"
    line = train_fails(capsys, ["--algo", algo, "--env", env, "-optimize", f"--tune={bound}"])
    assert expected in line


def test_missing_prior_names_file_and_command(capsys, in_tmp) -> None:
    line = train_fails(capsys, ["--algo", "spnn", "--env", PLAN_ENV])
    assert "missing path-following prior for spnn on rov_envs/PlanningStraight-v0" in line
    assert (
        "logs/dsac/rov_envs-PathFollowingStraight-v0_<N>/rov_envs-PathFollowingStraight-v0.zip"
        in line
    )
    assert (
        "python -m sb3_pnn.train --algo dsac --env rov_envs/PathFollowingStraight-v0 -f logs"
        in line
    )


def test_missing_explicit_prior(capsys, in_tmp) -> None:
    argv = ["--algo", "pnn", "--env", PLAN_ENV, "--priors", "nowhere/pf.zip", "nowhere/oa.zip"]
    line = train_fails(capsys, argv)
    assert (
        "missing path-following prior for pnn" in line and "nowhere/pf.zip does not exist" in line
    )


def test_wrong_number_of_priors(capsys, in_tmp) -> None:
    line = train_fails(capsys, ["--algo", "spnn", "--env", PLAN_ENV, "--priors", "a.zip"])
    assert (
        "--priors got 1 path(s) but spnn" in line and "path-following, obstacle-avoidance" in line
    )


def test_swapped_priors(capsys, in_tmp: Path) -> None:
    import gymnasium as gym

    import rov_envs  # noqa: F401 - registers the tasks
    from sb3_pnn import DiscreteSAC

    for name, env_id in (("pf", PF_ENV), ("oa", OA_ENV)):
        model = DiscreteSAC("MultiInputPolicy", gym.make(env_id), policy_kwargs={"net_arch": [8]})
        model.save(in_tmp / f"{name}.zip")
    argv = ["--algo", "spnn", "--env", PLAN_ENV, "--priors", "oa.zip", "pf.zip", "-n", "10"]
    line = train_fails(capsys, argv)
    assert "priors are swapped: 'oa.zip' observes 'sonar'" in line
    assert "i.e. ['pf.zip', 'oa.zip']" in line


def test_bad_storage(capsys, in_tmp) -> None:
    line = train_fails(
        capsys,
        ["--algo", "dsac", "--env", "rov_envs/PathFollowingStraight-v0", "-optimize",
         "--storage", "study.db", "-n", "10"],
    )  # fmt: skip
    assert "--storage 'study.db': expected a journal file ending in .log" in line


def test_value_refused_by_the_learner(capsys, in_tmp: Path) -> None:
    conf = in_tmp / "bad.yml"
    conf.write_text(DSAC_ENTRY + "  ent_coef: lots\n")
    line = train_fails(
        capsys, ["--algo", "dsac", "--env", "rov_envs/PathFollowingStraight-v0", "-conf", str(conf)]
    )
    assert "ValueError" in line and "lots" in line and "bad.yml" in line


def test_unknown_hyperparameter_from_the_command_line(capsys, in_tmp) -> None:
    line = train_fails(
        capsys,
        [
            "--algo",
            "dsac",
            "--env",
            "rov_envs/PathFollowingStraight-v0",
            "-params",
            "lerning_rate:1",
        ],
    )
    assert "unknown hyperparameter 'lerning_rate'" in line and "with -params" in line


@pytest.mark.parametrize("steps", ["0", "-5"])
def test_train_refuses_a_non_positive_budget(capsys, in_tmp: Path, steps: str) -> None:
    conf = in_tmp / "small.yml"
    conf.write_text(DSAC_ENTRY)  # without the check, a 100-step run would start and succeed
    line = train_fails(capsys, ["--algo", "dsac", "--env", PF_ENV, "-n", steps, "-conf", str(conf)])
    assert f"-n/--n-timesteps {steps}: expected a positive number of environment steps" in line
    assert "leave -n out for the config's n_timesteps" in line


def test_enjoy_refuses_a_non_positive_budget(capsys, in_tmp) -> None:
    argv = ["--algo", "dsac", "--env", PF_ENV, "--no-render", "-n", "-3"]
    line = fails(capsys, enjoy_main, ENJOY_PROG, argv)
    assert "-n/--n-timesteps -3: expected a positive number of environment steps" in line


def test_enjoy_without_a_window(capsys, in_tmp) -> None:
    line = fails(capsys, enjoy_main, ENJOY_PROG, ["--algo", "spnn", "--env", PLAN_ENV])
    assert "has no window to render to" in line and "--record PATH.mp4" in line


def test_enjoy_without_a_model(capsys, in_tmp) -> None:
    line = fails(
        capsys,
        enjoy_main,
        ENJOY_PROG,
        ["--algo", "spnn", "--env", PLAN_ENV, "-f", "logs", "--no-render"],
    )
    assert "no trained spnn model for rov_envs/PlanningStraight-v0" in line
    assert "python -m sb3_pnn.train --algo spnn --env rov_envs/PlanningStraight-v0 -f logs" in line


def test_command_line_gives_one_line_and_status_2(tmp_path: Path) -> None:
    result = run_cli("train", "--algo", "spnn", "--env", PLAN_ENV, cwd=tmp_path, check=False)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("python -m sb3_pnn.train: error: missing")


def test_unknown_setup(capsys, in_tmp) -> None:
    line = train_fails(capsys, ["--algo", "dsac", "--env", PF_ENV, "--setup", "papr"])
    assert "--setup 'papr': did you mean 'paper'?" in line and "ours, paper" in line


def test_setup_and_conf_file_together(capsys, in_tmp) -> None:
    (in_tmp / "mine.yml").write_text(DSAC_ENTRY)
    argv = ["--algo", "dsac", "--env", PF_ENV, "--setup", "paper", "--conf-file", "mine.yml"]
    line = train_fails(capsys, argv)
    assert "--setup paper and --conf-file mine.yml both pick" in line
