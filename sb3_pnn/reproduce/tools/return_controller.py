"""A diagnosis at inference: a trained policy with a classical controller bringing it back to
its path in open water (docs/ablation section 93, beyond the paper, not a default).

Among drawn obstacles the study's learners pass the end of their path 5-30 m beside the target
(docs/ablation section 88): after a detour they keep their heading along the path at an offset.
:class:`ReturnController` asks how much of that a missing way back explains: where the sonar
reads nothing within ``clear`` metres and the vehicle is at least ``offset`` metres off its path,
it plays a controller's action; elsewhere the trained policy's. The controller is a PID baseline
(:mod:`sb3_pnn.baselines`, which steers back to the path by line-of-sight; ``--return-by``) or
a path-following source column of the same path and seed from a study folder
(``--return-column STUDY``: e.g. columns trained with ``pf_arrival_gate``, which come back from
any offset; :class:`ColumnController`). It is stepped on every step, so a PID's integrator and
rate memory stay current when it takes over. Training and the saved policy are
unchanged; what the wrapped policy would have done is what it does wherever the controller does
not act.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from sb3_pnn import DiscreteSAC
from sb3_pnn.baselines import BASELINE_NAMES, make_baseline
from sb3_pnn.common.checks import float_in
from sb3_pnn.common.policy_wrapper import PolicyWrapper

#: Default least offset (m) from the path at which the controller takes over.
DEFAULT_OFFSET = 2.0


class ColumnController:
    """A trained source column as a controller: its greedy action from the observation parts it
    was trained on (the planning tasks observe more parts than a path-following column)."""

    def __init__(self, model: Any):
        self.model = model
        self.keys = tuple(model.observation_space.spaces)

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        own = {key: obs[key] for key in self.keys}
        return self.model.predict(own, state, episode_start, deterministic=True)

    def reset(self) -> None:
        """A column keeps no memory between steps."""


class ReturnController(PolicyWrapper):
    """``policy`` played with ``controller`` steering wherever nothing is within ``clear`` m of
    the sonar and abs(g) >= ``offset`` m, per vehicle; :attr:`acted` / :attr:`steps` count
    the vehicle-steps the controller played and all of them.

    :param policy: what to play elsewhere (a loaded model or a wrapper of one)
    :param controller: a PID baseline bound to the env the policy plays in, or a
        :class:`ColumnController`
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
        steered, _ = self.controller.predict(obs, episode_start=episode_start, deterministic=True)
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
    """``--return-by NAME`` or ``--return-column STUDY``, ``--return-clear M`` and
    ``--return-offset G``."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument(
        "--return-by",
        choices=list(BASELINE_NAMES),
        default=None,
        help="replay trained runs with this PID baseline steering wherever the sonar is clear "
        "and the vehicle off its path (a diagnosis, docs/ablation section 93; default: none)",
    )
    group.add_argument(
        "--return-column",
        type=Path,
        default=None,
        metavar="STUDY",
        help="the same, with the path-following column of the same path and seed in STUDY "
        "(its runs/prior-pf_PATH-sN) steering",
    )
    parser.add_argument(
        "--return-clear",
        type=float_in("--return-clear", 0.0, 1000.0, "m"),
        default=None,
        metavar="M",
        help="with --return-by or --return-column: no sonar reading within M m (default: the "
        "sonar's range)",
    )
    parser.add_argument(
        "--return-offset",
        type=float_in("--return-offset", 0.0, 1000.0, "m"),
        default=DEFAULT_OFFSET,
        metavar="G",
        help=f"with --return-by or --return-column: abs(g) of at least G m (default "
        f"{DEFAULT_OFFSET:g})",
    )


def return_column(parser: argparse.ArgumentParser, study: Path, run: Path) -> ColumnController:
    """The path-following column in ``study`` of ``run``'s path and seed (``run`` is a
    learner's ``AGENT-PATH-sN`` folder); a missing one stops the command with a message."""
    _, path, seed = run.name.rsplit("-", 2)
    column = study / "runs" / f"prior-pf_{path}-{seed}" / "model.zip"
    if not column.is_file():
        parser.error(f"--return-column: {column} does not exist: expected a study's column run")
    return ColumnController(DiscreteSAC.load(column, device="cpu"))


def returned(
    parser: argparse.ArgumentParser,
    args: argparse.Namespace,
    policy: Any,
    env_id: str,
    env_kwargs: dict[str, Any],
    run: Path | None = None,
) -> Any:
    """``policy`` (of the run folder ``run``) through a :class:`ReturnController` as
    ``--return-by`` or ``--return-column`` asks, for the env ``env_id`` made with
    ``env_kwargs`` (itself without either); a bad value or a PID baseline's run stops the
    command with a message."""
    column = getattr(args, "return_column", None)
    if args.return_by is None and column is None:
        return policy
    if isinstance(policy, str):
        parser.error(
            f"--return-by / --return-column need trained runs; got the baseline {policy!r}"
        )
    env = gym.make(env_id, **env_kwargs)
    config = env.unwrapped.config
    clear = config.sonar_range if args.return_clear is None else args.return_clear
    try:
        if column is None:
            controller: Any = make_baseline(args.return_by, env)
        else:
            if run is None:
                parser.error("--return-column needs the run's folder")
            controller = return_column(parser, column, run)
        return ReturnController(policy, controller, config, clear, args.return_offset)
    except ValueError as error:
        parser.error(f"--return-clear / --return-offset: {error}")
    finally:
        env.close()
