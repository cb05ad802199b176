"""Safe DiscreteSAC checkpoints: a JSON member beside SB3's zip parts, and loading from it.

Saving (:func:`save_with_metadata`) writes SB3's usual zip (``data``, ``policy.pth``, the
optimizers' ``.pth``, ``pytorch_variables.pth``; SB3 tools keep reading it) plus the member
:data:`JSON_MEMBER` = ``sb3_pnn.json``, which holds everything needed to rebuild the model:
format version, the policy class by registered name, policy kwargs (:mod:`.json_codec`),
observation and action spaces (:mod:`.spaces_codec`), the constructor's hyperparameters and the
training counters.

Loading (:func:`load_model`) reads only that member (``json``) and the ``.pth`` members through
SB3's ``load_from_zip_file(load_data=False)``, i.e. ``torch.load(weights_only=True)``: tensors
and plain containers, no code. The ``data`` member is never read. The model is rebuilt through
the constructor (``_init_setup_model=False``, then ``_setup_model()``) and the state dicts are
put back with ``set_parameters(exact_match=True)``.

This module is a layer below the algorithm: it knows SB3's ``OffPolicyAlgorithm`` and nothing of
:class:`sb3_pnn.DiscreteSAC`. The algorithm class tells it what to store: its
``CHECKPOINT_KEYS`` (the constructor arguments the JSON member holds, ``learning_rate`` aside)
and ``checkpoint_hyperparameters()`` (their values for one model).
"""

from __future__ import annotations

import inspect
import io
import json
import os
import pathlib
import pickle
import zipfile
from typing import TYPE_CHECKING, Any

import stable_baselines3 as sb3
import torch as th
from gymnasium import spaces
from stable_baselines3.common.buffers import ReplayBuffer
from stable_baselines3.common.save_util import load_from_zip_file, recursive_setattr
from stable_baselines3.common.utils import (
    ConstantSchedule,
    FloatSchedule,
    LinearSchedule,
    get_system_info,
)

from sb3_pnn.safe_io.files import read_file_bytes, write_checkpoint_bytes
from sb3_pnn.safe_io.json_codec import decode, encode, safe_class_name
from sb3_pnn.safe_io.limits import (
    MAX_CHECKPOINT_BYTES,
    MAX_JSON_BYTES,
    MAX_WEIGHTS_BYTES,
    ZIP_DAMAGE,
    check_number,
    check_widths,
    member_sizes,
    parse_json,
    read_member,
)
from sb3_pnn.safe_io.policy_registry import get_policy_class, policy_class_name
from sb3_pnn.safe_io.spaces_codec import space_from_json, space_to_json

if TYPE_CHECKING:
    from stable_baselines3.common.off_policy_algorithm import OffPolicyAlgorithm

JSON_MEMBER = "sb3_pnn.json"
FORMAT = "sb3_pnn.DiscreteSAC"
#: The format written; :data:`READABLE_VERSIONS` are read (an algorithm's
#: ``upgrade_checkpoint`` brings an older one up to date).
VERSION = 2
READABLE_VERSIONS = (1, 2)

#: Counters restored after ``_setup_model``
STATE_KEYS = (
    "num_timesteps", "_total_timesteps", "_num_timesteps_at_start", "_n_updates",
    "_episode_num", "_current_progress_remaining",
)  # fmt: skip
#: ``custom_objects`` entries that SB3's zoo passes and that a rebuilt model recomputes anyway
IGNORED_CUSTOM_OBJECTS = ("lr_schedule", "exploration_schedule", "clip_range", "clip_range_vf")


class UnsafeCheckpointError(ValueError):
    """A checkpoint that can only be loaded by unpickling (``trust_pickle=True``)."""


# --- learning rate ------------------------------------------------------------------------
def schedule_to_json(value: Any, current: float) -> dict[str, Any]:
    """A float or SB3's Constant/Linear/FloatSchedule as JSON; other callables are recorded as
    unsupported (load then asks for ``custom_objects={"learning_rate": ...}``)."""
    if isinstance(value, FloatSchedule):
        return schedule_to_json(value.value_schedule, current)
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return {"constant": float(value)}
    if isinstance(value, ConstantSchedule):
        return {"constant": float(value.val)}
    if isinstance(value, LinearSchedule):
        return {"linear": [float(value.start), float(value.end), float(value.end_fraction)]}
    return {"unsupported": repr(value)[:200], "value_when_saved": float(current)}


