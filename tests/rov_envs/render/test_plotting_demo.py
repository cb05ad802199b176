"""Plotting helper and the main-job demo."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from rov_envs_helpers import paper_env

from rov_envs.render import demo
from rov_envs.render.plotting import plot_runs, record_episode, run_arrays


def test_plot_runs_from_infos_and_arrays() -> None:
    env = paper_env("rov_envs/PlanningSine-v0", max_episode_seconds=10.0)
    infos = record_episode(env, lambda obs, info: 2, seed=0)
    assert len(infos) == 51
    arr = run_arrays(infos, dt=env.unwrapped.config.dt)
    assert arr["position"].shape == (51, 2) and arr["time"][-1] == 10.0
    fig = plot_runs(
        [infos, arr],
        labels=["a", "b"],
        config=env.unwrapped.config,
        obstacles=env.unwrapped.obstacles,
    )
    assert isinstance(fig, Figure) and len(fig.axes) == 3
    np.testing.assert_array_equal(fig.axes[0].lines[-1].get_xdata(), arr["position"][:, 0])


def test_demo_writes_picture(tmp_path, capsys) -> None:
    png = demo.main(["--out", str(tmp_path)])
    assert png.exists() and png.stat().st_size > 10000
    assert (tmp_path / "demo_topdown.png").exists()
    out = capsys.readouterr().out
    assert str(png.resolve()) in out
    assert "success=True" in out
