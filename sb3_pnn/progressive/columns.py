"""Columns of a progressive network (paper eq. 13 and 15, Rusu et al. 2016).

:class:`FrozenColumn` is a prior column: an MLP whose weights are *buffers*, not parameters, so no
optimizer, Polyak update or gradient clipping can reach them (they are in the state dict, so
they travel inside a saved model), and whose ``train()`` always leaves it in eval mode.

:class:`ProgressiveNet` is the trainable column k with its lateral adapters. For hidden layer
i = 1..L and the output layer L+1 of the new column (eq. 13)::

    z_i = own_weight * W_i h_{i-1}^{(k)}
          + sum_{j<k} c_j(s) * alpha_i^{(j)} * U_i^{(k:j)} h_{i-1}^{(j)} + b_i
    h_i^{(k)} = f(z_i)    (no f on the output layer)

* h_0^{(k)} is the new observation (flattened); there is no lateral at the input layer (i = 1),
  since the priors' inputs are observations too.
* U_i^{(k:j)} is a bias-free ``Linear`` from the width of prior j's hidden layer i-1 to the width
  of layer i of the new column, so columns may have different widths. The output layer gets
  laterals from each prior's *last* hidden layer; a prior with fewer hidden layers than the new
  column feeds only the layers it has (plus the output layer).
* alpha_i^{(j)} is Rusu et al.'s learned scalar per lateral (``learn_lateral_scale=True``,
  initialised to ``lateral_scale_init``); with ``False`` it is the constant 1, eq. 13 exactly.
* c_j(s) (B, 1) and own_weight are 1 for the PNN. The SPNN (eq. 15) sets own_weight = tau and
  c_j(s) = sigma * g_j(s) with the gate weights g(s) of :mod:`.gates` (see
  :mod:`.selective_policy` for the reading of eq. 15).
* Starting as the priors (``output_lateral_bias=True``, then
  :meth:`ProgressiveNet.start_as_priors_`; not in the paper or in Rusu et al., whose new column
  starts at random): the output layer's
  laterals get a bias and copy each prior's own output layer (weight and bias, divided by the
  constant part m of c_j), and the new column's own output weights and bias start at zero, so
  that before any update the column's output is sum_j g_j(s) * (prior j's own output): the
  prior's logits or Q-values for a PNN with one prior, the selected prior's for the SPNN's hard
  gate. The hidden layers start at random as before; they get gradients once the own output
  weights have moved from zero (the residual "zero-initialised head" of fine-tuning).

The prior columns are evaluated under ``torch.no_grad()``: nothing upstream of them is trained.
"""

from __future__ import annotations

from collections.abc import Sequence

import torch as th
import torch.nn.functional as F
from torch import nn

from sb3_pnn.progressive.prior_loading import ACTIVATIONS, ColumnSpec, Layers


def activation_name(activation_fn: type[nn.Module]) -> str:
    """The name under which ``activation_fn`` is in :data:`ACTIVATIONS` (``ValueError`` if not)."""
    for name, cls in ACTIVATIONS.items():
        if activation_fn is cls:
            return name
    raise ValueError(
        f"activation_fn {activation_fn!r} is not supported in progressive columns; "
        f"expected one of torch.nn.{sorted(ACTIVATIONS)}"
    )