def schedule_from_json(data: Any, where: str) -> float | LinearSchedule:
    if isinstance(data, dict) and "constant" in data:
        return float(data["constant"])
    if isinstance(data, dict) and "linear" in data:
        start, end, end_fraction = (float(v) for v in data["linear"])
        return LinearSchedule(start, end, end_fraction)
    if isinstance(data, dict) and "unsupported" in data:
        raise ValueError(
            f"{where}: the model was trained with a learning-rate schedule that a safe checkpoint "
            f"cannot store ({data['unsupported']}; value when saved: "
            f"{data.get('value_when_saved')}). Pass custom_objects={{'learning_rate': <float or "
            "schedule>}} to DiscreteSAC.load"
        )
    raise ValueError(f"{where}: malformed learning_rate entry {data!r:.200}")


# --- saving -------------------------------------------------------------------------------
def model_metadata(model: OffPolicyAlgorithm, algorithm_name: str = FORMAT) -> dict[str, Any]:
    """The JSON member of ``model``'s checkpoint (ValueError naming what cannot be stored).

    ``model``'s class provides ``checkpoint_hyperparameters()``: its constructor arguments as
    plain values, and ``checkpoint_extras()``: further JSON entries for the record (see the
    module docstring)."""
    hyper = model.checkpoint_hyperparameters()  # type: ignore[attr-defined]
    buffer_class = hyper.get("replay_buffer_class")
    if buffer_class is not None and safe_class_name(buffer_class) is None:
        raise ValueError(
            f"cannot store replay_buffer_class {buffer_class!r} in a safe checkpoint: register "
            "it with sb3_pnn.safe_io.register_safe_class"
        )
    state_dicts, variables = model._get_torch_save_params()
    return {
        "format": algorithm_name,
        "version": VERSION,
        "stable_baselines3": sb3.__version__,
        "policy_class": policy_class_name(model.policy_class),
        "observation_space": space_to_json(model.observation_space),
        "action_space": space_to_json(model.action_space),
        "n_envs": int(model.n_envs),
        "learning_rate": schedule_to_json(
            model.learning_rate, float(model.lr_schedule(model._current_progress_remaining))
        ),
        "hyperparameters": {k: encode(v, k) for k, v in hyper.items()},
        "state": {k: encode(getattr(model, k), k) for k in STATE_KEYS},
        **model.checkpoint_extras(),  # type: ignore[attr-defined]
        "state_dicts": list(state_dicts),
        "pytorch_variables": list(variables),
    }


def save_with_metadata(
    path: str | pathlib.Path | io.BufferedIOBase, sb3_zip: io.BytesIO, meta: dict[str, Any]
) -> None:
    """Write SB3's zip (built in memory) plus :data:`JSON_MEMBER` to ``path``, atomically (SB3
    naming: a path without suffix gets ``.zip``)."""
    with zipfile.ZipFile(sb3_zip, mode="a") as archive:
        archive.writestr(JSON_MEMBER, json.dumps(meta, indent=1, allow_nan=False))
    write_checkpoint_bytes(path, sb3_zip.getvalue(), "zip")


# --- loading ------------------------------------------------------------------------------
#: The members SB3 itself writes into every model zip (a zip with them but without
#: :data:`JSON_MEMBER` is an SB3 checkpoint that only unpickling can read).
SB3_MEMBERS = frozenset({"data", "policy.pth", "pytorch_variables.pth"})


def _missing_json_member(name: str, names: list[str]) -> ValueError:
    """The error for a zip without :data:`JSON_MEMBER`: unsafe when it is a whole SB3
    checkpoint, corrupt otherwise (e.g. a file cut short, where zipfile may find a weights
    archive nested inside)."""
    if SB3_MEMBERS <= set(names):
        return UnsafeCheckpointError(
            f"{name!r} is a Stable-Baselines3 zip without sb3_pnn's JSON member (saved by SB3 "
            "itself, or by sb3_pnn before safe checkpoints). Loading it needs unpickling its "
            "'data' part, which can run arbitrary code, so it is refused. If you trust the "
            "file, load it with DiscreteSAC.load(path, trust_pickle=True) and save it again to "
            "get a safe checkpoint"
        )
    return ValueError(
        f"{name!r} is not a complete DiscreteSAC checkpoint: it is truncated or corrupt (the zip "
        f"holds {sorted(names)[:6]}, not sb3_pnn's {JSON_MEMBER} and SB3's members)"
    )


def _read_weights(raw: io.BytesIO, names: list[str], name: str, device: Any) -> tuple[dict, dict]:
    """The ``.pth`` members through SB3's ``load_from_zip_file(load_data=False)``
    (``torch.load(weights_only=True)``), their sizes checked first."""
    with zipfile.ZipFile(raw) as archive:
        member_sizes(
            archive, [n for n in names if n.endswith(".pth")], MAX_WEIGHTS_BYTES, repr(name)
        )
    raw.seek(0)
    try:
        _, params, variables = load_from_zip_file(raw, load_data=False, device=device)
    except (ValueError, RuntimeError, EOFError, OSError, pickle.UnpicklingError) as e:
        # weights_only=True refuses anything that is not tensors / plain containers
        raise ValueError(f"{name!r}: cannot read the weights (.pth members) ({e})") from e
    except (*ZIP_DAMAGE, KeyError, IndexError, UnicodeDecodeError) as e:
        raise ValueError(f"{name!r}: the weights (.pth members) are corrupt ({e})") from e
    return params, variables or {}


