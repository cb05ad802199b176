"""The per-control-step numba kernels shared by the single and the batched environments.

One call of :func:`step_batch` (or :func:`step_batch_parallel`) advances N vehicles by one control
period: the actions become thruster commands, the physics advances each block of
``integrator.LANES`` vehicles with SIMD code (:mod:`rov_envs.physics.integrator`), then each
vehicle runs LOS guidance (eq. 16, :mod:`rov_envs.physics.guidance`), its sonar
(:mod:`rov_envs.physics.sonar`), the rewards (eq. 17-21, :mod:`rov_envs.sim.rewards`) and the ending
tests, and, if asked, starts its next episode (layout, start pose and noise drawn from its own
random stream, :mod:`rov_envs.sim.random_stream`) without returning to Python. A single environment
calls the same kernel with N = 1, so N batched vehicles and N single environments with the same
seeds produce the same numbers bit for bit.

Autoreset modes: ``MODE_PLAIN`` (none: single env, evaluation), ``MODE_NEXT_STEP`` (Gymnasium's
default: a vehicle flagged in ``pending`` is reset instead of stepped, with reward 0 and no
ending; ``pending`` then flags the vehicles that ended this step) and ``MODE_SAME_STEP`` (SB3:
a vehicle that ends is reset in the same call, its final observation copied to ``term_path`` /
``term_sonar`` / ``term_motion`` and its final reward and ending to ``final``, and flagged in
``pending``).

Per-vehicle results live in ``out`` with one row per field (``O_*``), so that each info array the
environments return is one contiguous row. The step path is compiled with ``_nrt=False``:
numba's reference counting of array arguments (atomic operations on every call of a function
taking arrays, shared between the threads) cost more than the whole task layer.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from rov_envs.physics.etd import ETD_SIZE, unpack_coefficients
from rov_envs.physics.guidance import los_tuple, wrap_to_pi
from rov_envs.physics.integrator import (
    LANES,
    ROW_CMD,
    ROW_CURRENT,
    ROW_PSI,
    ROW_Q0,
    ROW_R,
    ROW_U,
    ROW_X,
    ROW_Y,
    ROWS,
    UUV_SIMULATOR_PARAMS,
    VEHICLE_UUV_SIMULATOR,
    VEHICLE_WU2018,
    WU2018_PARAMS,
    advance_block_vehicle,
    lane_index,
)
from rov_envs.physics.params import P_SIZE, VEHICLES, vehicle_code, vehicle_params
from rov_envs.physics.sonar import _nearest, _scan
from rov_envs.physics.thrusters import continuous_pair_speeds
from rov_envs.sim.layouts import draw_layout
from rov_envs.sim.random_stream import gauss
from rov_envs.sim.rewards import (
    END_HEADING,
    END_MISSED,
    END_NONE,
    END_SUCCESS,
    END_TIME_LIMIT,
    FAILURE_REWARD,
    failure_code,
    reward_obstacle,
    reward_sine,
    reward_straight,
)

# ---- layout of the task array ``cfg`` (float64, rov_envs.sim.episode.cfg_array) ----
C_PATH = 0  # 0 straight, 1 sine (rov_envs.sim.tasks.PATH_*)
C_REWARD = 1  # rov_envs.sim.tasks.REWARD_*
C_DL = 2  # d_L (m)
C_LENGTH = 3  # path length along x (m)
C_AMP = 4  # sine amplitude (m)
C_WAVE = 5  # sine wavelength (m)
C_SPAN = 6  # sonar span S (rad)
C_RANGE = 7  # sonar range (m)
C_NOISE = 8  # sonar noise std (m)
C_DT = 9  # control period (s)
C_NSUB = 10  # integrator substeps per control period
C_MAXSTEPS = 11  # time limit in steps
C_LOOKAHEAD = 12  # LOS lookahead distance (m)
C_GOALX = 13  # target point
C_GOALY = 14
C_SONAR = 15  # 1.0 when the observation has a "sonar" part
C_TARGET_R = 16  # success radius around the target (m)
C_UREF = 17  # reference speed of the progress reward (m/s)
C_SUCCESS_R = 18  # reward added on reaching the target (our addition to eq. 21)
C_LAYOUT = 19  # rov_envs.sim.layouts.LAYOUT_CODES value; 0 = the obstacles never change
C_LAYOUT_N = 20  # that layout's obstacle count (the most it draws)
C_START_PSI = 21  # start heading: the path's tangent at the start (rad)
C_START_POS_STD = 22  # start-pose perturbation: position std (m)
C_START_HEAD_STD = 23  # start-pose perturbation: heading std (rad)
C_CURRENT_X = 24  # world-frame water velocity (m/s)
C_CURRENT_Y = 25
C_VEHICLE = 26  # vehicle code (rov_envs.physics.params.VEHICLES index): the compiled preset
C_MOTION = 27  # 1.0 when the observation has a "motion" part
C_PROGRESS_W = 28  # 0 / PROGRESS_PATH / PROGRESS_COURSE: how r_c (eq. 18/19) is weighted
C_HEADING_GOAL = 29  # 1.0: a_c is measured from the bearing to the goal, not the LOS course
C_GOAL_DIST = 30  # the goal: 0 = the target point; D > 0 = the path point D m further along x
C_RULE_GOAL = 31  # 1.0: eq. 21's |a_c| >= pi/2 rule reads the deviation from the goal's bearing
C_OBSTACLE_W = 32  # weight of eq. 20's r_v (1.0: the paper's)
C_ARRIVAL_GATE = 33  # > 0: the path's end counts as arrival only this close to the target (m)
C_ETD = 34  # ETD_SIZE: integrator.vehicle_coefficients(vehicle, dt, substeps), flattened
C_SIZE = C_ETD + ETD_SIZE

#: ``C_PROGRESS_W`` codes: r_c paid in proportion to the advance along the path's tangent, or
#: along the LOS course (the direction a_c is measured from).
PROGRESS_PATH = 1.0
PROGRESS_COURSE = 2.0

# ---- per-vehicle results and counters ``out`` (float64, shape (O_SIZE, N): one row per field,
# so that each info array is one contiguous row) ----
O_AC = 0  # heading deviation a_c (rad)
O_G = 1  # signed cross-track distance g (m)
O_D = 2  # distance to the nearest obstacle surface (m, inf without obstacles)
O_RC = 3  # r_c
O_RV = 4  # r_v
O_RT = 5  # r_terminal
O_R = 6  # total reward
O_END = 7  # end code (rov_envs.sim.rewards.END_*)
O_PROG = 8  # along-path progress (m of x of the closest path point; the sine's warm start)
O_TERM = 9  # 1.0 when terminated
O_TRUNC = 10  # 1.0 when truncated
O_X = 11  # position x, y (m)
O_Y = 12
O_PSI = 13  # heading (rad, continuous)
O_U = 14  # surge u, sway v (m/s), yaw rate r (rad/s)
O_V = 15
O_YAW_RATE = 16
O_STEPS = 17  # steps taken in this episode
O_PREV_GOAL = 18  # distance to the goal after the previous step (progress reward)
O_AGOAL = 19  # heading deviation from the bearing to the goal (rad)
O_SIZE = 20

#: Columns of the ``obs_path`` buffer: the "path" part (a_c / pi, g / d_L), then the "goal"
#: part (the heading deviation from the bearing to the target point, / pi). The environments
#: expose the parts their task observes (:attr:`rov_envs.sim.config.EnvConfig.obs_parts`).
PATH_COLUMNS = 3

MODE_PLAIN = 0
MODE_NEXT_STEP = 1
MODE_SAME_STEP = 2

# ---- a vehicle's final step in MODE_SAME_STEP, saved before its reset: ``final`` (float64,
# shape (F_SIZE, N)) ----
F_REWARD = 0
F_TERM = 1
F_TRUNC = 2
F_END = 3
F_SIZE = 4

#: Largest thruster command of the continuous mapping (rev/min), Table 1's largest.
_MAX_SPEED = 8000.0
#: Bounds of the observation's "motion" part (clipped): |sway| in m/s, |yaw rate| in rad/s. Under
#: Table 1 actions Wu's vehicle reaches 1.6 rad/s and 0.5 m/s of sway (UUV Simulator's 0.28 rad/s,
#: 0.06 m/s), and the largest current (2 m/s) adds its own sway: |v| <= 2.5 m/s.
MOTION_SWAY_LIMIT = 3.0
MOTION_YAW_RATE_LIMIT = 2.0


@njit(cache=True, _nrt=False)
def _compiled_params(vehicle, out):
    """Copy the parameters of preset ``vehicle`` compiled into this module's cached code.

    Defined here, not in ``integrator``: numba caches each module's code on its own, so only a
    probe cached with the step kernels sees the constants they were compiled with.
    """
    if vehicle == VEHICLE_UUV_SIMULATOR:
        for k in range(out.shape[0]):
            out[k] = UUV_SIMULATOR_PARAMS[k]
    elif vehicle == VEHICLE_WU2018:
        for k in range(out.shape[0]):
            out[k] = WU2018_PARAMS[k]


def check_compiled_params() -> None:
    """Refuse to run when numba's cache holds kernels compiled with other preset parameters.

    The kernels have every preset of ``params.VEHICLES`` compiled in
    (``integrator.advance_block_vehicle``); numba's cache does not notice edits to
    ``rov_envs/physics/params.py``.
    """
    compiled = np.empty(P_SIZE)
    for name in VEHICLES:  # a preset without a branch in ``_compiled_params`` stays NaN: refused
        compiled[:] = np.nan
        _compiled_params(vehicle_code(name), compiled)
        if not np.array_equal(compiled, vehicle_params(name).to_array()):
            raise RuntimeError(
                f"rov_envs: numba's cache holds physics compiled with other parameters of vehicle "
                f"{name!r} (rov_envs/physics/params.py changed); delete the __pycache__ folders "
                "under rov_envs/ (or set NUMBA_CACHE_DIR to an empty folder) and run again"
            )


@njit(cache=True, inline="always")
def _distance(dx, dy):
    """sqrt(dx^2 + dy^2) (libm's hypot guards against overflow we cannot meet, and is slow)."""
    return math.sqrt(dx * dx + dy * dy)


@njit(cache=True, inline="always")
def goal_point(cfg, progress):
    """The goal the "goal" part and the goal heading rule look at: the target point, or with
    ``C_GOAL_DIST`` = D > 0 the route point D m beyond the closest one along x, the route
    continued past its end in the same shape (so that the goal's bearing does not swing round
    as the vehicle passes beside the target)."""
    dist = cfg[C_GOAL_DIST]
    if dist <= 0.0:
        return cfg[C_GOALX], cfg[C_GOALY]
    x = progress + dist
    if cfg[C_PATH] == 1.0:
        return x, cfg[C_AMP] * math.sin(2.0 * math.pi * x / cfg[C_WAVE])
    return x, 0.0


@njit(cache=True, inline="always", _nrt=False)
def observe(i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out):
    """Guidance, obstacle distance, sonar and motion of vehicle i; fills its observation and
    ``out``.

    a_c is measured from the LOS course (eq. 16, lookahead ``C_LOOKAHEAD``), or, with
    ``C_HEADING_GOAL`` set, from the bearing to the goal point (:func:`goal_point`); the "goal"
    column always holds the deviation from that bearing. The sonar looks along the heading of
    the attitude quaternion (the body x axis projected on the horizontal plane); guidance uses
    the heading row. The
    motion part is the body-frame sway v (m/s, over ground, as the vehicle's velocity state)
    and yaw rate r (rad/s), clipped to
    +-``MOTION_SWAY_LIMIT`` / +-``MOTION_YAW_RATE_LIMIT``.
    """
    o = lane_index(i)
    x = lanes[o + ROW_X * LANES]
    y = lanes[o + ROW_Y * LANES]
    psi = lanes[o + ROW_PSI * LANES]
    # out[O_PROG, i] is read as the sine closest-point warm start, then overwritten
    a_c, g, progress = los_tuple(
        int(cfg[C_PATH]), x, y, psi, cfg[C_AMP], cfg[C_WAVE], cfg[C_LOOKAHEAD], out[O_PROG, i]
    )
    gx, gy = goal_point(cfg, progress)
    a_goal = wrap_to_pi(psi - math.atan2(gy - y, gx - x))
    if cfg[C_HEADING_GOAL] != 0.0:
        a_c = a_goal
    m = n_obs[i]
    d = _nearest(x, y, obstacles[i], m)
    obs_path[i, 0] = a_c / math.pi
    obs_path[i, 1] = min(1.0, max(-1.0, g / cfg[C_DL]))
    obs_path[i, 2] = a_goal / math.pi
    if cfg[C_SONAR] != 0.0:
        rmax = cfg[C_RANGE]
        q = obs_sonar.shape[1]
        if d >= rmax:  # no surface within range: every sector reads the range, no noise
            for k in range(q):
                sonar_raw[i, k] = rmax
                obs_sonar[i, k] = 1.0
        else:
            q0 = lanes[o + ROW_Q0 * LANES]
            q1 = lanes[o + (ROW_Q0 + 1) * LANES]
            q2 = lanes[o + (ROW_Q0 + 2) * LANES]
            q3 = lanes[o + (ROW_Q0 + 3) * LANES]
            hx = 1.0 - 2.0 * (q2 * q2 + q3 * q3)  # R[0, 0] = cos(psi) cos(theta)
            hy = 2.0 * (q1 * q2 + q0 * q3)  # R[1, 0] = sin(psi) cos(theta)
            hn = math.sqrt(hx * hx + hy * hy)
            _scan(x, y, hx / hn, hy / hn, obstacles[i], m, cfg[C_SPAN], rmax, sonar_raw[i])
            sigma = cfg[C_NOISE]
            for k in range(q):
                v = sonar_raw[i, k]
                if sigma > 0.0 and v < rmax:
                    v = min(rmax, max(0.0, v + sigma * gauss(rng, i)))
                obs_sonar[i, k] = v / rmax
    v = lanes[o + (ROW_U + 1) * LANES]
    r = lanes[o + ROW_R * LANES]
    if cfg[C_MOTION] != 0.0:
        obs_motion[i, 0] = min(MOTION_SWAY_LIMIT, max(-MOTION_SWAY_LIMIT, v))
        obs_motion[i, 1] = min(MOTION_YAW_RATE_LIMIT, max(-MOTION_YAW_RATE_LIMIT, r))
    out[O_AC, i] = a_c
    out[O_AGOAL, i] = a_goal
    out[O_G, i] = g
    out[O_D, i] = d
    out[O_PROG, i] = progress
    out[O_X, i] = x
    out[O_Y, i] = y
    out[O_PSI, i] = psi
    out[O_U, i] = lanes[o + ROW_U * LANES]
    out[O_V, i] = v
    out[O_YAW_RATE, i] = r


@njit(cache=True, _nrt=False)
def place_vehicle(i, lanes, cfg, x, y, psi):
    """Put vehicle i at rest at (x, y) with heading psi, thrusters stopped, in the task's
    current."""
    o = lane_index(i)
    for k in range(ROWS):
        lanes[o + k * LANES] = 0.0
    lanes[o + ROW_X * LANES] = x
    lanes[o + ROW_Y * LANES] = y
    lanes[o + ROW_Q0 * LANES] = math.cos(0.5 * psi)
    lanes[o + (ROW_Q0 + 3) * LANES] = math.sin(0.5 * psi)
    lanes[o + ROW_PSI * LANES] = psi
    lanes[o + ROW_CURRENT * LANES] = cfg[C_CURRENT_X]
    lanes[o + (ROW_CURRENT + 1) * LANES] = cfg[C_CURRENT_Y]


@njit(cache=True, _nrt=False)
def start_episode(
    i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out
):
    """Vehicle i starts an episode where it stands: clear its counters and observe."""
    o = lane_index(i)
    for k in range(O_SIZE):
        out[k, i] = 0.0
    out[O_PREV_GOAL, i] = _distance(
        cfg[C_GOALX] - lanes[o + ROW_X * LANES], cfg[C_GOALY] - lanes[o + ROW_Y * LANES]
    )
    out[O_PROG, i] = np.nan  # no warm start: global closest-point search
    observe(i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out)


@njit(cache=True, _nrt=False)
def reset_vehicle(
    i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out
):
    """Draw vehicle i's next episode from its stream (layout, start-pose noise) and start it."""
    kind = int(cfg[C_LAYOUT])
    if kind != 0:
        amplitude = cfg[C_AMP] if cfg[C_PATH] == 1.0 else 0.0  # a straight path: no sine
        n_obs[i] = draw_layout(
            kind, int(cfg[C_LAYOUT_N]), rng, i, cfg[C_LENGTH], amplitude, cfg[C_WAVE],
            obstacles[i],
        )  # fmt: skip
    x = 0.0
    y = 0.0
    psi = cfg[C_START_PSI]
    pos_std = cfg[C_START_POS_STD]
    if pos_std > 0.0:
        x = pos_std * gauss(rng, i)
        y = pos_std * gauss(rng, i)
    if cfg[C_START_HEAD_STD] > 0.0:
        psi += cfg[C_START_HEAD_STD] * gauss(rng, i)
    place_vehicle(i, lanes, cfg, x, y, psi)
    start_episode(
        i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out
    )


@njit(cache=True, _nrt=False)
def reset_all(
    n, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out
):
    """``reset_vehicle`` for vehicles 0..n-1."""
    for i in range(n):
        reset_vehicle(
            i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out
        )


@njit(parallel=True, cache=True, _nrt=False)
def reset_all_parallel(
    n, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out
):
    """``reset_all`` on numba's threads (a function of its own: see ``step_batch_parallel``)."""
    for i in prange(n):
        reset_vehicle(
            i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out
        )


@njit(cache=True, inline="always", _nrt=False)
def finish_step(
    i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out
):
    """After the physics: observe vehicle i, then its reward (eq. 17-21) and ending."""
    x_prev = out[O_X, i]
    y_prev = out[O_Y, i]
    observe(i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out)
    a_c = out[O_AC, i]
    g = out[O_G, i]
    d = out[O_D, i]
    d_L = cfg[C_DL]
    kind = cfg[C_REWARD]
    dist_goal = _distance(cfg[C_GOALX] - out[O_X, i], cfg[C_GOALY] - out[O_Y, i])
    if kind == 2.0:
        r_c = (out[O_PREV_GOAL, i] - dist_goal) / (cfg[C_UREF] * cfg[C_DT])
    else:
        if kind == 0.0:
            r_c = reward_straight(a_c, g, d_L)
        else:
            r_c = reward_sine(a_c, g, d_L)
        if cfg[C_PROGRESS_W] != 0.0 and r_c > 0.0:
            dx = out[O_X, i] - x_prev
            dy = out[O_Y, i] - y_prev
            if cfg[C_PROGRESS_W] == PROGRESS_COURSE:
                course = lanes[lane_index(i) + ROW_PSI * LANES] - a_c
                r_c *= course_fraction(cfg, course, dx, dy)
            else:
                r_c *= progress_fraction(cfg, out[O_PROG, i], dx, dy)
    out[O_PREV_GOAL, i] = dist_goal
    r_v = cfg[C_OBSTACLE_W] * reward_obstacle(d)
    a_rule = out[O_AGOAL, i] if cfg[C_RULE_GOAL] != 0.0 else a_c
    code = failure_code(a_rule, g, d, d_L)
    at_end = out[O_PROG, i] >= cfg[C_LENGTH]
    gate = cfg[C_ARRIVAL_GATE]
    arrived = dist_goal <= cfg[C_TARGET_R] or (at_end and (gate <= 0.0 or dist_goal <= gate))
    if at_end and not arrived and (code == END_NONE or code == END_HEADING):
        # the end of the path passed too far from the target point: the task ("return to the
        # set path to complete the task", section 4.2.1) is not done, a failure as eq. 21's
        code = END_MISSED
    if code == END_HEADING and arrived:
        # the step that reaches the end is a success, even where a vehicle passing beside the
        # target sees the target's bearing swing past 90 deg (a collision or leaving the
        # corridor still fails)
        code = END_NONE
    r_t = 0.0
    if code != END_NONE:
        r_t = FAILURE_REWARD
    elif arrived:
        code = END_SUCCESS
        r_t = cfg[C_SUCCESS_R]
    steps = out[O_STEPS, i] + 1.0
    out[O_STEPS, i] = steps
    trunc = 0.0
    if code == END_NONE and steps >= cfg[C_MAXSTEPS]:
        code = END_TIME_LIMIT
        trunc = 1.0
    out[O_RC, i] = r_c
    out[O_RV, i] = r_v
    out[O_RT, i] = r_t
    out[O_R, i] = r_c + r_v + r_t
    out[O_END, i] = code
    out[O_TERM, i] = 1.0 if (code != END_NONE and code != END_TIME_LIMIT) else 0.0
    out[O_TRUNC, i] = trunc


@njit(cache=True, inline="always")
def progress_fraction(cfg, x_path, dx, dy):
    """The step's displacement along the path's tangent at ``x_path``, as a fraction of
    ``U_REF * dt`` clipped to [0, 1] (``progress_weighted=True``; not in the paper)."""
    tx = 1.0
    ty = 0.0
    if cfg[C_PATH] == 1.0:
        k = 2.0 * math.pi / cfg[C_WAVE]
        ty = cfg[C_AMP] * k * math.cos(k * x_path)
        norm = math.sqrt(1.0 + ty * ty)
        tx = 1.0 / norm
        ty = ty / norm
    p = (dx * tx + dy * ty) / (cfg[C_UREF] * cfg[C_DT])
    return min(1.0, max(0.0, p))


@njit(cache=True, inline="always")
def course_fraction(cfg, course, dx, dy):
    """The step's displacement along the direction ``course`` (rad; the LOS course, heading
    minus a_c), as a fraction of ``U_REF * dt`` clipped to [0, 1] (``progress_along="course"``;
    not in the paper): pointing at the LOS course is paid in full, so the way back to the path
    pays as much as following it, while a stopped vehicle is still paid nothing."""
    p = (dx * math.cos(course) + dy * math.sin(course)) / (cfg[C_UREF] * cfg[C_DT])
    return min(1.0, max(0.0, p))


@njit(cache=True, _nrt=False)
def first_bad_action(n, actions, cont, continuous, n_actions):
    """Index of the first action that is not allowed (-1 if none)."""
    for i in range(n):
        if continuous:
            if not (math.isfinite(cont[i, 0]) and math.isfinite(cont[i, 1])):
                return i
        elif actions[i] < 0 or actions[i] >= n_actions:
            return i
    return -1


@njit(cache=True, _nrt=False)
def step_block(
    b, mode, n, actions, cont, continuous, table, cfg, lanes, obstacles, n_obs, rng,
    sonar_raw, obs_path, obs_sonar, obs_motion, out, pending, term_path, term_sonar, term_motion,
    final,
):  # fmt: skip
    """One control step for the vehicles of block b (see the module docstring for ``mode``)."""
    i0 = b * LANES
    i1 = min(n, i0 + LANES)
    for i in range(i0, i1):
        c = lane_index(i) + ROW_CMD * LANES
        if continuous:
            n_left, n_right = continuous_pair_speeds(cont[i, 0], cont[i, 1], _MAX_SPEED)
            lanes[c] = n_left
            lanes[c + LANES] = n_right
            lanes[c + 2 * LANES] = -n_left
            lanes[c + 3 * LANES] = -n_right
            lanes[c + 4 * LANES] = 0.0
            lanes[c + 5 * LANES] = 0.0
        else:
            a = actions[i]
            for k in range(6):
                lanes[c + k * LANES] = table[a, k]
    coef = unpack_coefficients(cfg, C_ETD)
    advance_block_vehicle(lanes, b, int(cfg[C_VEHICLE]), coef, cfg[C_DT], int(cfg[C_NSUB]))
    for i in range(i0, i1):
        if mode == MODE_NEXT_STEP and pending[i]:
            reset_vehicle(
                i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion,
                out,
            )  # fmt: skip
            pending[i] = False
            continue
        finish_step(
            i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion, out
        )
        if mode == MODE_PLAIN:
            continue
        done = out[O_TERM, i] != 0.0 or out[O_TRUNC, i] != 0.0
        pending[i] = done
        if mode == MODE_SAME_STEP and done:
            final[F_REWARD, i] = out[O_R, i]
            final[F_TERM, i] = out[O_TERM, i]
            final[F_TRUNC, i] = out[O_TRUNC, i]
            final[F_END, i] = out[O_END, i]
            for k in range(PATH_COLUMNS):
                term_path[i, k] = obs_path[i, k]
            for k in range(obs_sonar.shape[1]):
                term_sonar[i, k] = obs_sonar[i, k]
            term_motion[i, 0] = obs_motion[i, 0]
            term_motion[i, 1] = obs_motion[i, 1]
            reset_vehicle(
                i, lanes, cfg, obstacles, n_obs, rng, sonar_raw, obs_path, obs_sonar, obs_motion,
                out,
            )  # fmt: skip


@njit(cache=True, _nrt=False)
def step_batch(
    mode, n, actions, cont, continuous, table, cfg, lanes, obstacles, n_obs, rng,
    sonar_raw, obs_path, obs_sonar, obs_motion, out, pending, term_path, term_sonar, term_motion,
    final,
):  # fmt: skip
    """One control step for N vehicles, blocks one after the other (single env, small N)."""
    for b in range((n + LANES - 1) // LANES):
        step_block(
            b, mode, n, actions, cont, continuous, table, cfg, lanes, obstacles, n_obs,
            rng, sonar_raw, obs_path, obs_sonar, obs_motion, out, pending, term_path, term_sonar,
            term_motion, final,
        )  # fmt: skip


@njit(cache=True, parallel=True, _nrt=False)
def step_batch_parallel(
    mode, n, actions, cont, continuous, table, cfg, lanes, obstacles, n_obs, rng,
    sonar_raw, obs_path, obs_sonar, obs_motion, out, pending, term_path, term_sonar, term_motion,
    final,
):  # fmt: skip
    """``step_batch`` with the blocks spread over numba's threads (the same numbers).

    A function of its own rather than ``step_batch``'s body compiled twice: numba's cache keys
    compiled code by the Python function, so one function compiled with and without
    ``parallel=True`` shares its cache entries, and the threaded variant silently ran serial.
    """
    for b in prange((n + LANES - 1) // LANES):
        step_block(
            b, mode, n, actions, cont, continuous, table, cfg, lanes, obstacles, n_obs,
            rng, sonar_raw, obs_path, obs_sonar, obs_motion, out, pending, term_path, term_sonar,
            term_motion, final,
        )  # fmt: skip
