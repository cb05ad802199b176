"""Old module paths that moved when the packages were split into layers: importing one fails
with ``ModuleNotFoundError`` naming its new path (instead of a bare "No module named")."""

from __future__ import annotations

import importlib.abc
import sys
from collections.abc import Mapping, Sequence
from typing import Any


class MovedModules(importlib.abc.MetaPathFinder):
    """A finder consulted after the real ones: it only answers for the names in ``moved``."""

    def __init__(self, moved: Mapping[str, str]) -> None:
        self.moved = dict(moved)

    def find_spec(self, fullname: str, path: Sequence[str] | None = None, target: Any = None):
        new = self.moved.get(fullname)
        if new is not None:
            raise ModuleNotFoundError(f"{fullname} moved to {new}", name=fullname)
        return None


def install(moved: Mapping[str, str]) -> None:
    """Append a :class:`MovedModules` finder for ``moved`` (old name -> new) to
    ``sys.meta_path``."""
    sys.meta_path.append(MovedModules(moved))


#: rov_envs' old module paths -> the new ones.
ROV_ENVS_MOVED = {
    **{
        f"rov_envs.{m}": f"rov_envs.sim.{m}"
        for m in (
            "config",
            "tasks",
            "rewards",
            "layouts",
            "random_stream",
            "kernel",
            "episode",
            "engine",
            "spaces",
        )
    },  # fmt: skip
    **{f"rov_envs.{m}": f"rov_envs.envs.{m}" for m in ("env", "vector", "sb3")},
    "rov_envs.plotting": "rov_envs.render.plotting",
    "rov_envs.demo": "rov_envs.render.demo",
}