def read_checkpoint(
    path: str | os.PathLike[str] | io.BufferedIOBase, device: th.device | str = "cpu"
) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any], str]:
    """(JSON member, state dicts, pytorch variables, name) of a safe checkpoint; never reads
    ``data``. UnsafeCheckpointError when the file is an SB3 checkpoint without the JSON member,
    ValueError naming the problem when it is corrupt, truncated or larger than the limits of
    :mod:`sb3_pnn.safe_io.limits`."""
    raw, name = read_file_bytes(
        path, "zip", "DiscreteSAC checkpoint", "checkpoint", MAX_CHECKPOINT_BYTES
    )
    try:
        with zipfile.ZipFile(raw) as archive:
            names = archive.namelist()
            if JSON_MEMBER not in names:
                raise _missing_json_member(name, names)
            meta_bytes = read_member(archive, JSON_MEMBER, MAX_JSON_BYTES, repr(name))
    except ZIP_DAMAGE as e:
        raise ValueError(
            f"{name!r} is not a valid zip file ({e}): truncated or corrupt; expected a "
            "DiscreteSAC .zip checkpoint"
        ) from e
    meta = parse_json(meta_bytes, f"{name!r}: the {JSON_MEMBER} member")
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise ValueError(f"{name!r}: {JSON_MEMBER} is not a {FORMAT} description")
    if meta.get("version") not in READABLE_VERSIONS:
        raise ValueError(
            f"{name!r}: checkpoint format version {meta.get('version')!r:.20} is not supported "
            f"(this sb3_pnn reads versions {list(READABLE_VERSIONS)})"
        )
    params, variables = _read_weights(raw, names, name, device)
    expected = meta.get("state_dicts")
    if not isinstance(expected, list) or set(params) != set(map(str, expected)):
        raise ValueError(
            f"{name!r}: expected state dicts {expected!r:.200}, found {sorted(params)}"
        )
    if not isinstance(variables, dict) or set(variables) != set(meta.get("pytorch_variables", [])):
        raise ValueError(
            f"{name!r}: expected pytorch variables {meta.get('pytorch_variables')!r:.200}, found "
            f"{sorted(variables) if isinstance(variables, dict) else type(variables).__name__}"
        )
    return meta, params, variables, name


def check_state(state: Any, where: str) -> None:
    """The stored training counters: ints >= 0, the remaining progress a number <= 1."""
    if not isinstance(state, dict):
        raise ValueError(f"{where}: the state entry is not a mapping")
    for key in STATE_KEYS:
        if key not in state:
            continue
        if key == "_current_progress_remaining":
            check_number(state[key], f"{where} {key}", -1e9, 1.0)  # < 0 past the budget
        else:
            check_number(state[key], f"{where} {key}", 0, 10**15, integer=True)


def check_policy_kwargs(policy_class: type, kwargs: Any, where: str) -> None:
    """Stored policy keyword arguments: names the policy's constructor takes, and network
    sizes within :mod:`sb3_pnn.safe_io.limits` (before anything is built from them)."""
    if kwargs is None:
        return
    if not isinstance(kwargs, dict):
        raise ValueError(f"{where}: policy_kwargs is not a mapping: {kwargs!r:.100}")
    parameters = inspect.signature(policy_class.__init__).parameters
    takes_any = any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values())
    unknown = sorted(k for k in kwargs if k not in parameters or k in _POSITIONAL)
    if unknown and not takes_any:
        known = sorted(k for k in parameters if k not in _POSITIONAL)
        raise ValueError(
            f"{where}: policy_kwargs names {unknown}, which {policy_class.__name__} does not "
            f"take (expected some of {known})"
        )
    net_arch = kwargs.get("net_arch")
    if isinstance(net_arch, dict):
        for key, widths in net_arch.items():
            check_widths(widths, f"{where} policy_kwargs['net_arch'][{key!r}]")
    elif net_arch is not None:
        check_widths(net_arch, f"{where} policy_kwargs['net_arch']")


#: A policy constructor's arguments that a checkpoint never stores in policy_kwargs.
_POSITIONAL = ("self", "observation_space", "action_space", "lr_schedule")


def _check_env_spaces(env: Any, obs: spaces.Space, act: spaces.Space, name: str) -> None:
    for what, saved, given in (
        ("observation", obs, env.observation_space),
        ("action", act, env.action_space),
    ):
        if saved != given:
            raise ValueError(
                f"the environment does not fit checkpoint {name!r}: its {what} space is {given}, "
                f"the checkpoint's is {saved}"
            )


