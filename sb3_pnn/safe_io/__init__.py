"""Pickle-free checkpoints: DiscreteSAC models and replay buffers that load without running code.

Project rule: loading a checkpoint never unpickles (executes) anything from it. SB3 stores the
hyperparameters, spaces and policy class of a model as cloudpickle blobs in the zip's ``data``
part and pickles whole replay buffers; both run arbitrary code when loaded. This package writes
everything needed to rebuild a :class:`sb3_pnn.DiscreteSAC` as JSON (:mod:`.checkpoint`), with
classes named through allowlists (:mod:`.json_codec`, :mod:`.policy_registry`) and spaces through
a small codec (:mod:`.spaces_codec`), and replay buffers as plain numpy arrays
(:mod:`.replay_buffer_io`).
"""

from sb3_pnn.safe_io.json_codec import register_safe_class
from sb3_pnn.safe_io.policy_registry import get_policy_class, register_policy_class
from sb3_pnn.safe_io.spaces_codec import space_from_json, space_to_json

__all__ = [
    "get_policy_class",
    "register_policy_class",
    "register_safe_class",
    "space_from_json",
    "space_to_json",
]
