"""The registry of rov_envs tasks (paper section 4.2.1, plus the tasks the paper leaves open).

Each task is a :class:`TaskSpec`: which path the vehicle follows, which reward (eq. 18, eq. 19 or
the obstacle-avoidance progress reward), which observation parts it exposes and where its obstacles
come from (none, a fixed list from the paper, or a generator in :mod:`rov_envs.sim.layouts` drawn
afresh
each episode from the environment's seed). Every value here is a default that keyword arguments at
``gymnasium.make`` may override (see :mod:`rov_envs.sim.config`).
"""

from __future__ import annotations

from dataclasses import dataclass

from rov_envs.physics.guidance import SINE_AMPLITUDE, SINE_WAVELENGTH

# Path kinds (kernel codes).
PATH_STRAIGHT = 0
PATH_SINE = 1
# Reward kinds (kernel codes): eq. 18, eq. 19, progress toward the goal (ObstacleAvoidance).
REWARD_STRAIGHT = 0
REWARD_SINE = 1
REWARD_PROGRESS = 2

#: The tasks' definition revision: raised whenever a task's observation, reward or ending
#: changes, so that stored results made on an older definition are never reused as if current
#: (sb3_pnn.reproduce hashes it into every run's configuration). 2: ObstacleAvoidance measures
#: a_c from the bearing to the goal. 3: the "goal" observation part (ObstacleAvoidance observes
#: it instead of "path", the planning tasks beside "path"), the goal a route point 25 m ahead,
#: and the planning tasks' heading rule read from it. 4: the step that reaches the end is a
#: success even when the heading rule would fail it (a vehicle passing beside the target saw
#: the target's bearing swing past 90 deg), and the goal D m ahead follows the route continued
#: past its end instead of jumping to the target.
TASKS_REVISION = 4

#: The default goal of the "goal" part and of the goal heading rule: the route point this many
#: metres further along x than the closest one (the route continued past its end).
GOAL_DISTANCE = 25.0

#: Heading references of a_c (``TaskSpec.heading_reference``, env argument ``heading_reference``).
HEADING_REFERENCES = ("path", "goal")

#: The paper's straight-task obstacles (section 4.2.1), (x, y, radius) in metres.
PAPER_STRAIGHT_OBSTACLES = (
    (66.0, -2.5, 1.5),
    (80.0, 20.0, 1.5),
    (118.0, -20.0, 1.5),
    (132.0, 2.5, 1.5),
)
#: The paper's sine-task obstacles (section 4.2.1).
PAPER_SINE_OBSTACLES = ((30.0, 17.5, 1.5), (90.0, -12.5, 1.5))


@dataclass(frozen=True)
class TaskSpec:
    """Defaults of one task.

    Attributes:
        name: registered name without namespace/version, e.g. ``"PlanningStraight"``.
        path_kind: ``PATH_STRAIGHT`` (line from (0, 0) to (length, 0)) or ``PATH_SINE``
            (y = amplitude * sin(2 pi x / wavelength), 0 <= x <= length).
        reward_kind: ``REWARD_STRAIGHT`` (eq. 18), ``REWARD_SINE`` (eq. 19) or ``REWARD_PROGRESS``.
        d_L: the corridor half-width of eq. 18, 19 and 21 (m).
        length: path length along x (m).
        amplitude, wavelength: sine shape (m); ignored by straight paths.
        layout: ``"none"``, ``"fixed"`` or the name of a generator in :mod:`rov_envs.sim.layouts`.
        obstacles: the fixed obstacles when ``layout == "fixed"``.
        sonar: whether the observation has the "sonar" part.
        heading_reference: what the heading deviation a_c (observation, and eq. 21's
            |a_c| >= pi/2 failure) is measured from: ``"path"``, the LOS course of eq. 16
            (lookahead 5 m), or ``"goal"``, the bearing from the vehicle to the target point.
        path_obs, goal_obs: whether the observation has the "path" part [a_c / pi, g / d_L]
            and the "goal" part [deviation from the bearing to the goal / pi] by default.
        heading_rule: what eq. 21's heading failure reads (None: ``heading_reference``'s a_c;
            ``"goal"``: the deviation from the goal's bearing).
        goal_distance: the goal of the "goal" part: the route point this many metres ahead
            (None: the target point).
    """

    name: str
    path_kind: int
    reward_kind: int
    d_L: float
    length: float
    layout: str = "none"
    obstacles: tuple[tuple[float, float, float], ...] = ()
    amplitude: float = SINE_AMPLITUDE
    wavelength: float = SINE_WAVELENGTH
    sonar: bool = False
    heading_reference: str = "path"
    path_obs: bool = True
    goal_obs: bool = False
    heading_rule: str | None = None
    goal_distance: float | None = GOAL_DISTANCE


#: What the planning tasks share beyond the paper (TASKS_REVISION 3): the "goal" part beside
#: "path", so that an obstacle-avoidance column reads what it was trained on, and eq. 21's
#: heading rule read from the goal, so that a detour around obstacles is not a failure.
PLANNING: dict[str, object] = {"goal_obs": True, "heading_rule": "goal"}

TASKS: dict[str, TaskSpec] = {
    spec.name: spec
    for spec in (
        TaskSpec("PathFollowingStraight", PATH_STRAIGHT, REWARD_STRAIGHT, 30.0, 200.0),
        TaskSpec("PathFollowingSine", PATH_SINE, REWARD_SINE, 15.0, 120.0),
        TaskSpec(
            "ObstacleAvoidance",
            PATH_STRAIGHT,
            REWARD_PROGRESS,
            30.0,
            60.0,
            layout="avoidance",
            sonar=True,
            heading_reference="goal",
            path_obs=False,
            goal_obs=True,
        ),
        TaskSpec(
            "PlanningStraight",
            PATH_STRAIGHT,
            REWARD_STRAIGHT,
            30.0,
            200.0,
            layout="fixed",
            obstacles=PAPER_STRAIGHT_OBSTACLES,
            sonar=True,
            **PLANNING,
        ),
        TaskSpec(
            "PlanningSine",
            PATH_SINE,
            REWARD_SINE,
            15.0,
            120.0,
            layout="fixed",
            obstacles=PAPER_SINE_OBSTACLES,
            sonar=True,
            **PLANNING,
        ),
        TaskSpec(
            "PlanningStraightUniform",
            PATH_STRAIGHT,
            REWARD_STRAIGHT,
            30.0,
            200.0,
            layout="uniform",
            sonar=True,
            **PLANNING,
        ),
        TaskSpec(
            "PlanningStraightDense",
            PATH_STRAIGHT,
            REWARD_STRAIGHT,
            30.0,
            200.0,
            layout="dense",
            sonar=True,
            **PLANNING,
        ),
        TaskSpec(
            "PlanningSineDense",
            PATH_SINE,
            REWARD_SINE,
            15.0,
            120.0,
            layout="sine_dense",
            sonar=True,
            **PLANNING,
        ),
    )
}

#: The registered ids, in the table order of the README.
ENV_IDS: tuple[str, ...] = tuple(f"rov_envs/{name}-v0" for name in TASKS)


def task_of_env(env_id: str) -> TaskSpec:
    """The task behind an environment id: ``"rov_envs/PlanningSine-v0"`` (or without the
    namespace, ``"PlanningSine-v0"``) -> ``TASKS["PlanningSine"]``; ValueError naming the id
    and the known tasks otherwise."""
    name = str(env_id).split("/")[-1].rsplit("-v", 1)[0]
    if name not in TASKS:
        raise ValueError(f"env {env_id!r} is not an rov_envs task: expected one of {list(TASKS)}")
    return TASKS[name]
