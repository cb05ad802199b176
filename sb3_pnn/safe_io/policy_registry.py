"""Allowlist of policy classes a safe DiscreteSAC checkpoint may name.

A checkpoint stores its policy class by name; loading looks the name up here, so a file can only
pick a class this process already trusts. Built in: ``DiscreteSACPolicy``,
``MultiInputDiscreteSACPolicy`` and, imported lazily from :mod:`sb3_pnn.progressive` on first
use (so that the registry is complete without an import cycle), ``ProgressivePolicy`` and
``SelectivePolicy``. Other modules add theirs with :func:`register_policy_class`.
"""

from __future__ import annotations

import importlib

from sb3_pnn.policies import DiscreteSACPolicy, MultiInputDiscreteSACPolicy

_POLICIES: dict[str, type[DiscreteSACPolicy]] = {
    "DiscreteSACPolicy": DiscreteSACPolicy,
    "MultiInputDiscreteSACPolicy": MultiInputDiscreteSACPolicy,
}
#: name -> "module:attribute", imported on first use
_LAZY: dict[str, str] = {
    "ProgressivePolicy": "sb3_pnn.progressive:ProgressivePolicy",
    "SelectivePolicy": "sb3_pnn.progressive:SelectivePolicy",
}


def register_policy_class(name: str, cls: type[DiscreteSACPolicy]) -> None:
    """Allow ``cls`` (a :class:`DiscreteSACPolicy` subclass) in safe checkpoints as ``name``."""
    if not (isinstance(cls, type) and issubclass(cls, DiscreteSACPolicy)):
        raise ValueError(f"register_policy_class expects a DiscreteSACPolicy subclass, got {cls!r}")
    if not isinstance(name, str) or not name:
        raise ValueError(f"policy class name must be a non-empty string, got {name!r}")
    known = _POLICIES.get(name)
    if known is not None and known is not cls:
        raise ValueError(f"policy class name {name!r} is already registered for {known!r}")
    _POLICIES[name] = cls
    _LAZY.pop(name, None)


def _import_lazy() -> None:
    for name, target in list(_LAZY.items()):
        module, attr = target.split(":")
        register_policy_class(name, getattr(importlib.import_module(module), attr))


def policy_class_name(cls: type) -> str:
    """The registered name of ``cls`` (ValueError naming it when it is not registered)."""
    _import_lazy()
    for name, known in _POLICIES.items():
        if known is cls:
            return name
    raise ValueError(
        f"policy class {cls!r} is not registered for safe checkpoints (registered: "
        f"{sorted(_POLICIES)}); call sb3_pnn.safe_io.register_policy_class(name, cls) first"
    )


def get_policy_class(name: str, where: str = "checkpoint") -> type[DiscreteSACPolicy]:
    """The policy class registered as ``name`` (ValueError naming it otherwise)."""
    _import_lazy()
    if not isinstance(name, str) or name not in _POLICIES:
        raise ValueError(
            f"{where} names policy class {name!r}, which is not registered for safe loading "
            f"(registered: {sorted(_POLICIES)})"
        )
    return _POLICIES[name]
