"""The tasks' left-right mirror symmetry, as data a learner can use to augment its samples.

The BlueROV2 model, the thruster layout, the sonar and the paths are symmetric about the
vehicle's vertical x-z plane: reflecting a task in y -> -y (the obstacles' y, the sine path's
amplitude, the start heading) and swapping each turn of Table 1 for the same turn the other way
gives the same episode reflected, with the same rewards. In the observation that reflection
negates every signed quantity (the heading deviations a_c and from the goal, the distance g from
the path, the sway v and yaw rate r) and reverses the sonar's sectors (ordered from the
vehicle's right to its left). ``tests/rov_envs/sim/test_symmetry.py`` checks that the simulator
keeps this up to rounding.

:data:`LEFT_RIGHT_MIRROR` is the map in the form ``sb3_pnn.DiscreteSAC(mirror=...)`` takes:
``"actions"``, the index of each discrete action's mirror image (an involution), and
``"observations"``, per observation part, ``"negate"`` or ``"reverse"``.
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Any

__all__ = ["LEFT_RIGHT_MIRROR", "MIRRORED_ACTIONS", "MIRRORED_PARTS"]

#: Action i's mirror image (Table 1: 0 Turn left 1 <-> 3 Turn right 1, 1 Turn left 2 <->
#: 4 Turn right 2, 2 Go straight stays).
MIRRORED_ACTIONS: tuple[int, ...] = (3, 4, 2, 0, 1)

#: How each observation part changes under the reflection.
MIRRORED_PARTS: MappingProxyType[str, str] = MappingProxyType(
    {
        "path": "negate",  # [a_c / pi, g / d_L]
        "goal": "negate",  # [deviation from the goal's bearing / pi(, g / d_L)]
        "sonar": "reverse",  # sectors right to left become left to right
        "motion": "negate",  # [v, r]
    }
)


#: The discrete tasks' mirror map for ``DiscreteSAC(mirror=LEFT_RIGHT_MIRROR)``, in plain
#: lists and dicts, as a checkpoint or a YAML file holds it.
LEFT_RIGHT_MIRROR: dict[str, Any] = {
    "actions": list(MIRRORED_ACTIONS),
    "observations": dict(MIRRORED_PARTS),
}
