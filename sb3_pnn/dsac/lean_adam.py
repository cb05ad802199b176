"""``torch.optim.Adam(fused=True)`` with a lean ``step()`` and ``zero_grad()``, bit for bit.

DiscreteSAC steps two or three small optimizers per gradient step. With small networks most of
PyTorch's ``Adam.step()`` is spent around the fused kernel (profiler records, hooks, the dynamo
guard, grouping tensors by device and dtype; ``bench/lean_overheads.py`` measures it).
:class:`LeanFusedAdam` calls
the same ``torch._fused_adam_`` kernel with the same arguments in the same order as
``torch.optim.adam._fused_adam`` does, so parameters and optimizer state are bit-identical to
``torch.optim.Adam(fused=True)`` (tested); it falls back to Adam's own ``step()`` whenever the
lean path would not be exactly that: a closure, step hooks, a parameter without state yet (the
first step initialises it), AMSGrad, ``capturable`` / ``differentiable``, a tensor learning rate,
grad scaling, or parameters of several devices or dtypes. The state dict is Adam's.
"""

from __future__ import annotations

from typing import Any

import torch as th
from torch.optim import Adam, Optimizer
from torch.optim import optimizer as _optimizer_module

# Adam's step() with PyTorch's profiler records and step hooks (the wrapper every optimizer
# class gets on its first instance), used for every step the lean path does not take
_ADAM_STEP = (
    Adam.step if getattr(Adam.step, "hooked", False) else Optimizer.profile_hook_step(Adam.step)
)


class LeanFusedAdam(Adam):
    """``Adam(..., fused=True)`` (see the module docstring); refuses ``fused=False``."""

    def __init__(self, params: Any, **kwargs: Any) -> None:
        if not kwargs.get("fused"):
            raise ValueError(f"LeanFusedAdam needs fused=True, got fused={kwargs.get('fused')!r}")
        super().__init__(params, **kwargs)

    def _lean_lists(self) -> list[tuple[dict, list, list, list, list, list]] | None:
        """Per group: (group, params, grads, exp_avgs, exp_avg_sqs, steps) of the parameters
        with a gradient, as Adam's ``_init_group`` lists them; None if the lean path does not
        apply to this step."""
        if (
            self._optimizer_step_pre_hooks
            or self._optimizer_step_post_hooks
            or _optimizer_module._global_optimizer_pre_hooks
            or _optimizer_module._global_optimizer_post_hooks
            or getattr(self, "grad_scale", None) is not None
            or getattr(self, "found_inf", None) is not None
        ):
            return None
        state = self.state
        lists = []
        device = dtype = None
        for group in self.param_groups:
            if (
                group["amsgrad"]
                or group["capturable"]
                or group["differentiable"]
                or not group["fused"]
                or isinstance(group["lr"], th.Tensor)
            ):
                return None
            params, grads, exp_avgs, exp_avg_sqs, steps = [], [], [], [], []
            for p in group["params"]:
                grad = p.grad
                if grad is None:
                    continue
                p_state = state.get(p)
                if not p_state or "exp_avg_sq" not in p_state or grad.is_sparse or p.is_complex():
                    return None
                if device is None:
                    device, dtype = p.device, p.dtype
                elif p.device != device or p.dtype != dtype:
                    return None
                params.append(p)
                grads.append(grad)
                exp_avgs.append(p_state["exp_avg"])
                exp_avg_sqs.append(p_state["exp_avg_sq"])
                steps.append(p_state["step"])
            lists.append((group, params, grads, exp_avgs, exp_avg_sqs, steps))
        return lists

    def step(self, closure: Any = None) -> Any:  # type: ignore[override]
        """One Adam step: the fused kernel called directly, or Adam's own (module docstring)."""
        lists = None if closure is not None else self._lean_lists()
        if lists is None:
            return _ADAM_STEP(self, closure)
        with th.no_grad():
            for group, params, grads, exp_avgs, exp_avg_sqs, steps in lists:
                if not params:
                    continue
                beta1, beta2 = group["betas"]
                th._foreach_add_(steps, 1)
                fused = th._fused_adamw_ if group["decoupled_weight_decay"] else th._fused_adam_
                fused(
                    params,
                    grads,
                    exp_avgs,
                    exp_avg_sqs,
                    [],
                    steps,
                    amsgrad=False,
                    lr=group["lr"],
                    beta1=float(beta1),
                    beta2=float(beta2),
                    weight_decay=group["weight_decay"],
                    eps=group["eps"],
                    maximize=group["maximize"],
                    grad_scale=None,
                    found_inf=None,
                )
        return None

    # Adam's profiler wrapper is not put around this step (the fallback above carries it)
    step.hooked = True  # type: ignore[attr-defined]

    def zero_grad(self, set_to_none: bool = True) -> None:
        """``Optimizer.zero_grad`` without its profiler record: gradients set to None (default),
        or zeroed in place as Optimizer does with ``set_to_none=False``."""
        if not set_to_none:
            super().zero_grad(set_to_none=False)
            return
        for group in self.param_groups:
            for p in group["params"]:
                p.grad = None
