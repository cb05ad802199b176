"""Fuzzing the loaders: single-bit flips and truncations of a saved model, of the same file read
as a prior column, and of a replay buffer. Whatever the damage, a load either succeeds (the flip
hit a byte nothing reads) or raises ``ValueError`` (``FileNotFoundError`` for an empty name):
no other exception, and nothing in the file is ever executed (a flipped pickle opcode in SB3's
``data`` part is never unpickled)."""

from __future__ import annotations

import random
from pathlib import Path

import gymnasium as gym
import pytest

import rov_envs  # noqa: F401
from sb3_pnn import DiscreteSAC, load_prior

ENV = "rov_envs/PathFollowingStraight-v0"
#: Damaged copies per file kind: bit flips and truncations.
FLIPS, CUTS = 150, 50


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, bytes]:
    folder = tmp_path_factory.mktemp("fuzz")
    model = DiscreteSAC(
        "MultiInputPolicy",
        gym.make(ENV, max_episode_seconds=10),
        policy_kwargs={"net_arch": [8]},
        learning_starts=20,
        batch_size=16,
        buffer_size=200,
        train_freq=1,
        gradient_steps=1,
        seed=0,
    )
    model.learn(60)
    model.save(folder / "model.zip")
    model.save_replay_buffer(folder / "buffer.pkl")
    return {
        "model": (folder / "model.zip").read_bytes(),
        "buffer": (folder / "buffer.pkl").read_bytes(),
    }


def _damaged(data: bytes, seed: int) -> list[bytes]:
    rng = random.Random(seed)
    out = []
    for _ in range(FLIPS):
        damaged = bytearray(data)
        position = rng.randrange(len(data))
        damaged[position] ^= 1 << rng.randrange(8)
        out.append(bytes(damaged))
    out += [data[: rng.randrange(len(data))] for _ in range(CUTS)]
    return out


def _load_model(path: Path) -> None:
    DiscreteSAC.load(path)


def _load_prior(path: Path) -> None:
    load_prior(path)


@pytest.fixture(scope="module")
def buffer_owner(files: dict[str, bytes], tmp_path_factory: pytest.TempPathFactory):
    path = tmp_path_factory.mktemp("owner") / "model.zip"
    path.write_bytes(files["model"])
    return DiscreteSAC.load(path, env=gym.make(ENV))


@pytest.mark.parametrize(("kind", "seed"), [("model", 1), ("prior", 2), ("buffer", 3)])
def test_damaged_files_load_or_raise_value_error(
    kind: str, seed: int, files: dict[str, bytes], buffer_owner, tmp_path: Path
) -> None:
    source = files["buffer" if kind == "buffer" else "model"]
    path = tmp_path / ("buffer.pkl" if kind == "buffer" else "model.zip")
    outcomes = {"loaded": 0, "refused": 0}
    for damaged in _damaged(source, seed):
        path.write_bytes(damaged)
        try:
            if kind == "model":
                _load_model(path)
            elif kind == "prior":
                _load_prior(path)
            else:
                buffer_owner.load_replay_buffer(path)
        except ValueError:
            outcomes["refused"] += 1
        else:
            outcomes["loaded"] += 1
    assert sum(outcomes.values()) == FLIPS + CUTS
    assert outcomes["refused"] >= CUTS  # every truncation at least is refused


def _central_entry_set(data: bytes, member: str, offset: int, value: int) -> bytes:
    """``data`` with one byte of ``member``'s central-directory entry set to ``value``
    (``offset`` from the entry's signature: 6 the version needed to extract, 10 the
    compression method)."""
    end = data.rindex(b"PK\x05\x06")
    at = int.from_bytes(data[end + 16 : end + 20], "little")  # the central directory's start
    for _ in range(int.from_bytes(data[end + 10 : end + 12], "little")):
        assert data[at : at + 4] == b"PK\x01\x02"
        lengths = [int.from_bytes(data[at + k : at + k + 2], "little") for k in (28, 30, 32)]
        if data[at + 46 : at + 46 + lengths[0]] == member.encode():
            out = bytearray(data)
            out[at + offset] = value
            return bytes(out)
        at += 46 + sum(lengths)
    raise AssertionError(f"no member {member!r} in the zip")


@pytest.mark.parametrize("kind", ["model", "prior"])
@pytest.mark.parametrize(("offset", "value"), [(6, 84), (10, 99)])
def test_an_unsupported_zip_version_or_method_is_refused(kind, offset, value, files, tmp_path):
    """A flipped header field that zipfile answers with NotImplementedError (zip version 8.4,
    compression method 99) is a damaged file like any other: ValueError."""
    path = tmp_path / "model.zip"
    path.write_bytes(_central_entry_set(files["model"], "policy.pth", offset, value))
    with pytest.raises(ValueError):
        (_load_model if kind == "model" else _load_prior)(path)
