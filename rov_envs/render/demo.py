"""The main job until learning exists: a simple controller drives PlanningStraight-v0.

``python -m rov_envs.render.demo --out DIR`` runs one episode with a LOS heading PD-controller on
the
continuous (surge, yaw) action plus a crude sonar avoidance (steer away from the side where the
nearest return is, when it is close), then writes ``DIR/demo_trajectory.png`` (trajectory,
heading deviation, distance from the route) and ``DIR/demo_topdown.png`` (the env's own
``rgb_array`` render) and prints where it wrote them. The real PID baselines live in sb3_pnn.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import gymnasium as gym
import numpy as np

import rov_envs  # noqa: F401  (registers the ids)
from rov_envs.render.plotting import plot_runs, record_episode

#: Proportional gain on the heading deviation a_c (yaw command per rad).
K_HEADING = 1.2
#: Damping gain on the yaw rate r (yaw command per rad/s).
K_RATE = 0.8
#: Sonar avoidance: react to returns closer than this (m) ...
AVOID_DISTANCE = 10.0
#: ... by asking for up to this heading offset from the LOS course (rad).
AVOID_ANGLE = 0.9


def los_avoid_policy(sonar_range: float):
    """policy(obs, info) -> (surge, yaw): LOS heading PD-control plus sonar avoidance.

    yaw = -K_HEADING (a_c - a_target) - K_RATE r, where a_target = 0 (follow the LOS course)
    unless the nearest sonar return is closer than AVOID_DISTANCE: then a_target turns away from
    that return's side by up to AVOID_ANGLE, more the closer it is.
    """

    def policy(obs: dict[str, np.ndarray], info: dict) -> np.ndarray:
        a_c = float(obs["path"][0]) * np.pi
        r = float(info["velocity"][2])
        a_target = 0.0
        if "sonar" in obs:
            d = obs["sonar"] * sonar_range
            q = d.size
            k = int(np.argmin(d))
            if d[k] < AVOID_DISTANCE:
                # sectors run from the right (0) to the left (q - 1): turn away from sector k
                if k == q // 2 and q % 2 == 1:  # dead ahead: to the side with more room
                    left = 1.0 if d[k + 1 :].min() >= d[:k].min() else -1.0
                else:
                    left = 1.0 if k < q / 2 else -1.0
                a_target = left * AVOID_ANGLE * (1.0 - d[k] / AVOID_DISTANCE)
        yaw = -K_HEADING * (a_c - a_target) - K_RATE * r
        return np.array([0.7, np.clip(yaw, -1.0, 1.0)], dtype=np.float32)

    return policy


def main(argv: list[str] | None = None) -> Path:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="results/demo", help="output directory")
    parser.add_argument("--env", default="rov_envs/PlanningStraight-v0")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    env = gym.make(args.env, continuous=True, render_mode="rgb_array")
    policy = los_avoid_policy(env.unwrapped.sonar_range)
    infos = record_episode(env, policy, seed=args.seed)
    last = infos[-1]
    fig = plot_runs(
        [infos],
        labels=["LOS PD heading controller + sonar avoidance"],
        config=env.unwrapped.config,
        obstacles=env.unwrapped.obstacles,
        title=f"{args.env}: {last['end_reason']} after {last['steps']} steps",
    )
    png = out / "demo_trajectory.png"
    fig.savefig(png, dpi=120)
    top = out / "demo_topdown.png"
    import matplotlib.image

    matplotlib.image.imsave(top, env.render())
    ret = sum(i.get("r_c", 0.0) + i.get("r_v", 0.0) + i.get("r_terminal", 0.0) for i in infos[1:])
    print(
        f"episode: {last['end_reason']}, success={last.get('is_success')}, "
        f"steps={last['steps']}, return={ret:.1f}"
    )
    print(f"wrote {png.resolve()}")
    print(f"wrote {top.resolve()}")
    return png


if __name__ == "__main__":
    main()
