"""Safe loading of prior columns from SB3 checkpoints (paper section 3.1: frozen column 1..k-1).

A prior checkpoint is an ordinary SB3 ``.zip`` saved by :class:`sb3_pnn.DiscreteSAC` or by SB3's
``DQN``. Its ``data`` part holds cloudpickled objects: unpickling an untrusted checkpoint runs
arbitrary code. :func:`load_prior` therefore never unpickles ``data``:

* the weights come from ``policy.pth`` through ``torch.load(weights_only=True)`` (tensors only);
* the observation space, the action count and the activation come from the *readable* JSON
  fields SB3 writes beside each ``:serialized:`` blob (see :mod:`.obs_spec`). The activation,
  when ``policy_kwargs`` had to be pickled, is found by walking the pickle's opcodes with
  :func:`pickletools.genops`, which only tokenises the bytes and executes nothing;
* the layer sizes come from the weight shapes and are cross-checked against the observation
  space (the first ``Linear``'s ``in_features`` must equal the flattened observation size) and the
  action count (the output layer's ``out_features``).

Columns read from a checkpoint (a "Q-network is a column too"):

* ``DiscreteSAC``: the actor column is ``actor.latent_pi`` + ``actor.action_logits``; each critic
  column is one ``critic.q_networks[i]``.
* ``DQN``: the single column is ``q_net.q_net`` (the online network, not the target). It serves as
  the actor's prior column *and* as every critic's prior column: its hidden layers are features
  learnt for the task, which is what the laterals read (the output layer of a prior is never used
  by the new column, so Q-values versus logits does not matter for PNN/SPNN).
"""

from __future__ import annotations

import base64
import os
import pickle
import pickletools
import re
import zipfile
from dataclasses import dataclass, field
from typing import Any

import torch as th
from torch import nn

from sb3_pnn.progressive.obs_spec import ObsSpec, obs_spec_from_saved
from sb3_pnn.safe_io.limits import (
    MAX_CHECKPOINT_BYTES,
    MAX_JSON_BYTES,
    MAX_WEIGHTS_BYTES,
    ZIP_DAMAGE,
    check_file_size,
    check_widths,
    member_sizes,
    parse_json,
    read_member,
)

#: Activations a prior may use, by class name (``torch.nn`` classes with default arguments).
ACTIVATIONS: dict[str, type[nn.Module]] = {
    name: getattr(nn, name)
    for name in ("ReLU", "Tanh", "ELU", "LeakyReLU", "GELU", "SiLU", "Sigmoid", "Softplus", "Mish")
}

Layers = list[tuple[th.Tensor, th.Tensor]]


@dataclass(frozen=True)
class ColumnSpec:
    """Architecture of one column: input size, hidden widths, output size, activation name."""

    in_dim: int
    hidden: tuple[int, ...]
    out_dim: int
    activation: str

    def to_json(self) -> dict[str, Any]:
        return {
            "in_dim": self.in_dim,
            "hidden": list(self.hidden),
            "out_dim": self.out_dim,
            "activation": self.activation,
        }

    @staticmethod
    def from_json(d: dict[str, Any]) -> ColumnSpec:
        """A column stored in a saved model's ``prior_specs``; sizes checked before any network
        is built from them."""
        if not isinstance(d, dict):
            raise ValueError(f"prior column spec: expected a mapping, got {d!r:.100}")
        hidden = check_widths(d.get("hidden"), "prior column spec hidden")
        in_dim, out_dim = check_widths([d.get("in_dim"), d.get("out_dim")], "prior column spec")
        if d.get("activation") not in ACTIVATIONS:
            raise ValueError(
                f"prior column spec activation={d.get('activation')!r:.60} is not allowed: "
                f"expected one of {sorted(ACTIVATIONS)}"
            )
        return ColumnSpec(in_dim, tuple(hidden), out_dim, d["activation"])


