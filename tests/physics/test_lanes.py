"""The SIMD lane integrator: every variant and layout computes the same numbers bit for bit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rov_envs import kernel as K
from rov_envs.physics import ACTION_TABLE, BlueROV2Params
from rov_envs.physics import integrator as I  # noqa: E741
from rov_envs.physics.integrator import advance

P = BlueROV2Params().to_array()


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


@pytest.mark.parametrize("n", [1, 16, 37])
def test_default_parameter_kernel_equals_runtime_parameters(n: int) -> None:
    a = _fleet(n)
    b = a.copy()
    for _ in range(30):
        for blk in range(a.size // I.BLOCK):
            I.advance_block(a, blk, P, 0.2, 4)
            I.advance_block_default(b, blk, 0.2, 4)
    assert np.array_equal(a, b)  # the constant-folded variant changes no finite result


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
        I.advance_block_default(full, 0, 0.2, 4)
        I.advance_block_default(alone, 0, 0.2, 4)
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


def test_stale_compiled_parameters_are_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    K.check_compiled_params()  # the compiled-in values are today's defaults
    heavier = BlueROV2Params(mass=12.0)
    monkeypatch.setattr(K, "BlueROV2Params", lambda: heavier)
    with pytest.raises(RuntimeError, match="__pycache__"):
        K.check_compiled_params()


def test_bad_integrator_arguments_name_the_argument() -> None:
    with pytest.raises(ValueError, match="states"):
        I.advance_batch(np.zeros((2, 17)), np.zeros((2, 6)), P, np.zeros((2, 3)), 0.2, 4)
    with pytest.raises(ValueError, match="currents"):
        I.advance_batch(np.zeros((2, 18)), np.zeros((2, 6)), P, np.zeros((3, 3)), 0.2, 4)
    with pytest.raises(ValueError, match="n_substeps"):
        advance(np.zeros(18), np.zeros(6), P, np.zeros(3), 0.2, True)
