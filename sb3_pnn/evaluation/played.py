"""A trained model played as the study plays it: SPNN's switch with a memory
(:class:`sb3_pnn.progressive.SwitchMemory`) and / or without immediate turn reversals
(:class:`sb3_pnn.evaluation.NoReversal`); training and the saved policy are unchanged.

One place for the order of the wrappers (the memory decides the gate, NoReversal then filters
the action) and for the errors, which name the command-line options that ask for them
(``--switch-memory H`` and ``--no-reversal`` in ``python -m sb3_pnn.evaluate`` and
``python -m sb3_pnn.enjoy``)."""

from __future__ import annotations

from typing import Any


def played_through(
    policy: Any, switch_memory: float | None = None, no_reversal: bool = False
) -> Any:
    """``policy`` through a switch memory of ``switch_memory`` metres (None: none), then through
    NoReversal where ``no_reversal``; the policy itself when neither is asked.

    :raises ValueError: naming the option, for a policy the wrapper cannot play (a model without
        SPNN's distance gate for the memory; a PID baseline's name or a policy over other actions
        for NoReversal)
    """
    if switch_memory is not None:
        from sb3_pnn.progressive.switch_memory import SwitchMemory

        try:
            policy = SwitchMemory(policy, hysteresis=switch_memory)
        except ValueError as error:
            raise ValueError(f"--switch-memory {switch_memory}: {error}") from None
    if no_reversal:
        if isinstance(policy, str):
            raise ValueError(
                f"--no-reversal needs a trained model's zip; got the baseline {policy!r}"
            )
        from sb3_pnn.evaluation.no_reversal import NoReversal

        try:
            policy = NoReversal(policy)
        except ValueError as error:
            raise ValueError(f"--no-reversal: {error}") from None
    return policy
