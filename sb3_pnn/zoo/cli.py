"""``python -m sb3_pnn.train`` and ``python -m sb3_pnn.enjoy``: rl-zoo commands with our algos.

``train`` takes every flag of ``python -m rl_zoo3.train`` and these of ours; ``enjoy`` takes
rl_zoo3.enjoy's flags that apply to our models (``--help`` lists them) and these of ours:

train:
  --setup {ours,paper}        which shipped hyperparameter files: ours (default) or the paper's
                              read literally (zoo_configs/paper/); --conf-file names any other
  --priors A.zip [B.zip]      prior checkpoints, replacing the config's ``priors:`` (same order)
  --tune NAME=LOW:HIGH        tuning bounds (repeatable), e.g. ``--tune d_th=5:20``;
                              NAME=VALUE fixes it, NAME=none leaves it untuned
  --tune-sac                  also tune the usual SAC settings (learning rate, gamma, ...)
  --heartbeat-interval S      heartbeat of a database ``--storage`` (default 60 s)
  --grace-period S            a RUNNING trial without heartbeat for S seconds is marked FAIL
                              (default 2 x heartbeat interval)

enjoy:
  --record PATH               record the agent headless (render_mode="rgb_array") to a video
                              (.mp4 needs imageio-ffmpeg; .gif needs only pillow)
  --fps N                     frames per second of the recording (default 20)
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import os
import re
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager

import gymnasium as gym

from sb3_pnn.common.atomic import check_writable_folder
from sb3_pnn.common.checks import did_you_mean
from sb3_pnn.zoo.errors import ZooUsageError

TRAIN_PROG = "python -m sb3_pnn.train"
ENJOY_PROG = "python -m sb3_pnn.enjoy"


def _our_train_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=TRAIN_PROG, add_help=False)
    ours = parser.add_argument_group("sb3_pnn options (besides rl_zoo3's, listed below)")
    ours.add_argument(
        "--setup",
        default=None,
        metavar="{ours,paper}",
        help="the shipped hyperparameter files to use: ours (default) or the paper's read "
        "literally (zoo_configs/paper/)",
    )
    ours.add_argument("--priors", nargs="+", metavar="ZIP", help="prior checkpoints, in order")
    ours.add_argument(
        "--tune",
        action="append",
        metavar="NAME=LOW:HIGH",
        help="-optimize bounds of d_th, sigma, own_weight, temperature (or a SAC setting); "
        "NAME=VALUE fixes it, NAME=none leaves it untuned (repeatable)",
    )
    ours.add_argument("--tune-sac", action="store_true", help="also tune the SAC settings")
    ours.add_argument(
        "--heartbeat-interval",
        type=int,
        default=60,
        metavar="S",
        help="heartbeat of trials in a database --storage (default 60 s)",
    )
    ours.add_argument(
        "--grace-period",
        type=int,
        default=None,
        metavar="S",
        help="a RUNNING trial silent for S seconds is marked FAIL (default 2 x heartbeat)",
    )
    return parser


def _common_parser() -> argparse.ArgumentParser:
    """The zoo flags we check before the zoo sees them."""
    parser = argparse.ArgumentParser(add_help=False)
    parser.add_argument("--algo")
    parser.add_argument("--env")
    parser.add_argument("-conf", "--conf-file")
    parser.add_argument("--gym-packages", nargs="+", default=[])
    parser.add_argument("-n", "--n-timesteps", type=int, default=None)
    parser.add_argument("-f", "--log-folder", default="logs")
    parser.add_argument("-tb", "--tensorboard-log", default="")
    parser.add_argument("-i", "--trained-agent", default="")
    for flag in ("-params", "--hyperparams", "--env-kwargs", "--eval-env-kwargs"):
        parser.add_argument(flag, nargs="+", default=None, dest=flag.lstrip("-").replace("-", "_"))
    return parser


def check_train_inputs(common: argparse.Namespace) -> None:
    """What rl_zoo3 would only fail on with a traceback (after building the env): values of
    ``-params`` / ``--env-kwargs`` that are not Python expressions, a ``-i`` model that is not
    there, log folders that cannot be written."""
    import rl_zoo3.utils

    for flag, values in (
        ("-params", common.params or common.hyperparams),
        ("--env-kwargs", common.env_kwargs),
        ("--eval-env-kwargs", common.eval_env_kwargs),
    ):
        for item in values or []:
            key, sep, text = item.partition(":")
            if not sep or not key:
                raise ZooUsageError(f"{flag} {item!r}: expected key:value")
            try:
                # the zoo's StoreDict evaluates it the same way (the user's own input)
                eval(text, dict(vars(rl_zoo3.utils)))  # noqa: S307
            except Exception as error:  # noqa: BLE001 - any failure is a bad value
                raise ZooUsageError(
                    f"{flag} {item!r}: the value {text!r} is not a Python expression "
                    f"({type(error).__name__}: {error}); quote strings, e.g. {key}:\"'text'\""
                ) from None
    agent = common.trained_agent
    if agent and not (agent.endswith(".zip") and os.path.isfile(agent)):
        raise ZooUsageError(f"-i/--trained-agent {agent!r}: expected the path of a model .zip")
    for flag, folder in (("-f/--log-folder", common.log_folder), ("-tb", common.tensorboard_log)):
        if folder:
            try:
                check_writable_folder(folder)
            except ValueError as error:
                raise ZooUsageError(f"{flag} {error}") from None


def check_steps(n_timesteps: int | None, default: str) -> None:
    """Refuse ``-n/--n-timesteps`` below 1 (the zoo would run ``default`` or nothing, silently)."""
    if n_timesteps is not None and n_timesteps < 1:
        raise ZooUsageError(
            f"-n/--n-timesteps {n_timesteps}: expected a positive number of environment steps "
            f"(leave -n out for {default})"
        )


def check_algo_and_env(algo: str | None, env_id: str | None, gym_packages: list[str]) -> None:
    """Refuse a missing or unknown ``--algo`` / ``--env`` with one clear line."""
    import rl_zoo3

    from sb3_pnn.zoo.registry import OUR_ALGOS

    ours = ", ".join(OUR_ALGOS)
    if not algo:
        raise ZooUsageError(f"--algo is required: one of {ours} (or an rl_zoo3 algo)")
    if algo not in rl_zoo3.ALGOS:
        others = ", ".join(a for a in rl_zoo3.ALGOS if a not in OUR_ALGOS)
        raise ZooUsageError(
            f"unknown algo {algo!r}: {did_you_mean(algo, rl_zoo3.ALGOS)}expected one of {ours} "
            f"(rl_zoo3's: {others})"
        )
    for module in gym_packages:
        try:
            importlib.import_module(module)
        except ImportError as error:
            raise ZooUsageError(f"--gym-packages {module!r} cannot be imported: {error}") from None
    if not env_id:
        raise ZooUsageError("--env is required, e.g. --env rov_envs/PlanningStraight-v0")
    registered = list(gym.envs.registry.keys())
    if env_id not in gym.envs.registry:
        ours_envs = sorted(e for e in registered if e.startswith("rov_envs/"))
        hint = did_you_mean(env_id, registered)
        raise ZooUsageError(
            f"unknown env id {env_id!r}: {hint}rov_envs tasks: {', '.join(ours_envs) or 'none'}"
        )


@contextmanager
def _argv(argv: list[str]) -> Iterator[None]:
    saved = sys.argv
    sys.argv = argv
    try:
        yield
    finally:
        sys.argv = saved


@contextmanager
def _zoo_manager(manager: type) -> Iterator[None]:
    import rl_zoo3.train

    saved = rl_zoo3.train.ExperimentManager
    rl_zoo3.train.ExperimentManager = manager
    try:
        yield
    finally:
        rl_zoo3.train.ExperimentManager = saved


def print_help(ours: argparse.ArgumentParser, zoo_command: Callable[[], None], prog: str) -> None:
    """One help text: rl_zoo3's usage line, then our options, then rl_zoo3's options."""
    captured = io.StringIO()
    with _argv([prog, "--help"]), contextlib.redirect_stdout(captured):
        try:
            zoo_command()  # prints the zoo's help and exits
        except SystemExit:
            pass
    usage, _, zoo_options = captured.getvalue().partition("\n\n")
    # our flags, [--priors ZIP [ZIP ...]] ..., appended to the zoo's usage in its layout
    flags = re.findall(r"\[(?:[^\[\]]|\[[^\]]*\])*\]", ours.format_usage().split(prog, 1)[1])
    indent = " " * len(f"usage: {prog} ")
    lines = usage.splitlines()
    for flag in (" ".join(flag.split()) for flag in flags):
        if len(lines[-1]) + 1 + len(flag) <= 80:
            lines[-1] += f" {flag}"
        else:
            lines.append(indent + flag)
    ours.usage = argparse.SUPPRESS
    print("\n".join(lines), ours.format_help().strip("\n"), zoo_options.rstrip("\n"), sep="\n\n")


def train_main(argv: list[str] | None = None) -> None:
    """Parse our flags, check the input, then run ``rl_zoo3.train.train()`` with our manager."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = _our_train_parser()
    ours, rest = parser.parse_known_args(argv)
    import rl_zoo3.train

    from sb3_pnn.zoo.configs import default_config_path
    from sb3_pnn.zoo.experiment import PNNExperimentManager, ZooOptions
    from sb3_pnn.zoo.registry import OUR_ALGOS, register_algos
    from sb3_pnn.zoo.tuning import parse_cli_bounds

    register_algos()
    if "-h" in rest or "--help" in rest:
        print_help(parser, rl_zoo3.train.train, TRAIN_PROG)
        return
    common, _ = _common_parser().parse_known_args(rest)
    check_algo_and_env(common.algo, common.env, common.gym_packages)
    check_steps(common.n_timesteps, "the config's n_timesteps")
    check_train_inputs(common)
    if ours.setup is not None and common.conf_file is not None:
        raise ZooUsageError(
            f"--setup {ours.setup} and --conf-file {common.conf_file} both pick the "
            "hyperparameter file: give one of them"
        )
    if ours.setup is not None and common.algo not in OUR_ALGOS:
        raise ZooUsageError(
            f"--setup applies to {', '.join(OUR_ALGOS)}; {common.algo} reads rl_zoo3's files"
        )
    if common.conf_file is None and common.algo in OUR_ALGOS:
        rest += ["--conf-file", str(default_config_path(common.algo, ours.setup or "ours"))]
    options = ZooOptions(
        priors=ours.priors,
        tune=parse_cli_bounds(ours.tune),
        tune_sac=ours.tune_sac,
        heartbeat_interval=ours.heartbeat_interval,
        grace_period=ours.grace_period,
    )
    manager = type("TrainExperimentManager", (PNNExperimentManager,), {"options": options})
    with _argv([TRAIN_PROG, *with_defaults(rest)]), _zoo_manager(manager):
        rl_zoo3.train.train()


