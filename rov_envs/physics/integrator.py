"""Fixed-step exponential RK4 of the Fossen model (paper eq. (1)-(7)), many vehicles in SIMD lanes.

Every vehicle state lives in a flat float64 "lane buffer" laid out in blocks of ``LANES`` vehicles
(array-of-structures-of-arrays): block b holds ``ROWS`` rows of ``LANES`` values, so row k of
vehicle i sits at ``(i // LANES) * BLOCK + k * LANES + i % LANES``. With that layout the loop over
the vehicles of a block has a constant trip count and unit-stride loads, and LLVM turns it into
SIMD code (4 vehicles per AVX2 instruction); ``python bench/physics_speed.py`` reports whether it
did on the machine at hand. A single environment runs the very same code on one block in which
only lane 0 is used, so one vehicle and N vehicles produce the same numbers bit for bit.

Rows (``ROW_*``): position x, y, z (world, m); the attitude as a unit quaternion q0..q3 (Fossen
2011 eq. 2.86: the kinematics of eq. (2) without trigonometry, renormalised after every substep);
body velocities u, v, w, p, q, r; the heading psi integrated beside the quaternion from
psi_dot = (q sin(phi) + r cos(phi)) / cos(theta) (continuous, not wrapped; it is the heading the
task layer reads); the commanded thruster speeds T1..T6 (rev/min, held over a control period);
the lagged thruster speeds n1..n6; the world-frame water velocity (m/s, constant).

Integration (``advance_block``): ``n_substeps`` steps of h = dt / n_substeps of an exponential
RK4 (ETDRK4, :mod:`rov_envs.physics.etd`): the linear damping's diagonal part diag(M^-1 D_lin)
is integrated exactly, everything else as in classic RK4 (the position, attitude and heading rows
run exactly classic RK4). One scheme for both presets: UUV Simulator's BlueROV2 damps roll at
92 1/s and pitch at 25 1/s, which classic RK4 at the environments' h = 0.05 s cannot integrate
(h |lambda| = 4.6 against a stability limit of 2.8; it blows up within a few steps), while ETD
is stable for any damping rate and keeps the ODE's equilibria exact (steady cruise and turn
rates carry no step-size error). For Wu's set (decay rates <= 0.26 1/s) the step stays within
O(h^5) of classic RK4; its stiffest modes are explicit as before (yaw damping at full turn rate
~15 1/s, the roll/pitch righting oscillation ~4.4 rad/s), h |lambda| <= 0.8. The ETD
coefficients (six expm1) are computed once per block or call, or once per task by the
environments, never per vehicle.
The thruster lag is linear and decoupled, so n(t) comes from its exact solution
n(t) = n_cmd + (n(0) - n_cmd) exp(-t / t_lag) at the stage times and the wrench tau is
evaluated once per stage time (shared by stages 2 and 3). The right-hand side is
``dynamics._rates`` (eq. (1)-(6) with the quaternion kinematics); tests/physics compare the
result with scipy's ``solve_ivp`` on an independent Euler-angle model, for both presets.

Compilation: ``error_model="numpy"`` (no ZeroDivisionError branch, which would stop
vectorisation), ``_nrt=False`` (no reference counting of the arrays in the loops), and no
reassociation, no fused multiply-adds, no approximate functions: IEEE operations in source
order, so SIMD lanes and a scalar loop give identical results, and a symmetric command keeps a
symmetric vehicle exactly symmetric (fused multiply-adds would not: their rounding breaks the
left/right symmetry of "Go straight", and Wu's parameter set is directionally unstable, see
``params``). Unused lanes hold a vehicle at rest (q0 = 1) and cost the same as used ones.

Variants share the per-vehicle code ``_lane_step``: ``advance_block`` reads the parameter array
at run time (``advance``, ``advance_batch``, any ``BlueROV2Params``); ``advance_block_vehicle``,
which the environments run, has one compiled variant per preset of ``params.VEHICLES`` with its
parameters compiled in as constants (selected by the vehicle code, ``kernel.C_VEHICLE`` in the
task array), so that the many zeros of a set (M^-1 and the allocation matrix are sparse, r_g and
r_b lie on the z axis) fold away; to let them fold, LLVM may assume no NaN or infinite operands
and ignore the sign of zero in those variants (finite results are the same, up to the sign of a
zero). numba's cache does not notice edits to ``params``: :mod:`rov_envs.sim.kernel`, whose cached
step code embeds these constants, compares every compiled preset with ``vehicle_params(name)``
at import and refuses to run on stale ones.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from rov_envs.physics.dynamics import STATE_DIM, _wrench
from rov_envs.physics.etd import etd_coefficients, etd_step
from rov_envs.physics.params import P_INV_TAU, P_SIZE, vehicle_code, vehicle_params

__all__ = [
    "LANES",
    "ROWS",
    "BLOCK",
    "ROW_X",
    "ROW_Y",
    "ROW_Z",
    "ROW_Q0",
    "ROW_U",
    "ROW_R",
    "ROW_PSI",
    "ROW_CMD",
    "ROW_N",
    "ROW_CURRENT",
    "new_lanes",
    "n_blocks",
    "lane_index",
    "advance_block",
    "advance_block_vehicle",
    "vehicle_coefficients",
    "VEHICLE_UUV_SIMULATOR",
    "VEHICLE_WU2018",
    "UUV_SIMULATOR_PARAMS",
    "WU2018_PARAMS",
    "advance_blocks",
    "advance_blocks_parallel",
    "store_euler_state",
    "load_euler_state",
    "advance",
    "advance_batch",
]

LANES = 16
"""Vehicles per block: the SIMD loop's constant trip count (4 AVX2 vectors of float64)."""
ROW_X, ROW_Y, ROW_Z = 0, 1, 2
ROW_Q0 = 3  # q0 q1 q2 q3 (scalar first)
ROW_U = 7  # u v w p q r
ROW_R = 12
ROW_PSI = 13
ROW_CMD = 14  # 6 rows: commanded speeds T1..T6 (rev/min)
ROW_N = 20  # 6 rows: lagged thruster speeds n1..n6 (rev/min)
ROW_CURRENT = 26  # 3 rows: world-frame water velocity (m/s)
ROWS = 29
BLOCK = ROWS * LANES
"""float64 values per block."""