@dataclass(frozen=True)
class PriorSpec:
    """Everything needed to rebuild a prior's columns without its file (JSON-able via
    :meth:`to_json`): the algorithm ("dqn" or "dsac"), observation space, action count, actor
    column and critic columns (one per Q-network of the checkpoint), and the source file name."""

    algo: str
    obs: ObsSpec
    n_actions: int
    actor: ColumnSpec
    critics: tuple[ColumnSpec, ...]
    source: str = ""

    def to_json(self) -> dict[str, Any]:
        return {
            "algo": self.algo,
            "obs": self.obs.to_json(),
            "n_actions": self.n_actions,
            "actor": self.actor.to_json(),
            "critics": [c.to_json() for c in self.critics],
            "source": self.source,
        }

    @staticmethod
    def from_json(d: dict[str, Any]) -> PriorSpec:
        if not isinstance(d, dict) or not {"algo", "obs", "actor", "critics"} <= set(d):
            raise ValueError(f"expected a prior spec dict (from PriorSpec.to_json), got {d!r:.200}")
        return PriorSpec(
            algo=str(d["algo"]),
            obs=ObsSpec.from_json(d["obs"]),
            n_actions=int(d["n_actions"]),
            actor=ColumnSpec.from_json(d["actor"]),
            critics=tuple(ColumnSpec.from_json(c) for c in d["critics"]),
            source=str(d.get("source", "")),
        )


@dataclass
class PriorCheckpoint:
    """A prior read from disk: its :class:`PriorSpec` and the (W, b) pairs of every column."""

    spec: PriorSpec
    actor_layers: Layers
    critic_layers: list[Layers] = field(default_factory=list)


def _fail(path: str, what: str) -> ValueError:
    return ValueError(f"prior checkpoint {path!r}: {what}")


def _chain(sd: dict[str, th.Tensor], prefix: str, path: str) -> Layers:
    """The Linear layers ``<prefix><i>.weight``/``.bias`` of an ``nn.Sequential``, in order."""
    pat = re.compile(re.escape(prefix) + r"(\d+)\.weight$")
    idx = sorted(int(m.group(1)) for k in sd if (m := pat.match(k)))
    if not idx:
        raise _fail(path, f"no Linear layers under '{prefix}*' in policy.pth")
    return [(sd[f"{prefix}{i}.weight"], sd[f"{prefix}{i}.bias"]) for i in idx]


def _check_layers(layers: Layers, where: str, path: str) -> None:
    for i, (w, b) in enumerate(layers):
        if w.ndim != 2 or b.ndim != 1 or b.shape[0] != w.shape[0]:
            raise _fail(path, f"{where} layer {i} is not a Linear layer (weight {tuple(w.shape)})")
        if i and w.shape[1] != layers[i - 1][0].shape[0]:
            raise _fail(
                path,
                f"{where} layer {i} takes {w.shape[1]} inputs but layer {i - 1} gives "
                f"{layers[i - 1][0].shape[0]}",
            )


def _column_spec(layers: Layers, activation: str) -> ColumnSpec:
    return ColumnSpec(
        in_dim=int(layers[0][0].shape[1]),
        hidden=tuple(int(w.shape[0]) for w, _ in layers[:-1]),
        out_dim=int(layers[-1][0].shape[0]),
        activation=activation,
    )


def _pickle_strings(blob_b64: str) -> list[str]:
    """String arguments of the opcodes of a base64 pickle, found by tokenising (not running) it."""
    try:
        raw = base64.b64decode(blob_b64.encode(), validate=False)
        return [str(arg) for _, arg, _ in pickletools.genops(raw) if isinstance(arg, str)]
    except Exception:  # any malformed blob: tokenising failed, nothing was run
        return []


