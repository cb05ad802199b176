"""Start a new network from a prior column's weights (SAC-Multi; PNN's ``init_from_prior``).

The new task's observation may hold more than the prior's (e.g. the sonar, for a path-following
prior): the first layer copies the prior's weights into the columns of the prior's inputs and
gets zero weights on the others, so that the copy outputs exactly what the prior outputs on
every new observation.
"""

from __future__ import annotations

import torch as th

from sb3_pnn.progressive.obs_spec import ObsSpec
from sb3_pnn.progressive.prior_loading import Layers


def input_columns(prior_keys: tuple[str | None, ...], new: ObsSpec) -> list[int]:
    """Indices in the new flattened observation of each of the prior's input features."""
    offsets: dict[str | None, range] = {}
    start = 0
    for part in new.parts:
        offsets[part.key] = range(start, start + part.size)
        start += part.size
    return [i for key in prior_keys for i in offsets[key]]


def copy_layers(linears: list[th.nn.Linear], layers: Layers, columns: list[int]) -> None:
    """Copy the prior's ``layers`` into ``linears`` (the first layer into ``columns`` only)."""
    if len(linears) != len(layers):
        raise ValueError(f"expected {len(layers)} Linear layers, found {len(linears)}")
    with th.no_grad():
        for i, (lin, (w, b)) in enumerate(zip(linears, layers, strict=True)):
            if i == 0:
                lin.weight.zero_()
                lin.weight[:, columns] = w.to(lin.weight)
            else:
                lin.weight.copy_(w)
            lin.bias.copy_(b)
