"""End to end from the command line on tiny budgets: priors -> SPNN -> TensorBoard -> enjoy."""

from __future__ import annotations

import shutil
from pathlib import Path

import imageio.v2 as imageio
import pytest
import yaml
from tensorboard.backend.event_processing.event_accumulator import EventAccumulator
from zoo_helpers import OA_ENV, PF_ENV, PLAN_ENV, TINY, run_cli

pytestmark = pytest.mark.slow

RUN = "rov_envs-PlanningStraight-v0"


@pytest.fixture(scope="module")
def spnn_run(prior_logs: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """SPNN trained with `train` from the two priors that `train` made, with TensorBoard on."""
    work = tmp_path_factory.mktemp("zoo_spnn")
    shutil.copytree(prior_logs / "logs", work / "logs")
    run_cli(
        "train", "--algo", "spnn", "--env", PLAN_ENV, "-n", "150", "-tb", "runs", "-f", "logs",
        *TINY, cwd=work,
    )  # fmt: skip
    return work


def test_priors_are_in_the_zoo_layout(prior_logs: Path) -> None:
    for env_id in (PF_ENV, OA_ENV):
        name = env_id.replace("/", "-")
        run = prior_logs / "logs" / "dsac" / f"{name}_1"
        assert (run / f"{name}.zip").is_file()
        assert (run / name / "config.yml").is_file()


def test_spnn_trains_from_the_priors_train_made(spnn_run: Path, prior_logs: Path) -> None:
    run = spnn_run / "logs" / "spnn" / f"{RUN}_1"
    assert (run / f"{RUN}.zip").is_file()
    config = yaml.load((run / RUN / "config.yml").read_text(), Loader=yaml.UnsafeLoader)
    priors = [Path(p) for p in config["policy_kwargs"]["priors"]]
    assert [p.name for p in priors] == [
        "rov_envs-PathFollowingStraight-v0.zip",
        "rov_envs-ObstacleAvoidance-v0.zip",
    ]
    assert priors[0].parent.name == "rov_envs-PathFollowingStraight-v0_1"
    assert config["policy_kwargs"]["sonar_range"] == 25.0  # from the env
    assert config["policy_kwargs"]["net_arch"] == [32, 32]  # -params merged over the config
    assert config["policy_kwargs"]["d_th"] == 12.5  # the config's (paper) value kept
    assert "priors" not in config and "tuning" not in config
    env_kwargs = config["env_kwargs"]  # --env-kwargs merged key by key over the config's
    assert env_kwargs["max_episode_seconds"] == 3
    assert (env_kwargs["control_period"], env_kwargs["motion_obs"]) == (1.0, True)  # ours


def test_tensorboard_has_custom_scalars(spnn_run: Path) -> None:
    runs = list((spnn_run / "runs" / RUN).glob("SPNN_*"))
    assert [r.name for r in runs] == ["SPNN_1"]  # tb_log_name per algo
    events = EventAccumulator(str(runs[0]))
    events.Reload()
    tags = set(events.Tags()["scalars"])
    for tag in (
        "rollout/ep_rew_mean",  # SB3's own
        "train/critic_loss",
        "rollout/success_rate",
        "rollout/abs_cross_track_mean",
        "rollout/abs_heading_error_mean",
        "train/gate/step_share_path_following",
        "train/gate/step_share_obstacle_avoidance",
    ):
        assert tag in tags, f"{tag} missing from {sorted(tags)}"
    shares = [e.value for e in events.Scalars("train/gate/step_share_path_following")]
    assert all(0.0 <= s <= 1.0 for s in shares)
    cross = [e.value for e in events.Scalars("rollout/abs_cross_track_mean")]
    assert all(c >= 0.0 for c in cross)


def test_enjoy_records_a_video_headless(spnn_run: Path) -> None:
    out = spnn_run / "videos" / "spnn.gif"
    result = run_cli(
        "enjoy", "--algo", "spnn", "--env", PLAN_ENV, "-f", "logs", "-n", "40",
        "--record", str(out), "--fps", "10", cwd=spnn_run,
    )  # fmt: skip
    assert "Recorded 41 frames" in result.stdout
    frames = imageio.mimread(out)
    assert len(frames) == 41
    assert frames[0].ndim == 3 and frames[0].shape[2] in (3, 4)


def test_enjoy_runs_the_zoo_loop(spnn_run: Path) -> None:
    result = run_cli(
        "enjoy", "--algo", "spnn", "--env", PLAN_ENV, "-f", "logs", "-n", "40", "--no-render",
        cwd=spnn_run,
    )  # fmt: skip
    assert "Loading" in result.stdout and "Episode" in result.stdout


def test_enjoy_plays_spnn_as_the_study_does(spnn_run: Path) -> None:
    result = run_cli(
        "enjoy", "--algo", "spnn", "--env", PLAN_ENV, "-f", "logs", "-n", "40", "--no-render",
        "--switch-memory", "10", "--no-reversal", cwd=spnn_run,
    )  # fmt: skip
    assert "Loading" in result.stdout and "Episode" in result.stdout


@pytest.mark.parametrize("algo", ["pnn", "sac_multi"])
def test_pnn_and_sac_multi_train_from_the_path_following_prior(
    algo: str, prior_logs: Path, tmp_path: Path
) -> None:
    shutil.copytree(prior_logs / "logs", tmp_path / "logs")
    tiny = [a for a in TINY if not a.startswith("policy_kwargs")]  # SAC-Multi takes the prior's
    run_cli(
        "train", "--algo", algo, "--env", PLAN_ENV, "-n", "60", "-f", "logs", *tiny, cwd=tmp_path
    )
    assert (tmp_path / "logs" / algo / f"{RUN}_1" / f"{RUN}.zip").is_file()
    refused = run_cli(
        "enjoy", "--algo", algo, "--env", PLAN_ENV, "-f", "logs", "-n", "5", "--no-render",
        "--switch-memory", "10", cwd=tmp_path, check=False,
    )  # fmt: skip
    assert refused.returncode != 0
    assert "--switch-memory 10" in refused.stderr and "SPNN" in refused.stderr
