"""JSON encoding of keyword-argument values (policy_kwargs, replay_buffer_kwargs) for safe
checkpoints.

Plain JSON values are stored as they are; the rest is tagged:

* ``{"$class": name}``: a class from the allowlist (activations, features extractors,
  optimizers, replay buffers; others via :func:`register_safe_class`). Decoding looks the name
  up in the allowlist, so a checkpoint can only name classes this process already trusts;
* ``{"$tuple": [...]}``: a tuple;
* ``{"$float": "inf" | "-inf" | "nan"}``: a non-finite float.

Anything else (functions, arbitrary objects) is refused at save time with an error naming the
entry, e.g. ``policy_kwargs['features_extractor_kwargs']['net']``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import torch as th
from stable_baselines3.common import buffers, torch_layers
from torch import nn

from sb3_pnn.common.buffers import DictNStepReplayBuffer

_SAFE_CLASSES: dict[str, type] = {}


def register_safe_class(cls: type, name: str | None = None) -> str:
    """Allow ``cls`` in saved keyword arguments under ``name`` (default ``module.QualName``).
    Re-registering the same class under the same name is a no-op; a different class under a
    taken name is refused."""
    if not isinstance(cls, type):
        raise ValueError(f"register_safe_class expects a class, got {cls!r}")
    name = name or f"{cls.__module__}.{cls.__qualname__}"
    known = _SAFE_CLASSES.get(name)
    if known is not None and known is not cls:
        raise ValueError(f"safe class name {name!r} is already taken by {known!r}")
    _SAFE_CLASSES[name] = cls
    return name


def _register_defaults() -> None:
    activations = (
        "ReLU", "Tanh", "ELU", "LeakyReLU", "GELU", "SiLU", "Sigmoid", "Softplus", "Mish",
        "SELU", "CELU", "ReLU6", "Hardswish", "Identity",
    )  # fmt: skip
    for name in activations:
        register_safe_class(getattr(nn, name), f"torch.nn.{name}")
    for name in ("Adam", "AdamW", "RMSprop", "SGD", "Adagrad", "Adamax", "NAdam", "RAdam"):
        register_safe_class(getattr(th.optim, name), f"torch.optim.{name}")
    for name in ("FlattenExtractor", "CombinedExtractor", "NatureCNN"):
        register_safe_class(getattr(torch_layers, name), f"stable_baselines3.{name}")
    for name in ("ReplayBuffer", "DictReplayBuffer", "NStepReplayBuffer"):
        register_safe_class(getattr(buffers, name), f"stable_baselines3.{name}")
    register_safe_class(DictNStepReplayBuffer, "sb3_pnn.DictNStepReplayBuffer")


_register_defaults()


def safe_class_name(cls: type) -> str | None:
    for name, known in _SAFE_CLASSES.items():
        if known is cls:
            return name
    return None


def safe_class(name: str, where: str = "checkpoint") -> type:
    if name not in _SAFE_CLASSES:
        raise ValueError(
            f"{where} names class {name!r}, which is not in the allowlist of classes a safe "
            f"checkpoint may use ({sorted(_SAFE_CLASSES)}); register it with "
            "sb3_pnn.safe_io.register_safe_class if you trust it"
        )
    return _SAFE_CLASSES[name]


def encode(value: Any, where: str) -> Any:
    """JSON-able form of ``value`` (ValueError naming ``where`` for what cannot be stored)."""
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return value if math.isfinite(value) else {"$float": repr(value)}
    if isinstance(value, type):
        name = safe_class_name(value)
        if name is None:
            raise ValueError(
                f"cannot store {where} = {value!r} in a safe checkpoint: the class is not in the "
                "allowlist; register it with sb3_pnn.safe_io.register_safe_class(cls)"
            )
        return {"$class": name}
    if isinstance(value, tuple):
        return {"$tuple": [encode(v, f"{where}[{i}]") for i, v in enumerate(value)]}
    if isinstance(value, list):
        return [encode(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, dict):
        out = {}
        for key, v in value.items():
            if not isinstance(key, str) or key.startswith("$"):
                raise ValueError(
                    f"cannot store {where}: dict keys must be strings not starting with '$', "
                    f"got {key!r}"
                )
            out[key] = encode(v, f"{where}[{key!r}]")
        return out
    raise ValueError(
        f"cannot store {where} = {value!r:.100} (type {type(value).__name__}) in a safe "
        "checkpoint: expected JSON values, tuples or allowlisted classes"
    )


def decode(value: Any, where: str) -> Any:
    """Inverse of :func:`encode`; classes only from the allowlist."""
    if isinstance(value, list):
        return [decode(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, dict):
        if len(value) == 1:
            ((tag, inner),) = value.items()
            if tag == "$class":
                return safe_class(str(inner), where)
            if tag == "$tuple":
                if not isinstance(inner, list):
                    raise ValueError(f"{where}: malformed tuple {inner!r:.100}")
                return tuple(decode(v, f"{where}[{i}]") for i, v in enumerate(inner))
            if tag == "$float":
                if inner not in ("inf", "-inf", "nan"):
                    raise ValueError(f"{where}: malformed float {inner!r:.100}")
                return float(inner)
        if any(k.startswith("$") for k in value):
            raise ValueError(f"{where}: unknown tag in {value!r:.200}")
        return {k: decode(v, f"{where}[{k!r}]") for k, v in value.items()}
    return value
