"""The fused per-step numba kernels shared by the single and the batched environments.

One call advances the vehicle dynamics (``rov_envs.physics.dynamics.advance``), runs LOS guidance
(``rov_envs.physics.guidance``, eq. 16), the sonar (``rov_envs.physics.sonar``), the rewards
(eq. 17-21, :mod:`rov_envs.rewards`) and the ending tests, writing into preallocated buffers. The
batched kernel runs the very same per-vehicle function in a loop, so N batched vehicles and N
single environments with the same seeds produce the same numbers bit for bit.

Random numbers needed during an episode (sonar noise) come from a per-vehicle splitmix64 stream
kept in a ``uint64`` array and seeded at reset from the environment's ``np_random``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from rov_envs.physics.dynamics import advance_work
from rov_envs.physics.guidance import los_guidance
from rov_envs.physics.sonar import nearest_surface_distance, sonar_scan
from rov_envs.physics.thrusters import continuous_to_speeds_into
from rov_envs.rewards import (
    END_NONE,
    END_SUCCESS,
    END_TIME_LIMIT,
    FAILURE_REWARD,
    failure_code,
    reward_obstacle,
    reward_sine,
    reward_straight,
)

# ---- layout of the task array ``cfg`` (float64) ----
C_PATH = 0  # 0 straight, 1 sine (rov_envs.tasks.PATH_*)
C_REWARD = 1  # rov_envs.tasks.REWARD_*
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
C_SIZE = 19

# ---- per-vehicle auxiliary state ``aux`` (float64) ----
A_STEPS = 0  # steps taken in this episode
A_PREV_GOAL = 1  # distance to the goal after the previous step (progress reward)
A_SIZE = 2

# ---- per-vehicle step results ``out`` (float64) ----
O_AC = 0  # heading deviation a_c (rad)
O_G = 1  # signed cross-track distance g (m)
O_D = 2  # distance to the nearest obstacle surface (m, inf without obstacles)
O_RC = 3  # r_c
O_RV = 4  # r_v
O_RT = 5  # r_terminal
O_R = 6  # total reward
O_END = 7  # end code (rov_envs.rewards.END_*)
O_PROG = 8  # along-path progress (m of x for the closest path point)
O_TERM = 9  # 1.0 when terminated
O_TRUNC = 10  # 1.0 when truncated
O_SIZE = 11

_PI = math.pi
_M1 = np.uint64(0x9E3779B97F4A7C15)
_M2 = np.uint64(0xBF58476D1CE4E5B9)
_M3 = np.uint64(0x94D049BB133111EB)
_S30 = np.uint64(30)
_S27 = np.uint64(27)
_S31 = np.uint64(31)
_S11 = np.uint64(11)


@njit(cache=True)
def _uniform(rng: np.ndarray, i: int) -> float:
    """splitmix64: a float in [0, 1) from stream ``rng[i]``."""
    z = rng[i] + _M1
    rng[i] = z
    z = (z ^ (z >> _S30)) * _M2
    z = (z ^ (z >> _S27)) * _M3
    z = z ^ (z >> _S31)
    return float(z >> _S11) * (1.0 / 9007199254740992.0)


@njit(cache=True)
def _gauss(rng: np.ndarray, i: int) -> float:
    """A standard normal draw (Box-Muller) from stream ``rng[i]``."""
    u1 = 1.0 - _uniform(rng, i)
    u2 = _uniform(rng, i)
    return math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * _PI * u2)


@njit(cache=True)
def continuous_command(surge: float, yaw: float, max_speed: float, cmd: np.ndarray) -> None:
    """The (surge, yaw) -> T1..T6 mapping of ``rov_envs.physics.thrusters`` (inputs clipped)."""
    continuous_to_speeds_into(surge, yaw, max_speed, cmd)


@njit(cache=True)
def observe(
    state: np.ndarray,
    cfg: np.ndarray,
    obstacles: np.ndarray,
    rng: np.ndarray,
    ri: int,
    guide: np.ndarray,
    sonar_buf: np.ndarray,
    obs_path: np.ndarray,
    obs_sonar: np.ndarray,
    out: np.ndarray,
) -> None:
    """Guidance, obstacle distance and sonar at the current state; fills the observation."""
    x = state[0]
    y = state[1]
    psi = state[5]
    # guide[2] is read as the sine closest-point warm start, then overwritten
    los_guidance(int(cfg[C_PATH]), x, y, psi, cfg[C_AMP], cfg[C_WAVE], cfg[C_LOOKAHEAD], guide)
    a_c = guide[0]
    g = guide[1]
    d_L = cfg[C_DL]
    d = nearest_surface_distance(x, y, obstacles)
    obs_path[0] = a_c / _PI
    obs_path[1] = min(1.0, max(-1.0, g / d_L))
    if cfg[C_SONAR] != 0.0:
        rmax = cfg[C_RANGE]
        sonar_scan(x, y, psi, obstacles, cfg[C_SPAN], rmax, sonar_buf)
        sigma = cfg[C_NOISE]
        for k in range(sonar_buf.shape[0]):
            v = sonar_buf[k]
            if sigma > 0.0 and v < rmax:
                v = min(rmax, max(0.0, v + sigma * _gauss(rng, ri)))
            obs_sonar[k] = v / rmax
    out[O_AC] = a_c
    out[O_G] = g
    out[O_D] = d
    out[O_PROG] = guide[2]


@njit(cache=True)
def reset_vehicle(
    state: np.ndarray,
    cfg: np.ndarray,
    obstacles: np.ndarray,
    rng: np.ndarray,
    ri: int,
    aux: np.ndarray,
    guide: np.ndarray,
    sonar_buf: np.ndarray,
    obs_path: np.ndarray,
    obs_sonar: np.ndarray,
    out: np.ndarray,
) -> None:
    """Start an episode from ``state`` (already set): clear counters and observe."""
    aux[A_STEPS] = 0.0
    aux[A_PREV_GOAL] = math.hypot(cfg[C_GOALX] - state[0], cfg[C_GOALY] - state[1])
    guide[2] = np.nan  # no warm start: global closest-point search
    observe(state, cfg, obstacles, rng, ri, guide, sonar_buf, obs_path, obs_sonar, out)
    for k in range(O_RC, O_SIZE):
        if k != O_PROG:
            out[k] = 0.0


@njit(cache=True)
def step_vehicle(
    state: np.ndarray,
    cmd: np.ndarray,
    params: np.ndarray,
    current: np.ndarray,
    cfg: np.ndarray,
    obstacles: np.ndarray,
    rng: np.ndarray,
    ri: int,
    aux: np.ndarray,
    work: np.ndarray,
    guide: np.ndarray,
    sonar_buf: np.ndarray,
    obs_path: np.ndarray,
    obs_sonar: np.ndarray,
    out: np.ndarray,
) -> None:
    """One control period of one vehicle: dynamics, guidance, sonar, reward (eq. 17-21), ending.

    ``guide`` (3,) keeps [a_c, g, progress]; its progress is the sine closest-point warm start.
    """
    advance_work(state, cmd, params, current, cfg[C_DT], int(cfg[C_NSUB]), work)
    observe(state, cfg, obstacles, rng, ri, guide, sonar_buf, obs_path, obs_sonar, out)
    a_c = out[O_AC]
    g = out[O_G]
    d = out[O_D]
    d_L = cfg[C_DL]
    kind = cfg[C_REWARD]
    dist_goal = math.hypot(cfg[C_GOALX] - state[0], cfg[C_GOALY] - state[1])
    if kind == 0.0:
        r_c = reward_straight(a_c, g, d_L)
    elif kind == 1.0:
        r_c = reward_sine(a_c, g, d_L)
    else:
        r_c = (aux[A_PREV_GOAL] - dist_goal) / (cfg[C_UREF] * cfg[C_DT])
    aux[A_PREV_GOAL] = dist_goal
    r_v = reward_obstacle(d)
    code = failure_code(a_c, g, d, d_L)
    r_t = 0.0
    if code != END_NONE:
        r_t = FAILURE_REWARD
    elif out[O_PROG] >= cfg[C_LENGTH] or dist_goal <= cfg[C_TARGET_R]:
        code = END_SUCCESS
        r_t = cfg[C_SUCCESS_R]
    aux[A_STEPS] += 1.0
    trunc = 0.0
    if code == END_NONE and aux[A_STEPS] >= cfg[C_MAXSTEPS]:
        code = END_TIME_LIMIT
        trunc = 1.0
    out[O_RC] = r_c
    out[O_RV] = r_v
    out[O_RT] = r_t
    out[O_R] = r_c + r_v + r_t
    out[O_END] = code
    out[O_TERM] = 1.0 if (code != END_NONE and code != END_TIME_LIMIT) else 0.0
    out[O_TRUNC] = trunc


@njit(cache=True)
def step_single(
    state: np.ndarray,
    action: int,
    surge: float,
    yaw: float,
    continuous: bool,
    table: np.ndarray,
    cmd: np.ndarray,
    params: np.ndarray,
    current: np.ndarray,
    cfg: np.ndarray,
    obstacles: np.ndarray,
    rng: np.ndarray,
    aux: np.ndarray,
    work: np.ndarray,
    guide: np.ndarray,
    sonar_buf: np.ndarray,
    obs_path: np.ndarray,
    obs_sonar: np.ndarray,
    out: np.ndarray,
) -> None:
    """Single-environment step: the action becomes a thruster command, then ``step_vehicle``."""
    if continuous:
        continuous_command(surge, yaw, 8000.0, cmd)
    else:
        for k in range(6):
            cmd[k] = table[action, k]
    step_vehicle(
        state, cmd, params, current, cfg, obstacles, rng, 0, aux, work, guide, sonar_buf,
        obs_path, obs_sonar, out,
    )  # fmt: skip


def _step_batch_impl(
    states: np.ndarray,
    actions: np.ndarray,
    cont_actions: np.ndarray,
    continuous: bool,
    table: np.ndarray,
    cmds: np.ndarray,
    params: np.ndarray,
    currents: np.ndarray,
    cfg: np.ndarray,
    obstacles: np.ndarray,
    n_obs: np.ndarray,
    rng: np.ndarray,
    aux: np.ndarray,
    work: np.ndarray,
    guide: np.ndarray,
    sonar_buf: np.ndarray,
    obs_path: np.ndarray,
    obs_sonar: np.ndarray,
    out: np.ndarray,
) -> None:
    for i in prange(states.shape[0]):
        cmd = cmds[i]
        if continuous:
            continuous_command(cont_actions[i, 0], cont_actions[i, 1], 8000.0, cmd)
        else:
            a = actions[i]
            for k in range(6):
                cmd[k] = table[a, k]
        step_vehicle(
            states[i], cmd, params, currents[i], cfg, obstacles[i, : n_obs[i]], rng, i, aux[i],
            work[i], guide[i], sonar_buf[i], obs_path[i], obs_sonar[i], out[i],
        )  # fmt: skip


#: Batched step, serial loop over vehicles.
step_batch = njit(cache=True)(_step_batch_impl)
#: Batched step, vehicles spread over numba's threads (same numbers as ``step_batch``).
step_batch_parallel = njit(cache=True, parallel=True)(_step_batch_impl)
