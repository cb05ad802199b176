"""Replay buffers saved without pickle: numpy arrays in an ``.npz`` archive plus JSON metadata.

SB3's ``save_replay_buffer`` pickles the whole buffer object, and unpickling runs arbitrary code.
:func:`save_buffer` writes instead, with ``np.savez``, the filled rows of every array
(``observations``, ``next_observations``, ``actions``, ``rewards``, ``dones``, ``timeouts``;
``Dict`` observations one array per key, ``observations.<i>`` for the i-th key) and a JSON string
``__meta__`` (format version, buffer class by allowlisted name, buffer size, ``pos``, ``full``,
``n_envs``, spaces, ``optimize_memory_usage``, ``handle_timeout_termination``, n-step settings).
:func:`load_buffer` reads it with ``np.load(allow_pickle=False)`` and refuses anything else
(e.g. an SB3 pickle) with :class:`~sb3_pnn.safe_io.checkpoint.UnsafeCheckpointError`.

File names follow SB3 (a path without suffix gets ``.pkl``) so that SB3's
``CheckpointCallback`` and the zoo's ``replay_buffer.pkl`` keep working; the content is an
``.npz`` (zip) archive whatever the name.
"""

from __future__ import annotations

import io
import json
import os
import pathlib
import zipfile
from typing import Any

import numpy as np
import torch as th
from stable_baselines3.common.buffers import NStepReplayBuffer, ReplayBuffer

from sb3_pnn.common.buffers import DictNStepReplayBuffer
from sb3_pnn.safe_io.checkpoint import UnsafeCheckpointError
from sb3_pnn.safe_io.files import read_file_bytes, write_checkpoint_bytes
from sb3_pnn.safe_io.json_codec import safe_class, safe_class_name
from sb3_pnn.safe_io.limits import (
    MAX_BUFFER_BYTES,
    MAX_JSON_BYTES,
    ZIP_DAMAGE,
    check_number,
    member_sizes,
    parse_json,
)
from sb3_pnn.safe_io.spaces_codec import space_from_json, space_to_json

#: Buffers that sample n-step returns: their n and gamma are stored with them.
N_STEP_BUFFERS = (NStepReplayBuffer, DictNStepReplayBuffer)

FORMAT = "sb3_pnn.replay_buffer"
VERSION = 1
ARRAYS = ("observations", "next_observations", "actions", "rewards", "dones", "timeouts")


def _stored_rows(buffer: ReplayBuffer) -> int:
    # With optimize_memory_usage the next observation of the last transition sits at row pos
    return buffer.buffer_size if buffer.full else min(buffer.pos + 1, buffer.buffer_size)


def _arrays(buffer: ReplayBuffer, keys: list[str] | None) -> dict[str, np.ndarray]:
    out = {}
    for name in ARRAYS:
        value = getattr(buffer, name, None)
        if value is None:
            continue
        if isinstance(value, dict):
            assert keys is not None
            for i, key in enumerate(keys):
                out[f"{name}.{i}"] = value[key]
        else:
            out[name] = value
    return out


def save_buffer(buffer: ReplayBuffer, path: str | pathlib.Path | io.BufferedIOBase) -> None:
    """Write ``buffer`` to ``path`` without pickle (see the module docstring)."""
    if not isinstance(buffer, ReplayBuffer):
        raise ValueError(f"expected an SB3 ReplayBuffer, got {type(buffer).__name__}")
    cls_name = safe_class_name(type(buffer))
    if cls_name is None:
        raise ValueError(
            f"cannot save replay buffer class {type(buffer).__name__} without pickle: expected "
            "ReplayBuffer, DictReplayBuffer, NStepReplayBuffer or DictNStepReplayBuffer (or a "
            "class registered with "
            "sb3_pnn.safe_io.register_safe_class)"
        )
    keys = list(buffer.observations) if isinstance(buffer.observations, dict) else None
    meta: dict[str, Any] = {
        "format": FORMAT,
        "version": VERSION,
        "class": cls_name,
        "buffer_size": int(buffer.buffer_size),  # per environment
        "n_envs": int(buffer.n_envs),
        "pos": int(buffer.pos),
        "full": bool(buffer.full),
        "stored_rows": _stored_rows(buffer),
        "optimize_memory_usage": bool(buffer.optimize_memory_usage),
        "handle_timeout_termination": bool(buffer.handle_timeout_termination),
        "observation_space": space_to_json(buffer.observation_space),
        "action_space": space_to_json(buffer.action_space),
        "obs_keys": keys,
    }
    if isinstance(buffer, N_STEP_BUFFERS):
        meta["n_steps"] = int(buffer.n_steps)
        meta["gamma"] = float(buffer.gamma)
    n = meta["stored_rows"]
    arrays = {name: value[:n] for name, value in _arrays(buffer, keys).items()}
    archive = io.BytesIO()
    np.savez(archive, __meta__=np.array(json.dumps(meta)), **arrays)
    write_checkpoint_bytes(path, archive.getvalue(), "pkl")


def _not_a_buffer(name: str, head: bytes) -> ValueError:
    """Why a file is not a readable archive: a pickle (unsafe), or corrupt."""
    if head[:1] == b"\x80":  # pickle protocols 2 and later start with PROTO
        return UnsafeCheckpointError(
            f"replay buffer file {name!r} is a pickle (SB3's save_replay_buffer writes one), not "
            "an sb3_pnn replay-buffer archive. Unpickling can run arbitrary code, so it is "
            "refused; if you trust the file, pass trust_pickle=True to load_replay_buffer"
        )
    return ValueError(
        f"replay buffer file {name!r} is truncated or corrupt: expected an sb3_pnn replay-buffer "
        "archive (written by DiscreteSAC.save_replay_buffer)"
    )