#: Torch threads of ``train`` and ``enjoy`` unless ``--num-threads`` says otherwise (rl_zoo3's
#: own default, -1, lets torch take every core: on 2 cores the small networks here then run
#: several times slower than on one).
DEFAULT_NUM_THREADS = 1
#: Torch device of ``train`` and ``enjoy`` unless ``--device`` says otherwise (rl_zoo3's own
#: default, auto, takes a GPU where there is one: the study's networks then train 2.2-2.4x
#: slower per update than on one CPU thread, ``bench/gpu_vs_cpu.py``).
DEFAULT_DEVICE = "cpu"


def with_defaults(argv: list[str]) -> list[str]:
    """``argv`` with ``--num-threads 1`` and ``--device cpu`` added where it names none."""
    out = list(argv)
    for flag, value in (("--num-threads", str(DEFAULT_NUM_THREADS)), ("--device", DEFAULT_DEVICE)):
        if not any(a == flag or a.startswith(f"{flag}=") for a in argv):
            out += [flag, value]
    return out


def _enjoy_parser() -> argparse.ArgumentParser:
    """The flags of ``enjoy``: rl_zoo3.enjoy's that apply to our models, plus ours."""
    from rl_zoo3.utils import StoreDict

    parser = argparse.ArgumentParser(
        prog=ENJOY_PROG,
        description="Watch a model trained with python -m sb3_pnn.train (episode rewards, "
        "lengths and successes), or record a video of it. Run folders are read without "
        "running code from them.",
    )
    ours = parser.add_argument_group("sb3_pnn options")
    ours.add_argument("--record", metavar="PATH", help="record a video headless to PATH")
    ours.add_argument("--fps", type=int, default=20, help="frames per second of the recording")
    ours.add_argument(
        "--switch-memory",
        type=float,
        default=None,
        metavar="H",
        help="play an SPNN with a switch memory: the avoidance column keeps control until the "
        "nearest reading is beyond d_th + H metres (as the study plays SPNN on the line)",
    )
    ours.add_argument(
        "--no-reversal",
        action="store_true",
        help="play Go straight where the policy's turn reverses the step before's (as the "
        "study plays SPNN on the sinusoid)",
    )
    zoo = parser.add_argument_group("rl_zoo3.enjoy's options")
    zoo.add_argument("--env", help="environment id")
    zoo.add_argument("--algo", help="dsac, sac_multi, pnn or spnn")
    zoo.add_argument("-f", "--folder", default="logs", help="log folder (default logs)")
    zoo.add_argument("-n", "--n-timesteps", type=int, default=1000, help="steps to run")
    zoo.add_argument("--exp-id", type=int, default=0, help="run N (default: the latest)")
    zoo.add_argument("--load-best", action="store_true", help="load best_model.zip")
    zoo.add_argument("--load-checkpoint", type=int, help="load rl_model_<N>_steps.zip")
    zoo.add_argument("--load-last-checkpoint", action="store_true", help="the last checkpoint")
    zoo.add_argument("--deterministic", action="store_true", help="greedy actions (default)")
    zoo.add_argument("--stochastic", action="store_true", help="sample actions")
    zoo.add_argument("--seed", type=int, default=0, help="seed of the env and the model")
    zoo.add_argument(
        "--device", default=DEFAULT_DEVICE, help=f"torch device (default {DEFAULT_DEVICE})"
    )
    zoo.add_argument("--verbose", type=int, default=1, help="0: quiet")
    zoo.add_argument("--no-render", action="store_true", help="do not open a window")
    zoo.add_argument("--gym-packages", nargs="+", default=[], help="modules to import first")
    zoo.add_argument("--env-kwargs", nargs="+", action=StoreDict, help="key:value env arguments")
    zoo.add_argument(
        "--num-threads", type=int, default=DEFAULT_NUM_THREADS, help="torch threads (default 1)"
    )
    return parser


