"""What the play-time wrappers of a trained policy share (``SwitchMemory``, ``NoReversal``, the
corridor-release diagnosis): the wrapped policy's attributes pass through, so that an evaluation
reads the model's task keywords (``trained_env``) and checks its spaces, and ``reset`` forgets
the wrapper's memory and the wrapped policy's."""

from __future__ import annotations

from typing import Any


class PolicyWrapper:
    """Holds ``wrapped`` (anything with SB3's ``predict``); subclasses keep a per-vehicle memory
    and forget it in :meth:`forget`. Every other attribute is the wrapped policy's (``policy``
    of a wrapped SB3 model is the model's own policy network, as without the wrapper)."""

    def __init__(self, wrapped: Any):
        self.wrapped = wrapped

    def __getattr__(self, name: str) -> Any:
        wrapped = self.__dict__.get("wrapped")
        if wrapped is None or name.startswith("__"):
            raise AttributeError(name)
        return getattr(wrapped, name)

    def forget(self) -> None:
        """Drop the wrapper's own memory (every vehicle)."""

    def reset(self) -> None:
        """Forget every vehicle's memory (as ``episode_start`` true for all), here and in the
        wrapped policy where it has one."""
        self.forget()
        if callable(getattr(self.wrapped, "reset", None)):
            self.wrapped.reset()