def _read_archive(raw: io.BytesIO, name: str) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """The metadata and the arrays of a buffer archive, sizes checked before reading."""
    head = raw.getvalue()[:4]
    if not zipfile.is_zipfile(raw):
        raise _not_a_buffer(name, head)
    raw.seek(0)
    where = f"replay buffer file {name!r}"
    try:
        with zipfile.ZipFile(raw) as archive:
            names = archive.namelist()
            if "__meta__.npy" not in names:
                raise _not_a_buffer(name, head)
            member_sizes(archive, names, MAX_BUFFER_BYTES, where)
            member_sizes(archive, ["__meta__.npy"], MAX_JSON_BYTES, where)
        raw.seek(0)
        with np.load(raw, allow_pickle=False) as npz:
            meta_text = str(npz["__meta__"])
            arrays = {k: npz[k] for k in npz.files if k != "__meta__"}
    except (ValueError, *ZIP_DAMAGE, OSError, EOFError, KeyError) as e:
        if isinstance(e, ValueError) and "replay buffer file" in str(e):
            raise
        raise ValueError(f"{where} is truncated or corrupt ({e})") from e
    meta = parse_json(meta_text.encode("utf-8"), f"{where}: its metadata")
    if not isinstance(meta, dict):
        raise ValueError(f"{where}: its metadata is not a mapping")
    return meta, arrays


def _check_meta(meta: dict[str, Any], where: str) -> None:
    """Stored sizes and switches of the right type and range, before a buffer is allocated."""
    n_envs = check_number(meta.get("n_envs"), f"{where} n_envs", 1, 10**4, integer=True)
    check_number(meta.get("buffer_size"), f"{where} buffer_size", 1, 10**9, integer=True)
    if meta["buffer_size"] * n_envs > 10**9:
        raise ValueError(f"{where}: buffer_size x n_envs = {meta['buffer_size'] * n_envs} rows")
    for key in ("pos", "stored_rows"):
        check_number(meta.get(key), f"{where} {key}", 0, 10**9, integer=True)
    for key in ("full", "optimize_memory_usage", "handle_timeout_termination"):
        if not isinstance(meta.get(key), bool):
            raise ValueError(
                f"{where} {key}={meta.get(key)!r:.100} is not allowed: expected a bool"
            )
    if "n_steps" in meta:
        check_number(meta["n_steps"], f"{where} n_steps", 1, 10**4, integer=True)
        check_number(meta.get("gamma"), f"{where} gamma", 0.0, 1.0)


def load_buffer(
    path: str | os.PathLike[str] | io.BufferedIOBase, device: th.device | str = "cpu"
) -> ReplayBuffer:
    """Rebuild a replay buffer saved by :func:`save_buffer`, never unpickling anything; the
    archive's sizes and values are checked before anything is allocated."""
    raw, name = read_file_bytes(
        path, "pkl", "replay buffer file", "replay buffer", MAX_BUFFER_BYTES
    )
    meta, arrays = _read_archive(raw, name)
    if meta.get("format") != FORMAT or meta.get("version") != VERSION:
        raise ValueError(
            f"replay buffer file {name!r}: unsupported format {meta.get('format')!r:.60} version "
            f"{meta.get('version')!r:.20} (expected {FORMAT} version {VERSION})"
        )
    where = f"replay buffer file {name!r}"
    _check_meta(meta, where)
    cls = safe_class(str(meta.get("class")), where)
    if not issubclass(cls, ReplayBuffer):
        raise ValueError(f"{where}: class {meta['class']!r} is not a replay buffer")
    n_envs = int(meta["n_envs"])
    kwargs: dict[str, Any] = dict(
        device=device,
        n_envs=n_envs,
        optimize_memory_usage=bool(meta["optimize_memory_usage"]),
        handle_timeout_termination=bool(meta["handle_timeout_termination"]),
    )
    if issubclass(cls, N_STEP_BUFFERS):
        kwargs.update(n_steps=int(meta["n_steps"]), gamma=float(meta["gamma"]))
    buffer = cls(
        int(meta["buffer_size"]) * n_envs,
        space_from_json(meta["observation_space"], f"{where} observation_space"),
        space_from_json(meta["action_space"], f"{where} action_space"),
        **kwargs,
    )
    n, pos = int(meta["stored_rows"]), int(meta["pos"])
    if buffer.buffer_size != int(meta["buffer_size"]) or not (
        0 <= pos < buffer.buffer_size and 0 <= n <= buffer.buffer_size
    ):
        raise ValueError(
            f"{where}: inconsistent sizes (pos {pos}, rows {n}, size {meta['buffer_size']})"
        )
    keys = meta.get("obs_keys")
    buffer_keys = list(buffer.observations) if isinstance(buffer.observations, dict) else None
    if keys != buffer_keys:
        raise ValueError(f"{where}: observation keys {keys} do not match the space's {buffer_keys}")
    targets = _arrays(buffer, keys)
    if set(targets) != set(arrays):
        raise ValueError(f"{where}: expected arrays {sorted(targets)}, found {sorted(arrays)}")
    for key, target in targets.items():
        value = arrays[key]
        if value.shape != (n, *target.shape[1:]) or value.dtype != target.dtype:
            raise ValueError(
                f"{where}: array {key!r} has shape {value.shape} and dtype {value.dtype}, "
                f"expected {(n, *target.shape[1:])} and {target.dtype}"
            )
        target[:n] = value
    buffer.pos = pos
    buffer.full = bool(meta["full"])
    return buffer
