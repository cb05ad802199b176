"""The SIMD lane integrator: every variant and layout computes the same numbers bit for bit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rov_envs.physics import ACTION_TABLE, BlueROV2Params
from rov_envs.physics import integrator as I  # noqa: E741
from rov_envs.physics.integrator import advance
from rov_envs.physics.params import VEHICLES, vehicle_code, vehicle_params
from rov_envs.sim import kernel as K

P = vehicle_params("uuv_simulator").to_array()
UUV = vehicle_code("uuv_simulator")
UUV_COEF = I.vehicle_coefficients(UUV, 0.2, 4)


def _fleet(n: int, seed: int = 0) -> np.ndarray:
    """A lane buffer of n vehicles with mixed commands, currents and spread-out states."""
    rng = np.random.default_rng(seed)
    buf = I.new_lanes(n)
    for i in range(n):
        state = np.zeros(18)
        state[:6] = rng.uniform([-5, -5, -1, -0.2, -0.2, -4], [5, 5, 1, 0.2, 0.2, 4])
        state[6:12] = rng.uniform(-0.5, 0.5, 6)
        state[12:] = rng.uniform(-8000, 8000, 6)
        cmd = ACTION_TABLE[rng.integers(0, 5)].copy()
        cmd[4:] = rng.uniform(-2000, 2000, 2)  # exercise heave and roll
        I.store_euler_state(buf, i, state, cmd, rng.uniform(-0.3, 0.3, 3))
    return buf


@pytest.mark.parametrize("vehicle", VEHICLES)
@pytest.mark.parametrize("n", [1, 16, 37])
def test_preset_kernels_equal_runtime_parameters(vehicle: str, n: int) -> None:
    p = vehicle_params(vehicle).to_array()
    code = vehicle_code(vehicle)
    coef = I.vehicle_coefficients(code, 0.2, 4)
    a = _fleet(n)
    b = a.copy()
    for _ in range(30):
        for blk in range(a.size // I.BLOCK):
            I.advance_block(a, blk, p, 0.2, 4)
            I.advance_block_vehicle(b, blk, code, coef, 0.2, 4)
    assert np.array_equal(a, b)  # the constant-folded variant changes no finite result
    assert np.all(np.isfinite(a))


def test_preset_kernels_differ_and_refuse_unknown_codes() -> None:
    a = _fleet(16)
    b = a.copy()
    for code, buf in enumerate((a, b)):
        I.advance_block_vehicle(buf, 0, code, I.vehicle_coefficients(code, 0.2, 4), 0.2, 4)
    assert not np.array_equal(a, b)
    with pytest.raises(ValueError, match="unknown vehicle code"):
        I.vehicle_coefficients(len(VEHICLES), 0.2, 4)
    with pytest.raises(ValueError, match="unknown vehicle code"):
        I.advance_block_vehicle(a, 0, len(VEHICLES), UUV_COEF, 0.2, 4)


def test_parallel_equals_serial() -> None:
    a = _fleet(100)
    b = a.copy()
    for _ in range(10):
        I.advance_blocks(a, P, 0.2, 4)
        I.advance_blocks_parallel(b, P, 0.2, 4)
    assert np.array_equal(a, b)


def test_a_vehicle_does_not_depend_on_its_block_mates() -> None:
    """Lane 5 of a full block evolves exactly as the same vehicle alone in lane 0."""
    full = _fleet(16, seed=3)
    state = np.zeros(18)
    I.load_euler_state(full, 5, state)
    o = 5 + I.ROW_CMD * I.LANES
    cmd = full[o : o + 6 * I.LANES : I.LANES].copy()
    o = 5 + I.ROW_CURRENT * I.LANES
    current = full[o : o + 3 * I.LANES : I.LANES].copy()
    alone = I.new_lanes(1)
    I.store_euler_state(alone, 0, state, cmd, current)
    full_rows = full.reshape(I.ROWS, I.LANES)
    alone_rows = alone.reshape(I.ROWS, I.LANES)
    full_rows[:, 5] = alone_rows[:, 0]  # identical start, bit for bit
    for _ in range(25):
        I.advance_block_vehicle(full, 0, UUV, UUV_COEF, 0.2, 4)
        I.advance_block_vehicle(alone, 0, UUV, UUV_COEF, 0.2, 4)
    assert np.array_equal(full_rows[:, 5], alone_rows[:, 0])


def test_euler_state_round_trip_keeps_the_heading_continuous() -> None:
    buf = I.new_lanes(3)
    state = np.array([1.0, -2.0, 0.5, 0.1, -0.2, 7.5, 0.3, 0.1, 0.0, 0.02, 0.01, 0.5, *range(6)])
    I.store_euler_state(buf, 2, state, np.zeros(6), np.zeros(3))
    back = np.zeros(18)
    I.load_euler_state(buf, 2, back)
    np.testing.assert_allclose(back, state, rtol=0, atol=1e-12)
    assert back[5] > 2 * math.pi  # 7.5 rad, not wrapped


def test_advance_batch_rows_equal_advance() -> None:
    states = np.zeros((20, 18))
    states[:, 5] = np.linspace(-3, 3, 20)
    cmds = ACTION_TABLE[np.arange(20) % 5].copy()
    currents = np.zeros((20, 3))
    single = states.copy()
    I.advance_batch(states, cmds, P, currents, 0.2, 4)
    for i in range(20):
        advance(single[i], cmds[i], P, currents[i], 0.2, 4)
    assert np.array_equal(states, single)


@pytest.mark.parametrize("vehicle", VEHICLES)
def test_stale_compiled_parameters_are_refused(
    monkeypatch: pytest.MonkeyPatch, vehicle: str
) -> None:
    K.check_compiled_params()  # the compiled-in values are today's presets
    presets = {name: vehicle_params(name) for name in VEHICLES}
    presets[vehicle] = presets[vehicle].replace(mass=12.0)
    monkeypatch.setattr(K, "vehicle_params", presets.__getitem__)
    with pytest.raises(RuntimeError, match=f"vehicle {vehicle!r}.*__pycache__"):
        K.check_compiled_params()


def test_a_preset_without_compiled_code_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    names = (*VEHICLES, "new_vehicle")  # a preset added to params but not to the kernels
    monkeypatch.setattr(K, "VEHICLES", names)
    monkeypatch.setattr(K, "vehicle_code", names.index)
    monkeypatch.setattr(
        K,
        "vehicle_params",
        lambda name: BlueROV2Params() if name == names[-1] else vehicle_params(name),
    )
    with pytest.raises(RuntimeError, match="new_vehicle"):
        K.check_compiled_params()


def test_bad_integrator_arguments_name_the_argument() -> None:
    with pytest.raises(ValueError, match="states"):
        I.advance_batch(np.zeros((2, 17)), np.zeros((2, 6)), P, np.zeros((2, 3)), 0.2, 4)
    with pytest.raises(ValueError, match="currents"):
        I.advance_batch(np.zeros((2, 18)), np.zeros((2, 6)), P, np.zeros((3, 3)), 0.2, 4)
    with pytest.raises(ValueError, match="n_substeps"):
        advance(np.zeros(18), np.zeros(6), P, np.zeros(3), 0.2, True)