_UL = np.uint64(LANES)
_UBLOCK = np.uint64(BLOCK)
# row offsets inside a block, unsigned so that numba emits no negative-index wraparound
_O = tuple(np.uint64(k * LANES) for k in range(ROWS))

_JIT = {"cache": True, "error_model": "numpy", "_nrt": False}
# the preset variants: with the parameters constant, multiplications by their zeros fold away
# only when LLVM may ignore NaN/inf operands and the sign of zero (no reassociation, no
# contraction, no approximate functions: finite results are unchanged up to the sign of 0)
_JIT_PRESET = {**_JIT, "fastmath": {"nnan", "ninf", "nsz"}}
#: kernel codes of the presets (their index in ``params.VEHICLES``)
VEHICLE_UUV_SIMULATOR = vehicle_code("uuv_simulator")
VEHICLE_WU2018 = vehicle_code("wu2018")
#: ``vehicle_params(name).to_array()``, frozen into ``advance_block_vehicle`` at compile time
UUV_SIMULATOR_PARAMS = vehicle_params("uuv_simulator").to_array()
WU2018_PARAMS = vehicle_params("wu2018").to_array()


def n_blocks(n_vehicles: int) -> int:
    """Blocks needed for ``n_vehicles`` vehicles."""
    return (int(n_vehicles) + LANES - 1) // LANES