class FrozenColumn(nn.Module):
    """A frozen prior column built from a :class:`ColumnSpec`; :meth:`load_layers` fills it."""

    def __init__(self, spec: ColumnSpec):
        super().__init__()
        self.spec = spec
        self.activation = ACTIVATIONS[spec.activation]()
        sizes = [spec.in_dim, *spec.hidden, spec.out_dim]
        self.n_layers = len(sizes) - 1
        for i in range(self.n_layers):
            self.register_buffer(f"weight_{i}", th.zeros(sizes[i + 1], sizes[i]))
            self.register_buffer(f"bias_{i}", th.zeros(sizes[i + 1]))
        self._hidden_names = [(f"weight_{i}", f"bias_{i}") for i in range(self.n_layers - 1)]
        super().train(False)

    def train(self, mode: bool = True) -> FrozenColumn:
        """Always eval mode: a prior column never behaves as in training (no dropout/BN updates)."""
        return super().train(False)

    def layer(self, i: int) -> tuple[th.Tensor, th.Tensor]:
        return getattr(self, f"weight_{i}"), getattr(self, f"bias_{i}")

    @th.no_grad()
    def load_layers(self, layers: Layers) -> None:
        """Copy checkpoint (W, b) pairs in, checking every shape."""
        if len(layers) != self.n_layers:
            raise ValueError(f"expected {self.n_layers} layers for {self.spec}, got {len(layers)}")
        for i, (w, b) in enumerate(layers):
            mw, mb = self.layer(i)
            if tuple(w.shape) != tuple(mw.shape) or tuple(b.shape) != tuple(mb.shape):
                raise ValueError(
                    f"layer {i}: checkpoint weight {tuple(w.shape)} / bias {tuple(b.shape)} do not "
                    f"fit the column {tuple(mw.shape)} / {tuple(mb.shape)}"
                )
            mw.copy_(w)
            mb.copy_(b)

    @th.no_grad()
    def hidden(self, x: th.Tensor) -> list[th.Tensor]:
        """Hidden activations [h_1, ..., h_L] of the column for input x (B, in_dim)."""
        # the buffers by name (``.to()`` replaces them) and the activation's forward without
        # the module call: what self.layer(i) and self.activation(...) give, read faster
        buffers = self._buffers
        activation = self.activation.forward
        out = []
        h = x
        for weight_name, bias_name in self._hidden_names:
            h = activation(F.linear(h, buffers[weight_name], buffers[bias_name]))
            out.append(h)
        return out

    @th.no_grad()
    def forward(self, x: th.Tensor) -> th.Tensor:
        """The column's own output (logits or Q-values) for input x."""
        return self.output(self.hidden(x), x)

    @th.no_grad()
    def output(self, hidden: Sequence[th.Tensor], x: th.Tensor) -> th.Tensor:
        """The column's own output from its hidden activations ``hidden`` (:meth:`hidden`) for
        input x (which only a column without hidden layers reads)."""
        return F.linear(hidden[-1] if len(hidden) else x, *self.layer(self.n_layers - 1))


