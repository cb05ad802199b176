"""tools.return_controller: a PID baseline steers a trained policy back to its path where the
sonar is clear and the vehicle off its path, and nowhere else (docs/ablation section 93)."""

from __future__ import annotations

import argparse
import json
from types import SimpleNamespace

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

import rov_envs  # noqa: F401  (registers the tasks)
from sb3_pnn.baselines import make_baseline
from sb3_pnn.reproduce.tools.drawn_layouts import main as drawn_main
from sb3_pnn.reproduce.tools.return_controller import (
    ColumnController,
    ReturnController,
    return_column,
)

STRAIGHT, LEFT = 2, 0  # Table 1's "Go straight" and "Turn left 2"


class Constant:
    """A stand-in policy that plays one action; records every call's episode_start."""

    def __init__(self, action: int):
        self.action, self.starts = action, []

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        self.starts.append(None if episode_start is None else list(episode_start))
        return np.full(len(obs["path"]), self.action), state

    def reset(self) -> None:
        pass


CONFIG = SimpleNamespace(sonar_range=25.0, d_L=30.0)


def test_the_controller_steers_only_in_clear_water_off_the_path() -> None:
    """Per vehicle: clear sonar and abs(g) >= 2 m -> the controller's action; an obstacle within
    ``clear`` m or a vehicle near its path -> the policy's. The controller is asked every step."""
    policy, controller = Constant(STRAIGHT), Constant(LEFT)
    played = ReturnController(policy, controller, CONFIG, clear=12.5, offset=2.0)
    obs = {
        # g / d_L: 6 m, 6 m, 1 m, 6 m off; nearest reading 25, 10, 25, 13 m
        "path": np.array([[0, 0.2], [0, -0.2], [0, 1 / 30], [0, 0.2]], np.float32),
        "sonar": np.array([[1.0, 1.0], [0.4, 1.0], [1.0, 1.0], [0.52, 1.0]], np.float32),
    }
    starts = np.array([True, False, False, False])
    actions, _ = played.predict(obs, episode_start=starts)
    assert actions.tolist() == [LEFT, STRAIGHT, STRAIGHT, LEFT]
    assert controller.starts == [starts.tolist()]  # stepped, its memory kept current
    assert (played.acted, played.steps) == (2, 4)


@pytest.mark.parametrize(
    ("clear", "offset", "message"),
    [
        (30.0, 2.0, r"clear=30.0 is not allowed: expected metres in \(0, 25\]"),
        (0.0, 2.0, r"clear=0.0 is not allowed"),
        (25.0, 30.0, r"offset=30.0 is not allowed: expected metres in \[0, 30\)"),
    ],
)
def test_bad_distances_are_refused_by_name(clear, offset, message) -> None:
    with pytest.raises(ValueError, match=message):
        ReturnController(Constant(STRAIGHT), Constant(LEFT), CONFIG, clear, offset)


def _offset_after(policy, steps: int = 60) -> float:
    """abs(g) after ``steps`` steps from 8 m beside the straight path, heading along it."""
    env = gym.make("rov_envs/PlanningStraight-v0", obstacles=[], start_noise=(0.0, 0.0))
    env.reset(seed=0)
    obs = env.unwrapped.set_pose(20.0, 8.0, 0.0)
    start = np.array([True])
    for _ in range(steps):
        batch = {k: np.asarray(v)[None] for k, v in obs.items()}
        action, _ = policy.predict(batch, episode_start=start)
        start = np.array([False])
        obs, _, terminated, truncated, info = env.step(int(np.asarray(action)[0]))
        assert not (terminated or truncated)
    return abs(float(info["cross_track"]))


def test_a_policy_that_holds_an_offset_is_brought_back() -> None:
    """ "Go straight" from 8 m off holds the offset; with the adaptive PID taking over in open
    water the vehicle ends within the 2 m at which it hands back."""
    env = gym.make("rov_envs/PlanningStraight-v0", obstacles=[])
    assert _offset_after(Constant(STRAIGHT)) > 7.0
    pid = make_baseline("adaptive_pid", env)
    returned = ReturnController(Constant(STRAIGHT), pid, env.unwrapped.config, 25.0, 2.0)
    assert _offset_after(returned) < 2.5


def test_the_replay_tools_refuse_a_baselines_run_and_a_bad_option(tmp_path, capsys) -> None:
    run = tmp_path / "runs" / "adaptive_pid-straight"
    run.mkdir(parents=True)
    (run / "manifest.json").write_text(json.dumps({"agent": "adaptive_pid"}))
    (run / "eval.json").write_text(json.dumps({"original": {"env_kwargs": {}}}))
    argv = [str(tmp_path), "--agent", "adaptive_pid", "--episodes", "1"]
    with pytest.raises(SystemExit):
        drawn_main([*argv, "--return-by", "pid"])
    assert "--return-by / --return-column need trained runs; got the baseline 'adaptive_pid'" in (
        capsys.readouterr().err
    )
    with pytest.raises(SystemExit):
        drawn_main([*argv, "--return-by", "pid", "--return-offset", "-1"])
    assert "--return-offset" in capsys.readouterr().err


def test_a_column_controller_reads_its_own_parts_greedily() -> None:
    """A path-following column observes fewer parts than a planning task: it is given only its
    own, and plays its greedy action whatever the caller asks."""

    class Column:
        observation_space = spaces.Dict(
            {"path": spaces.Box(-1, 1, (2,)), "motion": spaces.Box(-3, 3, (2,))}
        )

        def predict(self, obs, state=None, episode_start=None, deterministic=False):
            self.seen = (sorted(obs), deterministic)
            return np.zeros(len(obs["path"]), int), state

    column = Column()
    obs = {key: np.zeros((1, 2)) for key in ("path", "goal", "sonar", "motion")}
    ColumnController(column).predict(obs, deterministic=False)
    assert column.seen == (["motion", "path"], True)


def test_a_missing_return_column_stops_with_a_message(tmp_path, capsys) -> None:
    parser = argparse.ArgumentParser()
    with pytest.raises(SystemExit):
        return_column(parser, tmp_path, tmp_path / "runs" / "spnn-straight-s3")
    assert "prior-pf_straight-s3/model.zip does not exist" in capsys.readouterr().err
