"""What the play-time wrappers of a trained policy share (``NoReversal``, the corridor-release
diagnosis): the wrapped policy's attributes pass through, so that an evaluation reads the
model's task keywords (``trained_env``) and checks its spaces, and ``reset`` forgets the
wrapper's memory and the wrapped policy's."""

from __future__ import annotations

from typing import Any


class PolicyWrapper:
    """Holds ``policy`` (anything with SB3's ``predict``); subclasses keep a per-vehicle memory
    and forget it in :meth:`forget`."""

    def __init__(self, policy: Any):
        self.policy = policy

    def __getattr__(self, name: str) -> Any:
        policy = self.__dict__.get("policy")
        if policy is None or name.startswith("__"):
            raise AttributeError(name)
        return getattr(policy, name)

    def forget(self) -> None:
        """Drop the wrapper's own memory (every vehicle)."""

    def reset(self) -> None:
        """Forget every vehicle's memory (as ``episode_start`` true for all), here and in the
        wrapped policy where it has one."""
        self.forget()
        if callable(getattr(self.policy, "reset", None)):
            self.policy.reset()
