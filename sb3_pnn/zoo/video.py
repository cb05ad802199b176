"""Headless recording for ``python -m sb3_pnn.enjoy --record PATH``.

The env is built with ``render_mode="rgb_array"`` through rl_zoo3's ``create_test_env`` (so the
saved ``config.yml``/``args.yml`` env settings and wrappers apply), the model is loaded with the
zoo's algo class, and the frames are written with imageio (``.gif`` via pillow, ``.mp4`` and
other video formats via imageio-ffmpeg). No display is needed.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from huggingface_sb3 import EnvironmentName

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


def _env_kwargs(args: argparse.Namespace, log_path: str, hyperparams: dict[str, Any]) -> dict:
    env_kwargs: dict[str, Any] = dict(hyperparams.pop("env_kwargs", None) or {})
    args_path = os.path.join(log_path, EnvironmentName(args.env), "args.yml")
    if os.path.isfile(args_path):
        with open(args_path) as handle:
            loaded = yaml.load(handle, Loader=yaml.UnsafeLoader)  # the zoo's own file
        if loaded.get("env_kwargs") is not None:
            env_kwargs.update(loaded["env_kwargs"])
    if args.env_kwargs is not None:
        env_kwargs.update(args.env_kwargs)
    env_kwargs["render_mode"] = "rgb_array"
    return env_kwargs


def write_video(frames: list[np.ndarray], path: str | Path, fps: int) -> None:
    """Write RGB frames (H, W, 3) uint8 to ``path`` with imageio."""
    import imageio.v2 as imageio

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.suffix.lower() == ".gif":
        imageio.mimsave(path, frames, duration=1000.0 / fps, loop=0)
        return
    try:
        import imageio_ffmpeg  # noqa: F401
    except ImportError:
        raise ZooUsageError(
            f"--record {path}: writing {path.suffix or 'this format'} needs imageio-ffmpeg "
            "(pip install imageio-ffmpeg), or record a .gif"
        ) from None
    imageio.mimsave(path, frames, fps=fps, macro_block_size=1)


def record(args: argparse.Namespace) -> list[np.ndarray]:
    """Run the trained agent ``args.n_timesteps`` steps; write the frames to ``args.record``."""
    from rl_zoo3 import ALGOS, create_test_env, get_saved_hyperparams
    from stable_baselines3.common.off_policy_algorithm import OffPolicyAlgorithm
    from stable_baselines3.common.utils import set_random_seed

    if args.fps <= 0:
        raise ZooUsageError(f"--fps must be positive, got {args.fps}")
    model_path, log_path = find_model(args)
    set_random_seed(args.seed)
    stats_path = os.path.join(log_path, EnvironmentName(args.env))
    hyperparams, maybe_stats_path = get_saved_hyperparams(stats_path, test_mode=True)
    env_kwargs = _env_kwargs(args, log_path, hyperparams)
    env = create_test_env(
        args.env,
        n_envs=1,
        stats_path=maybe_stats_path,
        seed=args.seed,
        log_dir=None,
        should_render=False,
        hyperparams=hyperparams,
        env_kwargs=env_kwargs,
    )
    algo_class = ALGOS[args.algo]
    load_kwargs: dict[str, Any] = {"seed": args.seed}
    if issubclass(algo_class, OffPolicyAlgorithm):
        load_kwargs["buffer_size"] = 1  # no replay memory needed to watch
    custom_objects = {"learning_rate": 0.0, "lr_schedule": lambda _: 0.0}
    model = algo_class.load(
        model_path, custom_objects=custom_objects, device=args.device, **load_kwargs
    )
    deterministic = not args.stochastic
    frames: list[np.ndarray] = []
    obs = env.reset()
    frame = env.render()
    if frame is None:
        raise ZooUsageError(f"{args.env} returns no rgb_array frame: it cannot be recorded")
    frames.append(np.asarray(frame))
    episode_reward, rewards, successes = 0.0, [], []
    for _ in range(args.n_timesteps):
        action, _ = model.predict(obs, deterministic=deterministic)
        obs, reward, done, infos = env.step(action)
        frames.append(np.asarray(env.render()))
        episode_reward += float(reward[0])
        if done[0]:
            rewards.append(episode_reward)
            episode_reward = 0.0
            if infos[0].get("is_success") is not None:
                successes.append(bool(infos[0]["is_success"]))
    env.close()
    write_video(frames, args.record, args.fps)
    if args.verbose > 0:
        print(f"Loaded {model_path}")
        print(f"Recorded {len(frames)} frames to {args.record}")
        if rewards:
            print(f"{len(rewards)} episodes, mean reward {np.mean(rewards):.2f}")
        if successes:
            print(f"Success rate: {100 * np.mean(successes):.2f}%")
    return frames