def _activation(data: dict[str, Any], path: str) -> str:
    """Activation class name from ``policy_kwargs`` (plain JSON, or the opcodes of its pickle)."""
    kwargs = data.get("policy_kwargs", {})
    if isinstance(kwargs, dict) and ":serialized:" not in kwargs:
        if "activation_fn" in kwargs:  # JSON cannot hold a class, so this is never a class
            raise _fail(
                path, f"unreadable policy_kwargs['activation_fn'] = {kwargs['activation_fn']!r}"
            )
        return "ReLU"  # SB3's and DiscreteSAC's default
    strings = _pickle_strings(str(kwargs.get(":serialized:", "")))
    if "activation_fn" not in strings:
        return "ReLU"
    found = {
        strings[i + 1]
        for i, s in enumerate(strings[:-1])
        if s.startswith("torch.nn.modules") and strings[i + 1] in ACTIVATIONS
    }
    if len(found) != 1:
        raise _fail(
            path,
            "policy_kwargs sets activation_fn, but it is not one of the supported torch.nn "
            f"activations {sorted(ACTIVATIONS)} (found {sorted(found) or 'none'})",
        )
    return found.pop()


def _n_actions(data: dict[str, Any], path: str) -> int:
    space = data.get("action_space")
    type_name = str(space.get(":type:", "")) if isinstance(space, dict) else ""
    if not type_name.endswith(".Discrete'>"):
        raise _fail(
            path,
            f"expected a policy for a Discrete action space (DiscreteSAC or DQN), got action "
            f"space type {type_name or space!r}",
        )
    try:
        n = int(str(space["n"]))
        start = int(str(space.get("start", "0")))
    except (KeyError, ValueError) as e:
        raise _fail(path, f"unreadable Discrete action space fields {space!r:.200}") from e
    if start != 0:
        raise _fail(path, f"Discrete action space must start at 0, got start={start}")
    return n


