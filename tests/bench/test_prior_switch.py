"""bench/prior_switch.py's switch: eq. 15's memoryless selector, and with hysteresis a switch
that keeps the avoidance prior until the nearest obstacle is beyond d_th + h."""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np
from gymnasium import spaces

PriorSwitch = runpy.run_path(str(Path(__file__).parents[2] / "bench" / "prior_switch.py"))[
    "PriorSwitch"
]


class Constant:
    """A stand-in column that always plays one action (reads only its own keys)."""

    def __init__(self, action: int):
        self.action = action
        self.observation_space = spaces.Dict({"sonar": spaces.Box(0, 1, (3,))})

    def predict(self, obs, deterministic=True):
        return np.full(len(obs["sonar"]), self.action), None


def _play(switch, nearest_m, starts):
    actions = []
    for d, start in zip(nearest_m, starts):
        obs = {"sonar": np.full((1, 3), d / 25.0, np.float32)}
        action, _ = switch.predict(obs, episode_start=np.array([start]))
        actions.append(int(action[0]))
    return actions


def test_memoryless_switch_is_eq_15_selector() -> None:
    switch = PriorSwitch(Constant(2), Constant(0), d_th=12.5, sonar_range=25.0)
    nearest = [20.0, 12.0, 14.0, 12.5, 13.0]
    assert _play(switch, nearest, [True, False, False, False, False]) == [2, 0, 2, 0, 2]
    assert switch.handovers == 4


def test_hysteresis_keeps_avoidance_until_beyond_d_th_plus_h() -> None:
    switch = PriorSwitch(Constant(2), Constant(0), d_th=12.5, sonar_range=25.0, hysteresis=5.0)
    nearest = [20.0, 12.0, 14.0, 17.5, 17.6, 14.0, 10.0]
    assert _play(switch, nearest, [True] + [False] * 6) == [2, 0, 0, 0, 2, 2, 0]
    assert switch.handovers == 3


def test_a_new_episode_forgets_the_switch() -> None:
    switch = PriorSwitch(Constant(2), Constant(0), d_th=12.5, sonar_range=25.0, hysteresis=5.0)
    assert _play(switch, [10.0, 14.0, 14.0], [True, False, True]) == [0, 0, 2]
    assert switch.handovers == 0
