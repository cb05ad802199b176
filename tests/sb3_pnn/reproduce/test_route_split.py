"""The near / clear split of a route: the parts add up to the whole and follow the distance."""

from __future__ import annotations

import numpy as np
import pytest
from reproduce_helpers import pid_baseline_run

from sb3_pnn.reproduce.tools.route_split import main, summary


def test_summary_splits_the_steps_by_the_obstacle_distance() -> None:
    steps = {
        "g": np.array([1.0, 3.0, 5.0, 7.0]),
        "ac": np.array([10.0, 20.0, 30.0, 40.0]),
        "near": np.array([True, False, True, True]),
    }
    s = summary(steps)
    assert s["share"] == 75.0
    assert (s["near_g"], s["clear_g"], s["all_g"]) == (13 / 3, 3.0, 4.0)
    assert (s["near_ac"], s["clear_ac"], s["all_ac"]) == (80 / 3, 20.0, 25.0)
    # the parts weighted by their shares give the whole
    assert 0.75 * s["near_g"] + 0.25 * s["clear_g"] == pytest.approx(s["all_g"])


def test_the_adaptive_pid_strays_near_obstacles_and_keeps_its_path_beyond(tmp_path, capsys) -> None:
    """The PID detours around the planning task's obstacles (several metres off the path within
    12.5 m of them) and keeps its path beyond them (well under a metre)."""
    pid_baseline_run(tmp_path)
    assert main([str(tmp_path), "--agent", "adaptive_pid", "--episodes", "2"]) == 0
    row = capsys.readouterr().out.splitlines()[-1]
    cells = [c.strip() for c in row.strip("|").split("|")]
    near_g = float(cells[2].split(" m")[0])
    clear_g = float(cells[3].split(" m")[0])
    assert 0 < float(cells[1].rstrip(" %")) < 100
    assert near_g > 2.0 > 1.0 > clear_g


def test_near_must_be_positive(tmp_path, capsys) -> None:
    pid_baseline_run(tmp_path)
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), "--agent", "adaptive_pid", "--near", "0"])
    assert stop.value.code == 2
    assert "expected a distance > 0 (m)" in capsys.readouterr().err
