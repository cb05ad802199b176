"""The parallel-offset diagnostic: where a policy is put, and that a path follower comes back."""

from __future__ import annotations

import json
import math

import gymnasium as gym
import pytest

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn.reproduce.tools.offset_return import main, start_pose


@pytest.mark.parametrize(
    ("env_id", "path"),
    [("rov_envs/PathFollowingStraight-v0", "straight"), ("rov_envs/PathFollowingSine-v0", "sine")],
)
@pytest.mark.parametrize("offset", [3.0, 9.0])
def test_start_pose_is_offset_metres_off_heading_along_the_path(env_id, path, offset) -> None:
    """The guidance reads g = offset (to the left) and a_c = atan(g / Delta): parallel to the
    path, which the LOS course would leave by turning back."""
    env = gym.make(env_id, start_noise=(0.0, 0.0))
    env.reset(seed=0)
    obs = env.unwrapped.set_pose(*start_pose(env, path, offset))
    g = float(obs["path"][1]) * env.unwrapped.config.d_L
    a_c = float(obs["path"][0]) * math.pi
    assert abs(g) == pytest.approx(offset, abs=1e-4)
    assert abs(a_c) == pytest.approx(math.atan(offset / 5.0), abs=1e-4)


def _pid_run(study, path: str) -> None:
    run = study / "runs" / f"adaptive_pid-{path}"
    run.mkdir(parents=True)
    (run / "manifest.json").write_text(json.dumps({"agent": "adaptive_pid"}))
    env = "PathFollowingStraight-v0" if path == "straight" else "PathFollowingSine-v0"
    tasks = {"path_following": {"env_id": f"rov_envs/{env}", "env_kwargs": {}}}
    (run / "eval.json").write_text(json.dumps(tasks))


@pytest.mark.parametrize("path", ["straight", "sine"])
def test_the_adaptive_pid_comes_back_from_every_offset(tmp_path, capsys, path) -> None:
    _pid_run(tmp_path, path)
    argv = [str(tmp_path), "--agent", "adaptive_pid", "--path", path, "--offsets", "3", "9"]
    assert main(argv) == 0
    row = capsys.readouterr().out.splitlines()[-1]
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[0] == "0"
    for cell, offset in zip(cells[1:], (3.0, 9.0), strict=True):
        after_half, after_all = (float(v) for v in cell.split(" / "))
        assert after_all < 1.0 < offset  # back on the path, not holding the offset


def test_offsets_must_be_positive(tmp_path, capsys) -> None:
    _pid_run(tmp_path, "straight")
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), "--agent", "adaptive_pid", "--offsets", "3", "-2"])
    assert stop.value.code == 2
    assert "expected distances > 0 (m)" in capsys.readouterr().err
