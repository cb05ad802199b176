"""``python -m sb3_pnn.enjoy``: watch a model trained with ``sb3_pnn.train``, or record it.

The model is found in the zoo's log layout (:func:`find_model`), the env settings it was trained
with are read from the run's ``config.yml`` and ``args.yml`` with a loader that cannot run code
(:mod:`sb3_pnn.common.safe_yaml`; rl_zoo3's own ``enjoy`` reads them with ``yaml.UnsafeLoader``
and ``eval``), the model is loaded with its algorithm's safe ``load``, and :func:`play` runs it:
it prints each episode's reward, length and success, and with ``--record PATH`` writes the frames
(``render_mode="rgb_array"``) with imageio (``.gif`` via pillow, ``.mp4`` and other video
formats via imageio-ffmpeg), atomically. No display is needed.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
from typing import Any

import numpy as np
from huggingface_sb3 import EnvironmentName

from sb3_pnn.common.atomic import check_writable, write_atomic
from sb3_pnn.common.safe_yaml import load_yaml
from sb3_pnn.zoo.errors import ZooUsageError
from sb3_pnn.zoo.runs import HasModel, latest_run_with, runs_summary


def _model_test(args: argparse.Namespace) -> tuple[HasModel, str]:
    """(whether a run folder holds the model ``enjoy`` is asked for, that model's file name)."""
    if args.load_last_checkpoint:
        pattern = "rl_model_*_steps.zip"
        return (lambda run: any(run.glob(pattern))), pattern
    if args.load_best:
        name = "best_model.zip"
    elif args.load_checkpoint is not None:
        name = f"rl_model_{args.load_checkpoint}_steps.zip"
    else:
        name = f"{EnvironmentName(args.env)}.zip"
    return (lambda run: (run / name).is_file()), name


def find_model(args: argparse.Namespace) -> tuple[str, str]:
    """(model_path, log_path) as rl_zoo3.enjoy finds them; a clear error when absent.

    With ``--exp-id 0`` (the default) the run is the latest one that holds the model: rl_zoo3
    would take the largest run number, also a folder left empty by ``-optimize`` or a failed run.
    ``args.exp_id`` is set to that run, so that rl_zoo3.enjoy loads the same model.
    """
    from rl_zoo3.utils import get_model_path

    env_name = EnvironmentName(args.env)
    algo_folder = os.path.join(args.folder, args.algo)
    has_model, model_name = _model_test(args)
    train = (
        f"train one with: python -m sb3_pnn.train --algo {args.algo} --env {args.env} "
        f"-f {args.folder}"
    )
    missing = f"no trained {args.algo} model for {args.env} in {args.folder!r}"
    if args.exp_id == 0:
        args.exp_id = latest_run_with(algo_folder, env_name, has_model)
        if args.exp_id == 0:
            expected = os.path.join(algo_folder, f"{env_name}_<N>", model_name)
            runs = runs_summary(algo_folder, env_name, has_model)
            raise ZooUsageError(f"{missing} (expected {expected}; {runs}); {train}")
    try:
        _, model_path, log_path = get_model_path(
            args.exp_id,
            args.folder,
            args.algo,
            env_name,
            args.load_best,
            args.load_checkpoint,
            args.load_last_checkpoint,
        )
    except (AssertionError, ValueError) as error:
        runs = runs_summary(algo_folder, env_name, has_model)
        raise ZooUsageError(
            f"{missing} ({error}; {runs}: pick one with --exp-id N, or leave --exp-id out for "
            f"the latest); {train}"
        ) from None
    return model_path, log_path


def _saved_dict(path: str, what: str) -> dict[str, Any]:
    """A run's saved YAML settings as a dict ({} when the file is absent)."""
    if not os.path.isfile(path):
        return {}
    try:
        content = load_yaml(path)
    except (OSError, ValueError) as error:
        raise ZooUsageError(f"cannot read the run's {what}: {error}") from None
    if not isinstance(content, dict):
        raise ZooUsageError(f"{path}: expected the run's {what} as a mapping, got {content!r:.80}")
    return content


def saved_env_kwargs(args: argparse.Namespace, log_path: str) -> dict[str, Any]:
    """The env keyword arguments the run was trained with: its config's ``env_kwargs``, replaced
    by ``args.yml``'s when the run was started with ``--env-kwargs`` (as rl_zoo3's enjoy does),
    then updated with this command's ``--env-kwargs``."""
    folder = os.path.join(log_path, EnvironmentName(args.env))
    config = _saved_dict(os.path.join(folder, "config.yml"), "hyperparameters (config.yml)")
    for key in ("normalize", "frame_stack", "env_wrapper"):
        if config.get(key):
            raise ZooUsageError(
                f"{folder}/config.yml sets {key}={config[key]!r}: sb3_pnn.enjoy plays models "
                "without observation wrappers or normalization (loading VecNormalize statistics "
                "would unpickle a file)"
            )
    env_kwargs = dict(config.get("env_kwargs") or {})
    saved_args = _saved_dict(os.path.join(folder, "args.yml"), "command-line arguments (args.yml)")
    if saved_args.get("env_kwargs") is not None:
        env_kwargs = dict(saved_args["env_kwargs"])
    if args.env_kwargs is not None:
        env_kwargs.update(args.env_kwargs)
    return env_kwargs


def write_video(frames: list[np.ndarray], path: str | Path, fps: int) -> None:
    """Write RGB frames (H, W, 3) uint8 to ``path`` with imageio, atomically."""
    import imageio.v2 as imageio

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix != ".gif":
        try:
            import imageio_ffmpeg  # noqa: F401
        except ImportError:
            raise ZooUsageError(
                f"--record {path}: writing {path.suffix or 'this format'} needs imageio-ffmpeg "
                "(pip install imageio-ffmpeg), or record a .gif"
            ) from None

    def write(tmp: Path) -> None:
        if suffix == ".gif":
            imageio.mimsave(tmp, frames, format="GIF", duration=1000.0 / fps, loop=0)
        else:
            imageio.mimsave(tmp, frames, format="FFMPEG", fps=fps, macro_block_size=1)

    write_atomic(path, write)


def check_record_path(record: str) -> None:
    """Refuse an output path that cannot be written, before any episode runs."""
    try:
        check_writable(record)
    except ValueError as error:
        raise ZooUsageError(f"--record {error}") from None


def play(args: argparse.Namespace) -> list[np.ndarray]:
    """Run the trained agent ``args.n_timesteps`` steps, printing each episode's reward, length
    and success; with ``args.record``, write the frames there and return them."""
    import gymnasium as gym
    from rl_zoo3 import ALGOS
    from stable_baselines3.common.utils import set_random_seed

    from sb3_pnn.zoo.registry import OUR_ALGOS

    if args.algo not in OUR_ALGOS:
        raise ZooUsageError(
            f"sb3_pnn.enjoy plays {', '.join(OUR_ALGOS)} models (their checkpoints load without "
            f"unpickling); for {args.algo} use python -m rl_zoo3.enjoy"
        )
    if args.fps <= 0:
        raise ZooUsageError(f"--fps must be positive, got {args.fps}")
    if args.record:
        check_record_path(args.record)
    model_path, log_path = find_model(args)
    env_kwargs = saved_env_kwargs(args, log_path)
    if args.record:
        env_kwargs["render_mode"] = "rgb_array"
    set_random_seed(args.seed)
    try:
        env = gym.make(args.env, **env_kwargs)
    except (TypeError, ValueError) as error:
        raise ZooUsageError(f"{args.env} with the run's env_kwargs {env_kwargs}: {error}") from None
    try:
        model = ALGOS[args.algo].load(model_path, env=env, device=args.device, buffer_size=1)
    except ValueError as error:
        raise ZooUsageError(f"cannot load {model_path}: {error}") from None
    if args.verbose > 0:
        print(f"Loading {model_path}")
    frames = _run(played_as_asked(model, args), env, args)
    env.close()
    if args.record:
        write_video(frames, args.record, args.fps)
        if args.verbose > 0:
            print(f"Recorded {len(frames)} frames to {args.record}")
    return frames


def played_as_asked(model: Any, args: argparse.Namespace) -> Any:
    """``model`` played through a switch memory (``--switch-memory H``) and / or without
    immediate turn reversals (``--no-reversal``), as the study plays SPNN's runs
    (:func:`sb3_pnn.evaluation.played.played_through`); the model itself otherwise."""
    from sb3_pnn.evaluation.played import played_through

    try:
        return played_through(model, args.switch_memory, args.no_reversal)
    except ValueError as error:
        raise ZooUsageError(str(error)) from None


def _run(model: Any, env: Any, args: argparse.Namespace) -> list[np.ndarray]:
    """Step ``model`` (or a policy wrapping it) on ``env`` for ``args.n_timesteps`` steps
    (frames when recording); ``episode_start`` tells a wrapper when an episode begins."""
    deterministic = not args.stochastic
    frames: list[np.ndarray] = []
    obs, _ = env.reset(seed=args.seed)
    starting = True
    if args.record:
        frame = env.render()
        if frame is None:
            raise ZooUsageError(f"{args.env} returns no rgb_array frame: it cannot be recorded")
        frames.append(np.asarray(frame))
    episode_reward, length, rewards, successes = 0.0, 0, [], []
    for _ in range(args.n_timesteps):
        action, _ = model.predict(
            obs, episode_start=np.array([starting]), deterministic=deterministic
        )
        starting = False
        obs, reward, terminated, truncated, info = env.step(action)
        if args.record:
            frames.append(np.asarray(env.render()))
        episode_reward += float(reward)
        length += 1
        if terminated or truncated:
            rewards.append(episode_reward)
            if args.verbose > 0:
                print(f"Episode Reward: {episode_reward:.2f}")
                print(f"Episode Length {length}")
            if info.get("is_success") is not None:
                successes.append(bool(info["is_success"]))
            episode_reward, length = 0.0, 0
            obs, _ = env.reset()
            starting = True
    if args.verbose > 0 and rewards:
        print(f"{len(rewards)} episodes, mean reward {np.mean(rewards):.2f}")
    elif args.verbose > 0:
        print(
            f"No episode ended within {args.n_timesteps} steps (reward so far "
            f"{episode_reward:.2f}; -n N runs longer)"
        )
    if args.verbose > 0 and successes:
        print(f"Success rate: {100 * np.mean(successes):.2f}%")
    return frames