def new_lanes(n_vehicles: int) -> np.ndarray:
    """A zeroed lane buffer for ``n_vehicles`` (rounded up to whole blocks), quaternions = 1."""
    buf = np.zeros((n_blocks(max(1, n_vehicles)), ROWS, LANES), dtype=np.float64)
    buf[:, ROW_Q0, :] = 1.0
    return buf.reshape(-1)


@njit(cache=True, inline="always")
def lane_index(i: int) -> int:
    """Offset of row 0 of vehicle i (add ``k * LANES`` for row k)."""
    return (i // LANES) * BLOCK + i % LANES


@njit(cache=True, inline="always")
def _lane_step(buf, i, P, C, fa, fm, fb, h):
    """One step of length h for the vehicle whose row 0 is at ``buf[i]``, in place (ETDRK4,
    :func:`rov_envs.physics.etd.etd_step`; C = ``etd_coefficients(P, h)``).

    fa, fm, fb: exp(-t / t_lag) at the step's start, middle and end, measured from the start of
    the control period (the thruster speeds follow n = cmd + (n0 - cmd) f).
    """
    y = (
        buf[i + _O[0]], buf[i + _O[1]], buf[i + _O[2]], buf[i + _O[3]], buf[i + _O[4]],
        buf[i + _O[5]], buf[i + _O[6]], buf[i + _O[7]], buf[i + _O[8]], buf[i + _O[9]],
        buf[i + _O[10]], buf[i + _O[11]], buf[i + _O[12]], buf[i + _O[13]],
    )  # fmt: skip
    c0 = buf[i + _O[14]]
    c1 = buf[i + _O[15]]
    c2 = buf[i + _O[16]]
    c3 = buf[i + _O[17]]
    c4 = buf[i + _O[18]]
    c5 = buf[i + _O[19]]
    e0 = buf[i + _O[20]] - c0
    e1 = buf[i + _O[21]] - c1
    e2 = buf[i + _O[22]] - c2
    e3 = buf[i + _O[23]] - c3
    e4 = buf[i + _O[24]] - c4
    e5 = buf[i + _O[25]] - c5
    ta = _wrench(c0 + e0 * fa, c1 + e1 * fa, c2 + e2 * fa, c3 + e3 * fa, c4 + e4 * fa,
                 c5 + e5 * fa, P)  # fmt: skip
    tm = _wrench(c0 + e0 * fm, c1 + e1 * fm, c2 + e2 * fm, c3 + e3 * fm, c4 + e4 * fm,
                 c5 + e5 * fm, P)  # fmt: skip
    tb = _wrench(c0 + e0 * fb, c1 + e1 * fb, c2 + e2 * fb, c3 + e3 * fb, c4 + e4 * fb,
                 c5 + e5 * fb, P)  # fmt: skip
    o = etd_step(y, ta, tm, tb, buf[i + _O[26]], buf[i + _O[27]], buf[i + _O[28]], P, C, h)
    buf[i + _O[0]] = o[0]
    buf[i + _O[1]] = o[1]
    buf[i + _O[2]] = o[2]
    buf[i + _O[3]] = o[3]
    buf[i + _O[4]] = o[4]
    buf[i + _O[5]] = o[5]
    buf[i + _O[6]] = o[6]
    buf[i + _O[7]] = o[7]
    buf[i + _O[8]] = o[8]
    buf[i + _O[9]] = o[9]
    buf[i + _O[10]] = o[10]
    buf[i + _O[11]] = o[11]
    buf[i + _O[12]] = o[12]
    buf[i + _O[13]] = o[13]


@njit(**_JIT)
def _substep(buf, base, P, C, fa, fm, fb, h):
    """``_lane_step`` for the LANES vehicles of the block at ``base`` (SIMD), parameters ``P``."""
    for lane in range(_UL):
        _lane_step(buf, base + lane, P, C, fa, fm, fb, h)


@njit(**_JIT_PRESET)
def _substep_uuv_simulator(buf, base, P, C, fa, fm, fb, h):
    """``_substep`` with ``UUV_SIMULATOR_PARAMS`` compiled in as constants (``P`` is not read:
    the signature is ``_substep``'s, so that ``_period`` runs either)."""
    for lane in range(_UL):
        _lane_step(buf, base + lane, UUV_SIMULATOR_PARAMS, C, fa, fm, fb, h)


@njit(**_JIT_PRESET)
def _substep_wu2018(buf, base, P, C, fa, fm, fb, h):
    """``_substep`` with ``WU2018_PARAMS`` compiled in as constants (``P`` is not read)."""
    for lane in range(_UL):
        _lane_step(buf, base + lane, WU2018_PARAMS, C, fa, fm, fb, h)


@njit(**_JIT)
def _settle_thrusters(buf, base, f):
    """n <- cmd + (n - cmd) f for the block at ``base`` (end of a control period)."""
    for j in range(6):
        row_c = base + _O[ROW_CMD + j]
        row_n = base + _O[ROW_N + j]
        for lane in range(_UL):
            c = buf[row_c + lane]
            buf[row_n + lane] = c + (buf[row_n + lane] - c) * f


@njit(cache=True, inline="always")
def _period(buf, block, P, C, dt, n_substeps, substep):
    """One control period dt (s) of ``block``: ``substep`` n_substeps times, then the lag.

    C: ``etd_coefficients(P, dt / n_substeps)``, computed once for every block of a call.
    """
    base = np.uint64(block) * _UBLOCK
    h = dt / n_substeps
    decay_half = math.exp(-0.5 * h * P[P_INV_TAU])
    f = 1.0
    for _ in range(n_substeps):
        fm = f * decay_half
        fb = fm * decay_half
        substep(buf, base, P, C, f, fm, fb, h)
        f = fb
    _settle_thrusters(buf, base, f)


@njit(**_JIT)
def _advance_block_with(buf, block, P, C, dt, n_substeps):
    """``advance_block`` with its ETD coefficients C given."""
    _period(buf, block, P, C, dt, n_substeps, _substep)


@njit(**_JIT)
def advance_block(buf, block, P, dt, n_substeps):
    """Advance the LANES vehicles of ``block`` by one control period dt (s), in place."""
    _advance_block_with(buf, block, P, etd_coefficients(P, dt / n_substeps), dt, n_substeps)


@njit(**_JIT)
def advance_blocks(buf, P, dt, n_substeps):
    """``advance_block`` for every block of ``buf``, one after the other."""
    C = etd_coefficients(P, dt / n_substeps)
    for b in range(buf.shape[0] // BLOCK):
        _advance_block_with(buf, b, P, C, dt, n_substeps)


@njit(parallel=True, **_JIT)
def advance_blocks_parallel(buf, P, dt, n_substeps):
    """``advance_block`` for every block of ``buf`` on numba's threads (same numbers)."""
    for b in prange(buf.shape[0] // BLOCK):  # (a tuple cannot enter a parallel loop's body)
        advance_block(buf, b, P, dt, n_substeps)


@njit(**_JIT)
def vehicle_coefficients(vehicle, dt, n_substeps):
    """The ETD coefficients of preset ``vehicle`` (a code of ``params.VEHICLES``: 0 UUV
    Simulator, 1 Wu 2018) for substeps of dt / n_substeps, for ``advance_block_vehicle``.
    Other codes raise ValueError."""
    h = dt / n_substeps
    if vehicle == VEHICLE_UUV_SIMULATOR:
        return etd_coefficients(UUV_SIMULATOR_PARAMS, h)
    if vehicle == VEHICLE_WU2018:
        return etd_coefficients(WU2018_PARAMS, h)
    raise ValueError("vehicle_coefficients: unknown vehicle code (see params.VEHICLES)")


@njit(**_JIT)
def advance_block_vehicle(buf, block, vehicle, C, dt, n_substeps):
    """``advance_block`` with preset ``vehicle`` compiled in (what the environments run).

    ``vehicle``: a code of ``params.VEHICLES`` (0 UUV Simulator, 1 Wu 2018; other codes raise);
    C = ``vehicle_coefficients(vehicle, dt, n_substeps)``, computed once for many blocks (the
    environments keep it in their task array).
    """
    if vehicle == VEHICLE_UUV_SIMULATOR:
        _period(buf, block, UUV_SIMULATOR_PARAMS, C, dt, n_substeps, _substep_uuv_simulator)
    elif vehicle == VEHICLE_WU2018:
        _period(buf, block, WU2018_PARAMS, C, dt, n_substeps, _substep_wu2018)
    else:
        raise ValueError("advance_block_vehicle: unknown vehicle code (see params.VEHICLES)")


# ---- the 18-dim Euler-angle state of ``dynamics`` <-> a lane -----------------------------------


@njit(cache=True)
def store_euler_state(buf, i, state, cmd, current):
    """Put vehicle i's lane at ``state`` (18,), commands ``cmd`` (6,) and ``current`` (3,)."""
    o = lane_index(i)
    hf = 0.5 * state[3]
    ht = 0.5 * state[4]
    hp = 0.5 * state[5]
    cr = math.cos(hf)
    sr = math.sin(hf)
    cp = math.cos(ht)
    sp = math.sin(ht)
    cy = math.cos(hp)
    sy = math.sin(hp)
    buf[o + ROW_X * LANES] = state[0]
    buf[o + ROW_Y * LANES] = state[1]
    buf[o + ROW_Z * LANES] = state[2]
    buf[o + ROW_Q0 * LANES] = cr * cp * cy + sr * sp * sy
    buf[o + (ROW_Q0 + 1) * LANES] = sr * cp * cy - cr * sp * sy
    buf[o + (ROW_Q0 + 2) * LANES] = cr * sp * cy + sr * cp * sy
    buf[o + (ROW_Q0 + 3) * LANES] = cr * cp * sy - sr * sp * cy
    for k in range(6):
        buf[o + (ROW_U + k) * LANES] = state[6 + k]
        buf[o + (ROW_CMD + k) * LANES] = cmd[k]
        buf[o + (ROW_N + k) * LANES] = state[12 + k]
    buf[o + ROW_PSI * LANES] = state[5]
    for k in range(3):
        buf[o + (ROW_CURRENT + k) * LANES] = current[k]


@njit(cache=True)
def load_euler_state(buf, i, out):
    """Write vehicle i's state into ``out`` (18,) in the Euler-angle layout of ``dynamics``.

    Roll and pitch come from the quaternion (ZYX); the heading is the quaternion's, taken on
    the branch of the continuous heading row (so it is not wrapped).
    """
    o = lane_index(i)
    q0 = buf[o + ROW_Q0 * LANES]
    q1 = buf[o + (ROW_Q0 + 1) * LANES]
    q2 = buf[o + (ROW_Q0 + 2) * LANES]
    q3 = buf[o + (ROW_Q0 + 3) * LANES]
    r20 = 2.0 * (q1 * q3 - q0 * q2)
    r21 = 2.0 * (q2 * q3 + q0 * q1)
    r22 = 1.0 - 2.0 * (q1 * q1 + q2 * q2)
    r10 = 2.0 * (q1 * q2 + q0 * q3)
    r00 = 1.0 - 2.0 * (q2 * q2 + q3 * q3)
    out[0] = buf[o + ROW_X * LANES]
    out[1] = buf[o + ROW_Y * LANES]
    out[2] = buf[o + ROW_Z * LANES]
    out[3] = math.atan2(r21, r22)
    out[4] = -math.asin(min(1.0, max(-1.0, r20)))
    psi_c = buf[o + ROW_PSI * LANES]
    d = math.atan2(r10, r00) - psi_c
    d -= 2.0 * math.pi * math.floor((d + math.pi) / (2.0 * math.pi))
    out[5] = psi_c + d
    for k in range(6):
        out[6 + k] = buf[o + (ROW_U + k) * LANES]
        out[12 + k] = buf[o + (ROW_N + k) * LANES]


# ---- public one-vehicle / N-vehicle API on the Euler-angle state ------------------------------


def _check_step(dt: float, n_substeps: int) -> None:
    if not (isinstance(dt, (int, float, np.floating)) and math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt={dt!r} is not allowed: expected a positive finite number of seconds")
    if isinstance(n_substeps, bool) or int(n_substeps) != n_substeps or n_substeps < 1:
        raise ValueError(f"n_substeps={n_substeps!r} is not allowed: expected an integer >= 1")


def _check_array(name: str, a: object, shape: tuple[int, ...], what: str) -> None:
    if not isinstance(a, np.ndarray) or a.dtype != np.float64 or a.shape != shape:
        got = f"{a.dtype} array of shape {a.shape}" if isinstance(a, np.ndarray) else type(a)
        raise ValueError(f"{name} must be a float64 array of shape {shape} ({what}), got {got}")


def advance_batch(
    states: np.ndarray,
    cmds: np.ndarray,
    p: np.ndarray,
    currents: np.ndarray,
    dt: float,
    n_substeps: int,
) -> None:
    """Advance N vehicles by ``dt`` seconds in place with ``n_substeps`` ETDRK4 steps each.

    states (N, 18) Euler-angle layout of ``dynamics`` (psi continuous, not wrapped), cmds (N, 6)
    commanded speeds in rev/min held over the period, p = ``BlueROV2Params.to_array()``,
    currents (N, 3) world-frame m/s. Row i evolves exactly (bit for bit) as ``advance`` on it.
    """
    if not (isinstance(states, np.ndarray) and states.ndim == 2):
        raise ValueError(f"states must be a float64 array of shape (N, {STATE_DIM})")
    n = states.shape[0]
    _check_array("states", states, (n, STATE_DIM), "x y z phi theta psi u v w p q r n1..n6")
    _check_array("cmds", cmds, (n, 6), "rev/min, T1..T6")
    _check_array("p", p, (P_SIZE,), "BlueROV2Params.to_array()")
    _check_array("currents", currents, (n, 3), "world-frame m/s")
    _check_step(dt, n_substeps)
    _advance_euler(states, cmds, p, currents, float(dt), int(n_substeps))


def advance(
    state: np.ndarray,
    cmd: np.ndarray,
    p: np.ndarray,
    current: np.ndarray,
    dt: float,
    n_substeps: int,
) -> None:
    """Advance one vehicle by ``dt`` seconds in place (see ``advance_batch``).

    state (18,), cmd (6,) rev/min, p = ``BlueROV2Params.to_array()``, current (3,) world m/s.
    """
    _check_array("state", state, (STATE_DIM,), "x y z phi theta psi u v w p q r n1..n6")
    _check_array("cmd", cmd, (6,), "rev/min, T1..T6")
    _check_array("p", p, (P_SIZE,), "BlueROV2Params.to_array()")
    _check_array("current", current, (3,), "world-frame m/s")
    _check_step(dt, n_substeps)
    _advance_euler(
        state.reshape(1, STATE_DIM), cmd.reshape(1, 6), p, current.reshape(1, 3), float(dt),
        int(n_substeps),
    )  # fmt: skip


@njit(cache=True)
def _advance_euler(states, cmds, p, currents, dt, n_substeps):
    n = states.shape[0]
    buf = np.zeros(((n + LANES - 1) // LANES) * BLOCK)
    for b in range(buf.shape[0] // BLOCK):
        for lane in range(LANES):
            buf[b * BLOCK + ROW_Q0 * LANES + lane] = 1.0
    for i in range(n):
        store_euler_state(buf, i, states[i], cmds[i], currents[i])
    advance_blocks(buf, p, dt, n_substeps)
    for i in range(n):
        load_euler_state(buf, i, states[i])
