"""Allowlist of policy classes a safe checkpoint may name.

A checkpoint stores its policy class by name; loading looks the name up here, so a file can only
pick a class this process already trusts. The classes register themselves where they are defined
(:mod:`sb3_pnn.dsac.policies`, :mod:`sb3_pnn.progressive`), which ``import sb3_pnn`` imports;
other packages add theirs with :func:`register_policy_class`.
"""

from __future__ import annotations

from stable_baselines3.common.policies import BasePolicy

_POLICIES: dict[str, type[BasePolicy]] = {}


def register_policy_class(name: str, cls: type[BasePolicy]) -> None:
    """Allow ``cls`` (an SB3 policy class) in safe checkpoints as ``name``."""
    if not (isinstance(cls, type) and issubclass(cls, BasePolicy)):
        raise ValueError(f"register_policy_class expects an SB3 policy class, got {cls!r}")
    if not isinstance(name, str) or not name:
        raise ValueError(f"policy class name must be a non-empty string, got {name!r}")
    known = _POLICIES.get(name)
    if known is not None and known is not cls:
        raise ValueError(f"policy class name {name!r} is already registered for {known!r}")
    _POLICIES[name] = cls


def policy_class_name(cls: type) -> str:
    """The registered name of ``cls`` (ValueError naming it when it is not registered)."""
    for name, known in _POLICIES.items():
        if known is cls:
            return name
    raise ValueError(
        f"policy class {cls!r} is not registered for safe checkpoints (registered: "
        f"{sorted(_POLICIES)}); call sb3_pnn.safe_io.register_policy_class(name, cls) first"
    )


def get_policy_class(name: str, where: str = "checkpoint") -> type[BasePolicy]:
    """The policy class registered as ``name`` (ValueError naming it otherwise)."""
    if not isinstance(name, str) or name not in _POLICIES:
        raise ValueError(
            f"{where} names policy class {name!r}, which is not registered for safe loading "
            f"(registered: {sorted(_POLICIES)})"
        )
    return _POLICIES[name]