def enjoy_main(argv: list[str] | None = None) -> None:
    """Watch a trained model (episode rewards and successes), or record it with ``--record``;
    never through rl_zoo3's enjoy, which reads a run folder's files with ``yaml.UnsafeLoader``
    and ``eval`` (:mod:`sb3_pnn.zoo.play`)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = _enjoy_parser()
    wants_help = "-h" in argv or "--help" in argv
    from sb3_pnn.zoo.registry import register_algos

    register_algos()
    if wants_help:
        parser.print_help()
        return
    args, rest = parser.parse_known_args(argv)
    check_algo_and_env(args.algo, args.env, args.gym_packages)
    check_steps(args.n_timesteps, f"{parser.get_default('n_timesteps')} steps")
    if args.record is None and not args.no_render:
        modes = gym.make(args.env).metadata.get("render_modes", [])
        if "human" not in modes:
            raise ZooUsageError(
                f"{args.env} has no window to render to (render modes: {modes}): pass "
                "--record PATH.mp4 (or .gif) to record a video, or --no-render"
            )
    if rest:
        raise ZooUsageError(f"{ENJOY_PROG} does not support {' '.join(rest)}")
    threads = None if args.num_threads == -1 else args.num_threads
    if threads is not None and threads < 1:
        raise ZooUsageError(f"--num-threads {threads}: expected an int >= 1, or -1")
    if threads is not None:
        import torch

        torch.set_num_threads(threads)
        if args.verbose > 0:
            print(f"Setting torch.num_threads to {threads}")
    from sb3_pnn.zoo.play import play

    play(args)