def load_model(
    cls: type[OffPolicyAlgorithm],
    path: str | os.PathLike[str] | io.BufferedIOBase,
    env: Any = None,
    device: th.device | str = "auto",
    custom_objects: dict[str, Any] | None = None,
    print_system_info: bool = False,
    kwargs: dict[str, Any] | None = None,
) -> OffPolicyAlgorithm:
    """Rebuild a model of class ``cls`` from a safe checkpoint (see the module docstring)."""
    kwargs = dict(kwargs or {})
    meta, params, variables, name = read_checkpoint(path, device="cpu")
    upgrade = getattr(cls, "upgrade_checkpoint", None)
    if upgrade is not None:
        meta = upgrade(meta)
    if print_system_info:
        print("== CURRENT SYSTEM INFO ==")
        get_system_info()
    where = f"checkpoint {name!r}"
    policy_class = get_policy_class(meta.get("policy_class"), where)
    obs_space = space_from_json(meta.get("observation_space"), f"{where} observation_space")
    act_space = space_from_json(meta.get("action_space"), f"{where} action_space")
    hyper_json = meta.get("hyperparameters")
    if not isinstance(hyper_json, dict) or set(hyper_json) != set(cls.CHECKPOINT_KEYS):  # type: ignore[attr-defined]
        raise ValueError(f"{where}: malformed hyperparameters entry")
    hyper = {k: decode(v, f"{where} {k}") for k, v in hyper_json.items()}
    cls.check_checkpoint_hyperparameters(hyper, where)  # type: ignore[attr-defined]
    check_policy_kwargs(policy_class, hyper.get("policy_kwargs"), where)
    check_state(meta.get("state", {}), where)
    buffer_class = hyper["replay_buffer_class"]
    if buffer_class is not None and not (
        isinstance(buffer_class, type) and issubclass(buffer_class, ReplayBuffer)
    ):
        raise ValueError(f"{where}: replay_buffer_class {buffer_class!r} is not a replay buffer")

    custom_objects = dict(custom_objects or {})
    for key in IGNORED_CUSTOM_OBJECTS:
        custom_objects.pop(key, None)
    if "learning_rate" in custom_objects:
        hyper["learning_rate"] = custom_objects.pop("learning_rate")
    else:
        hyper["learning_rate"] = schedule_from_json(meta.get("learning_rate"), where)
    for key in list(custom_objects):  # SB3: custom objects replace saved entries
        if key in hyper:
            hyper[key] = custom_objects.pop(key)
    obs_space = custom_objects.pop("observation_space", obs_space)
    act_space = custom_objects.pop("action_space", act_space)
    # other custom objects name nothing a safe checkpoint stores: nothing to replace

    if "policy_kwargs" in kwargs and kwargs["policy_kwargs"] != hyper["policy_kwargs"]:
        raise ValueError(
            f"The specified policy kwargs do not equal the stored policy kwargs. Stored kwargs: "
            f"{hyper['policy_kwargs']}, specified kwargs: {kwargs['policy_kwargs']}"
        )
    kwargs.pop("policy_kwargs", None)
    for key in list(kwargs):  # overrides of constructor arguments, e.g. the zoo's buffer_size=1
        if key in hyper:
            hyper[key] = kwargs.pop(key)

    n_envs = int(meta.get("n_envs", 1))
    if env is not None:
        env = cls._wrap_env(env, hyper["verbose"])
        _check_env_spaces(env, obs_space, act_space, name)
        n_envs = env.num_envs
    model = cls(policy=policy_class, env=env, device=device, _init_setup_model=False, **hyper)
    if env is None:
        model.observation_space = obs_space
        model.action_space = act_space
        model.n_envs = n_envs
    state = meta.get("state", {})
    for key in STATE_KEYS:
        if key in state:
            setattr(model, key, decode(state[key], f"{where} {key}"))
    for key, value in kwargs.items():  # as SB3's load: other kwargs set attributes
        setattr(model, key, value)
    model._setup_model()
    restore = getattr(model, "restore_checkpoint_extras", None)
    if restore is not None:
        restore(meta, where)
    try:
        model.set_parameters(params, exact_match=True, device=device)
    except (ValueError, RuntimeError, KeyError) as e:
        raise ValueError(f"{where}: the saved weights do not fit the rebuilt model ({e})") from e
    for var_name, value in variables.items():
        if not isinstance(value, th.Tensor):
            raise ValueError(f"{where}: pytorch variable {var_name!r} is not a tensor")
        recursive_setattr(model, f"{var_name}.data", value.data.to(model.device))
    return model
