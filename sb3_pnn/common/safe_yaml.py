"""YAML that cannot run code: the plain data of YAML plus the two Python tags rl_zoo3 writes.

rl_zoo3 saves a run's ``config.yml`` and ``args.yml`` with ``yaml.dump``, which tags an
``OrderedDict`` as ``!!python/object/apply:collections.OrderedDict`` and a tuple as
``!!python/tuple``, and reads them back with ``yaml.UnsafeLoader``, which builds any Python
object a file names (``!!python/object/apply:os.system [...]`` runs a command). Users share log
folders, so :func:`load_yaml` reads them with PyYAML's ``SafeLoader`` taught only those two
tags, rebuilt as a plain dict and a tuple; any other tag is refused with a ``ValueError`` naming
the file and the tag.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import yaml

#: Largest YAML file read (bytes): a run's settings are a few kB.
MAX_YAML_BYTES = 1 << 20


class _ZooLoader(yaml.SafeLoader):
    """SafeLoader plus rl_zoo3's ordered dicts and tuples."""


def _ordered_dict(loader: yaml.SafeLoader, node: yaml.Node) -> dict[str, Any]:
    """``OrderedDict([[key, value], ...])`` as rl_zoo3 dumps it, rebuilt as a plain dict."""
    args = (
        loader.construct_sequence(node, deep=True) if isinstance(node, yaml.SequenceNode) else None
    )
    pairs = args[0] if args is not None and len(args) == 1 else None
    if not isinstance(pairs, list) or not all(
        isinstance(p, list) and len(p) == 2 and isinstance(p[0], (str, int, float, bool))
        for p in pairs
    ):
        raise yaml.constructor.ConstructorError(
            None, None, "an OrderedDict must be one list of [key, value] pairs", node.start_mark
        )
    return {key: value for key, value in pairs}


def _tuple(loader: yaml.SafeLoader, node: yaml.Node) -> tuple[Any, ...]:
    return tuple(loader.construct_sequence(node, deep=True))


_ZooLoader.add_constructor(
    "tag:yaml.org,2002:python/object/apply:collections.OrderedDict", _ordered_dict
)
_ZooLoader.add_constructor("tag:yaml.org,2002:python/tuple", _tuple)


def load_yaml(path: str | os.PathLike[str]) -> Any:
    """The content of the YAML file ``path`` (see the module docstring); ``ValueError`` naming
    the file for a tag that could build an object, malformed YAML or a file over
    :data:`MAX_YAML_BYTES`."""
    path = Path(path)
    size = path.stat().st_size
    if size > MAX_YAML_BYTES:
        raise ValueError(
            f"{path}: {size} bytes is not allowed: expected a YAML file of at most "
            f"{MAX_YAML_BYTES} bytes"
        )
    return loads_yaml(path.read_text(encoding="utf-8"), str(path))


def loads_yaml(text: str, where: str = "YAML") -> Any:
    """:func:`load_yaml` for text already read (``where`` names it in errors)."""
    try:
        return yaml.load(text, Loader=_ZooLoader)  # noqa: S506 - a safe loader (see above)
    except yaml.constructor.ConstructorError as error:
        raise ValueError(
            f"{where}: {error.problem or error}; only plain data (and rl_zoo3's ordered dicts and "
            "tuples) is read, never a tag that builds a Python object"
        ) from None
    except yaml.YAMLError as error:
        raise ValueError(f"{where} is not valid YAML: {error}") from None
    except RecursionError:
        raise ValueError(f"{where}: nesting too deep: expected a run's settings") from None