def read_zip(path: str | os.PathLike[str]) -> tuple[dict[str, Any], dict[str, th.Tensor]]:
    """The ``data`` JSON (as plain JSON, nothing unpickled) and ``policy.pth`` state dict of a
    SB3 zip; ``ValueError``/``FileNotFoundError`` naming the path on any problem. The file's and
    the members' sizes are checked before they are read (:mod:`sb3_pnn.safe_io.limits`)."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"prior checkpoint {path!r} does not exist (expected an SB3 .zip)")
    check_file_size(os.path.getsize(path), MAX_CHECKPOINT_BYTES, path, "prior checkpoint")
    where = f"prior checkpoint {path!r}"
    try:
        with zipfile.ZipFile(path) as archive:
            names = set(archive.namelist())
            missing = {"data", "policy.pth"} - names
            if missing:
                raise _fail(
                    path,
                    f"not a SB3 checkpoint: missing {sorted(missing)} in the zip (truncated or "
                    "corrupt, or another kind of file)",
                )
            data = parse_json(
                read_member(archive, "data", MAX_JSON_BYTES, where), f"{where}: the 'data' part"
            )
            member_sizes(archive, ["policy.pth"], MAX_WEIGHTS_BYTES, where)
            with archive.open("policy.pth") as f:
                state_dict = th.load(f, map_location="cpu", weights_only=True)
    except ZIP_DAMAGE as e:
        raise _fail(path, "not a zip file (expected an SB3 .zip checkpoint)") from e
    except (RuntimeError, EOFError, OSError, pickle.UnpicklingError, KeyError) as e:
        # weights_only=True refuses any pickled object that is not a tensor / plain container
        raise _fail(path, f"policy.pth is not a plain tensor state dict, refused ({e})") from e
    if not isinstance(data, dict):
        raise _fail(path, "the 'data' part is not a JSON object")
    if not isinstance(state_dict, dict) or not all(
        isinstance(k, str) and isinstance(v, th.Tensor) for k, v in state_dict.items()
    ):
        raise _fail(path, "policy.pth is not a state dict of tensors")
    return data, state_dict


def load_prior(path: str | os.PathLike[str]) -> PriorCheckpoint:
    """Read a ``DiscreteSAC`` or ``DQN`` checkpoint as prior columns, never unpickling code."""
    path = os.fspath(path)
    data, sd = read_zip(path)
    if "observation_space" not in data:
        raise _fail(path, "the 'data' part has no observation_space (not an SB3 checkpoint)")
    obs = obs_spec_from_saved(data["observation_space"], f"prior checkpoint {path!r}")
    n_actions = _n_actions(data, path)
    activation = _activation(data, path)
    extractor = [
        k for k in sd if ".features_extractor." in k or k.startswith("features_extractor.")
    ]
    if extractor:
        raise _fail(
            path,
            f"its features extractor has weights ({extractor[0]}, ...); only parameter-free "
            "Flatten/Combined extractors of Box observations are supported",
        )
    if any(k.startswith("q_net.q_net.") for k in sd):
        algo = "dqn"
        actor_layers = _chain(sd, "q_net.q_net.", path)
        critic_layers = [actor_layers]
    elif any(k.startswith("actor.latent_pi.") or k == "actor.action_logits.weight" for k in sd):
        algo = "dsac"
        if "actor.action_logits.weight" not in sd:
            raise _fail(path, "DiscreteSAC policy without actor.action_logits")
        hidden = (
            _chain(sd, "actor.latent_pi.", path)
            if any(k.startswith("actor.latent_pi.") for k in sd)
            else []
        )
        actor_layers = hidden + [(sd["actor.action_logits.weight"], sd["actor.action_logits.bias"])]
        n_q = sorted(
            {int(m.group(1)) for k in sd if (m := re.match(r"critic\.q_networks\.(\d+)\.", k))}
        )
        if not n_q:
            raise _fail(path, "DiscreteSAC policy without critic.q_networks")
        critic_layers = [_chain(sd, f"critic.q_networks.{i}.", path) for i in n_q]
    else:
        raise _fail(
            path,
            "expected the policy of a DiscreteSAC (actor.latent_pi / actor.action_logits / "
            "critic.q_networks) or SB3 DQN (q_net.q_net) checkpoint; policy.pth has keys "
            f"{sorted(sd)[:6]}",
        )
    for name, layers in [("actor", actor_layers)] + [
        (f"critic {i}", c) for i, c in enumerate(critic_layers)
    ]:
        _check_layers(layers, name, path)
        if layers[0][0].shape[1] != obs.flat_dim:
            raise _fail(
                path,
                f"{name}'s first Linear takes {layers[0][0].shape[1]} inputs but the saved "
                f"observation space {obs.describe()} flattens to {obs.flat_dim}",
            )
        if layers[-1][0].shape[0] != n_actions:
            raise _fail(
                path,
                f"{name}'s output layer has {layers[-1][0].shape[0]} units but the action space "
                f"has {n_actions} actions",
            )
    spec = PriorSpec(
        algo=algo,
        obs=obs,
        n_actions=n_actions,
        actor=_column_spec(actor_layers, activation),
        critics=tuple(_column_spec(c, activation) for c in critic_layers),
        source=os.path.basename(path),
    )
    detach = [[(w.detach().clone(), b.detach().clone()) for w, b in c] for c in critic_layers]
    return PriorCheckpoint(
        spec, [(w.detach().clone(), b.detach().clone()) for w, b in actor_layers], detach
    )


def trained_env_id(path: str | os.PathLike[str]) -> str | None:
    """The env id a prior checkpoint says it was trained on (the ``env`` entry of a
    :class:`sb3_pnn.DiscreteSAC` checkpoint's JSON member); None when it does not say (a plain
    SB3 checkpoint, or one saved without a registered env)."""
    path = os.fspath(path)
    where = f"prior checkpoint {path!r}"
    try:
        with zipfile.ZipFile(path) as archive:
            if "sb3_pnn.json" not in archive.namelist():
                return None
            meta = parse_json(read_member(archive, "sb3_pnn.json", MAX_JSON_BYTES, where), where)
    except ZIP_DAMAGE as e:
        raise _fail(path, "not a zip file (expected an SB3 .zip checkpoint)") from e
    env = meta.get("env") if isinstance(meta, dict) else None
    env_id = env.get("id") if isinstance(env, dict) else None
    return env_id if isinstance(env_id, str) else None
