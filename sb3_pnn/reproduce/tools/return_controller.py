"""A diagnosis at inference: a trained policy with a classical controller bringing it back to
its path in open water (docs/ablation section 93, beyond the paper, not a default).

Among drawn obstacles the study's learners pass the end of their path 5-30 m beside the target
(docs/ablation section 88): after a detour they keep their heading along the path at an offset.
:class:`ReturnController` asks how much of that a missing way back explains: where the sonar
reads nothing within ``clear`` metres and the vehicle is at least ``offset`` metres off its path,
it plays a PID baseline's action (:mod:`sb3_pnn.baselines`, which steers back to the path by
line-of-sight); elsewhere the trained policy's. The baseline is stepped on every step, so its
integrator and rate memory stay current when it takes over. Training and the saved policy are
unchanged; what the wrapped policy would have done is what it does wherever the controller does
not act.
"""

from __future__ import annotations

import argparse
from typing import Any

import gymnasium as gym
import numpy as np

from sb3_pnn.baselines import BASELINE_NAMES, make_baseline
from sb3_pnn.common.checks import float_in
from sb3_pnn.common.policy_wrapper import PolicyWrapper

#: Default least offset (m) from the path at which the controller takes over.
DEFAULT_OFFSET = 2.0


class ReturnController(PolicyWrapper):
    """``policy`` played with ``controller`` steering wherever nothing is within ``clear`` m of
    the sonar and abs(g) >= ``offset`` m, per vehicle; :attr:`acted` / :attr:`steps` count
    the vehicle-steps the controller played and all of them.

    :param policy: what to play elsewhere (a loaded model or a wrapper of one)
    :param controller: a PID baseline bound to the env the policy plays in
    :param config: that env's ``rov_envs.sim.config.EnvConfig`` (sonar range, d_L)
    :param clear: metres within which any sonar reading keeps the policy in control (0, range]
    :param offset: least abs(g) in metres at which the controller takes over (>= 0)
    """

    def __init__(self, policy: Any, controller: Any, config: Any, clear: float, offset: float):
        sonar_range, d_l = float(config.sonar_range), float(config.d_L)
        if not 0 < clear <= sonar_range:
            raise ValueError(
                f"clear={clear!r} is not allowed: expected metres in (0, {sonar_range:g}] (the "
                "sonar's range)"
            )
        if not 0 <= offset < d_l:
            raise ValueError(
                f"offset={offset!r} is not allowed: expected metres in [0, {d_l:g}) (d_L)"
            )
        super().__init__(policy)
        self.controller = controller
        # the observation's sonar part is reading / range, its path part [a_c, g / d_L]
        self.clear_fraction = clear / sonar_range
        self.offset_fraction = offset / d_l
        self.acted = 0
        self.steps = 0

    def forget(self) -> None:
        self.controller.reset()

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        action, state = self.wrapped.predict(obs, state, episode_start, deterministic)
        steered, _ = self.controller.predict(obs, episode_start=episode_start)
        sonar = np.atleast_2d(np.asarray(obs["sonar"]))
        offset = np.abs(np.atleast_2d(np.asarray(obs["path"]))[:, 1])
        takes_over = (sonar.min(axis=1) >= self.clear_fraction) & (offset >= self.offset_fraction)
        self.steps += len(takes_over)
        self.acted += int(takes_over.sum())
        if not takes_over.any():
            return action, state
        played = np.atleast_1d(np.array(action)).copy()
        played[takes_over] = np.atleast_1d(np.asarray(steered))[takes_over]
        return (played if np.ndim(action) else played[0]), state


def add_return_options(parser: argparse.ArgumentParser) -> None:
    """``--return-by NAME``, ``--return-clear M`` and ``--return-offset G``."""
    parser.add_argument(
        "--return-by",
        choices=list(BASELINE_NAMES),
        default=None,
        help="replay trained runs with this PID baseline steering wherever the sonar is clear "
        "and the vehicle off its path (a diagnosis, docs/ablation section 93; default: none)",
    )
    parser.add_argument(
        "--return-clear",
        type=float_in("--return-clear", 0.0, 1000.0, "m"),
        default=None,
        metavar="M",
        help="with --return-by: no sonar reading within M m (default: the sonar's range)",
    )
    parser.add_argument(
        "--return-offset",
        type=float_in("--return-offset", 0.0, 1000.0, "m"),
        default=DEFAULT_OFFSET,
        metavar="G",
        help=f"with --return-by: abs(g) of at least G m (default {DEFAULT_OFFSET:g})",
    )


def returned(
    parser: argparse.ArgumentParser,
    args: argparse.Namespace,
    policy: Any,
    env_id: str,
    env_kwargs: dict[str, Any],
) -> Any:
    """``policy`` through a :class:`ReturnController` as ``--return-by`` asks, for the env
    ``env_id`` made with ``env_kwargs`` (itself without ``--return-by``); a bad value or a PID
    baseline's run stops the command with a message."""
    if args.return_by is None:
        return policy
    if isinstance(policy, str):
        parser.error(f"--return-by needs trained runs; got the baseline {policy!r}")
    env = gym.make(env_id, **env_kwargs)
    config = env.unwrapped.config
    clear = config.sonar_range if args.return_clear is None else args.return_clear
    try:
        return ReturnController(
            policy, make_baseline(args.return_by, env), config, clear, args.return_offset
        )
    except ValueError as error:
        parser.error(f"--return-clear / --return-offset: {error}")
    finally:
        env.close()