class ProgressiveNet(nn.Module):
    """The trainable column k plus its lateral adapters (module docstring, eq. 13).

    :param in_dim: Size of the new (flattened) observation h_0^{(k)}
    :param hidden: Hidden widths of the new column
    :param out_dim: Output size (n_actions)
    :param activation_fn: Non-linearity f of the hidden layers
    :param priors: The frozen prior columns j < k
    :param learn_lateral_scale: Learn Rusu et al.'s scalar alpha per lateral
    :param lateral_scale_init: Initial alpha
    :param output_lateral_bias: The output layer's laterals have a bias (to hold a prior's own
        output bias after :meth:`start_as_priors_`)
    """

    def __init__(
        self,
        in_dim: int,
        hidden: Sequence[int],
        out_dim: int,
        activation_fn: type[nn.Module],
        priors: Sequence[FrozenColumn],
        learn_lateral_scale: bool = True,
        lateral_scale_init: float = 1.0,
        output_lateral_bias: bool = False,
    ):
        super().__init__()
        self.priors = nn.ModuleList(priors)
        sizes = [in_dim, *hidden, out_dim]
        self.layers = nn.ModuleList(
            nn.Linear(sizes[i], sizes[i + 1]) for i in range(len(sizes) - 1)
        )
        self.activation = activation_fn()
        n_out = len(self.layers)
        # source[i][j]: index of prior j's hidden layer feeding layer i (None: no lateral)
        self.sources: list[list[int | None]] = []
        self.laterals = nn.ModuleDict()
        for i in range(n_out):
            row: list[int | None] = []
            for j, prior in enumerate(priors):
                n_hidden = len(prior.spec.hidden)
                if i == 0 or n_hidden == 0:
                    src = None
                elif i == n_out - 1:
                    src = n_hidden - 1
                else:
                    src = i - 1 if i - 1 < n_hidden else None
                row.append(src)
                if src is not None:
                    self.laterals[f"{i}_{j}"] = nn.Linear(
                        prior.spec.hidden[src],
                        sizes[i + 1],
                        bias=output_lateral_bias and i == n_out - 1,
                    )
            self.sources.append(row)
        # per layer, the laterals that feed it: (prior j, its hidden layer, key in laterals)
        self._lateral_plan: list[list[tuple[int, int, str]]] = [
            [(j, src, f"{i}_{j}") for j, src in enumerate(row) if src is not None]
            for i, row in enumerate(self.sources)
        ]
        n_priors = max(len(priors), 1)
        scale = th.full((n_out, n_priors), float(lateral_scale_init))
        if learn_lateral_scale:
            self.lateral_scale = nn.Parameter(scale)
        else:
            self.register_buffer("lateral_scale", scale)

    def prior_hidden(self, prior_inputs: Sequence[th.Tensor]) -> list[list[th.Tensor]]:
        """Hidden activations of every prior column, each fed its own input."""
        return [col.hidden(x) for col, x in zip(self.priors, prior_inputs, strict=True)]

    def forward(
        self,
        x: th.Tensor,
        prior_hidden: Sequence[Sequence[th.Tensor]],
        lateral_weights: th.Tensor | None = None,
        own_weight: float = 1.0,
    ) -> th.Tensor:
        """Output of column k. ``lateral_weights`` (B, n_priors) are the c_j(s) (1 if None)."""
        # A fixed (not learned) alpha of exactly 1 is skipped: x * 1.0 == x in floating point,
        # so the output is the same bit for bit, without two tensor operations per lateral.
        scale = self.lateral_scale
        fixed = None if scale.requires_grad or scale.device.type != "cpu" else scale.tolist()
        weight_of = (
            None
            if lateral_weights is None
            else [lateral_weights[:, j : j + 1] for j in range(lateral_weights.shape[1])]
        )
        # F.linear with the modules' own tensors is what nn.Linear.__call__ computes, without
        # the module-call machinery (no hooks are used on these layers), as is .forward below
        activation = self.activation.forward
        laterals = self.laterals
        h = x
        last = len(self.layers) - 1
        for i, layer in enumerate(self.layers):
            z = (
                F.linear(h, layer.weight, layer.bias)
                if own_weight == 1.0
                else own_weight * F.linear(h, layer.weight) + layer.bias
            )
            for j, src, key in self._lateral_plan[i]:
                lateral = laterals[key]
                lat = F.linear(prior_hidden[j][src], lateral.weight, lateral.bias)
                if fixed is None or fixed[i][j] != 1.0:
                    lat = scale[i, j] * lat
                if weight_of is not None:
                    lat = weight_of[j] * lat
                z = z + lat
            h = activation(z) if i < last else z
        return h

    @th.no_grad()
    def start_as_priors_(self, multiplier: float = 1.0, only: int | None = None) -> None:
        """Make the output equal sum_j (c_j(s) / multiplier) * (prior j's own output) before any
        update (module docstring): the output laterals copy the priors' output layers divided by
        ``multiplier`` (the constant part of c_j: 1 for the PNN, sigma for the SPNN), their scale
        alpha is set to 1, and the own output weights and bias to 0. Needs
        ``output_lateral_bias=True`` and priors with hidden layers and this column's output size.
        With ``only=j`` the output starts as prior j's alone: the other priors' output laterals
        start at zero weight and bias (scale 1, so that they learn from there).
        """
        last = len(self.layers) - 1
        if not self.priors:
            raise ValueError("start_as_priors_ needs prior columns; this column has none")
        if only is not None and not 0 <= only < len(self.priors):
            raise ValueError(
                f"only={only!r} is not allowed: expected None or a prior index in "
                f"[0, {len(self.priors) - 1}]"
            )
        if not multiplier > 0:
            raise ValueError(f"multiplier must be > 0, got {multiplier!r}")
        own = self.layers[last]
        output_laterals = {j: self.laterals[key] for j, _, key in self._lateral_plan[last]}
        for j, prior in enumerate(self.priors):
            lateral = output_laterals.get(j)
            if lateral is None or lateral.bias is None:
                raise ValueError(
                    f"prior {j} cannot be copied into the output layer: it needs hidden layers "
                    "and the column output_lateral_bias=True"
                )
            weight, bias = prior.layer(prior.n_layers - 1)
            if tuple(weight.shape) != tuple(lateral.weight.shape):
                raise ValueError(
                    f"prior {j}'s output layer {tuple(weight.shape)} does not fit this column's "
                    f"output lateral {tuple(lateral.weight.shape)} (a different number of "
                    "actions?)"
                )
            if only is None or j == only:
                lateral.weight.copy_(weight / multiplier)
                lateral.bias.copy_(bias / multiplier)
            else:
                lateral.weight.zero_()
                lateral.bias.zero_()
            self.lateral_scale[last, j] = 1.0
        own.weight.zero_()
        own.bias.zero_()

    def zero_laterals_(self) -> None:
        """Set every U to zero (column k then ignores the priors); for tests and ablations."""
        with th.no_grad():
            for lat in self.laterals.values():
                lat.weight.zero_()
