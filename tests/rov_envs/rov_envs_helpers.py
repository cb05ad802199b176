"""Helpers of the rov_envs tests: stepping a batched env beside single envs."""

from __future__ import annotations

import numpy as np

KW = {"sonar_noise": 0.5, "start_noise": (0.5, 0.1), "max_episode_seconds": 20.0}


def _actions(rng: np.random.Generator, n: int, continuous: bool) -> np.ndarray:
    if continuous:
        return rng.uniform(-1, 1, size=(n, 2)).astype(np.float32)
    return rng.integers(0, 5, size=n)


def _lockstep(venv, singles: dict, steps: int, continuous: bool = False, seed: int = 0) -> int:
    """Step the batch and the single envs (vehicle i <-> singles[i]) side by side with the same
    random actions, the singles reset the step after they end (Gymnasium's next-step autoreset);
    assert every transition equal. Returns the number of episodes that ended."""
    rng = np.random.default_rng(seed)
    pending = dict.fromkeys(singles, False)
    ends = 0
    for _ in range(steps):
        acts = _actions(rng, venv.num_envs, continuous)
        vobs, vr, vterm, vtrunc, vinfo = venv.step(acts)
        for i, env in singles.items():
            if pending[i]:
                obs, info = env.reset()
                r, term, trunc = 0.0, False, False
                pending[i] = False
            else:
                obs, r, term, trunc, info = env.step(acts[i])
                if term or trunc:
                    pending[i] = True
                    ends += 1
                    assert vinfo["_is_success"][i]
                    assert vinfo["is_success"][i] == info["is_success"]
            for k in obs:
                np.testing.assert_array_equal(obs[k], vobs[k][i])
            assert (r, term, trunc) == (vr[i], vterm[i], vtrunc[i])
            np.testing.assert_array_equal(info["position"], vinfo["position"][i])
            assert info["cross_track"] == vinfo["cross_track"][i]
            np.testing.assert_array_equal(env.unwrapped.obstacles, venv.batch.vehicle_obstacles(i))
    return ends


#: The environments' arguments read as the paper's tasks (the tests of eq. 16-21 and of the
#: physics were written for them): 0.2 s steps, the state [a_c, g, sonar], eq. 18/19 as written,
#: the exact start pose, the heading rule on the LOS course.
PAPER_KW = {
    "control_period": 0.2,
    "motion_obs": False,
    "progress_weighted": False,
    "start_noise": (0.0, 0.0),
    "goal_obs": False,
    "path_obs": True,
    "heading_rule": "path",
    "goal_distance": None,
}


def paper_env(env_id: str, **kwargs):
    """``gymnasium.make(env_id)`` with :data:`PAPER_KW` under ``kwargs``."""
    import gymnasium as gym

    return gym.make(env_id, **{**PAPER_KW, **kwargs})
