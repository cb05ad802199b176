"""Files nobody should trust: a failed save keeps the previous file, a corrupt file is called
corrupt (never "needs unpickling"), and loads are bounded before they allocate anything.

The hostile files are built by the tests themselves from a freshly saved model."""

from __future__ import annotations

import io
import json
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import rov_envs  # noqa: F401
from sb3_pnn import DiscreteSAC, ProgressivePolicy, load_prior
from sb3_pnn.safe_io.checkpoint import JSON_MEMBER, UnsafeCheckpointError

ENV = "rov_envs/PathFollowingStraight-v0"


@pytest.fixture(scope="module")
def saved(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A small model, its replay buffer (a few hundred steps), and a second model."""
    folder = tmp_path_factory.mktemp("hostile")
    model = DiscreteSAC(
        "MultiInputPolicy",
        gym.make(ENV, max_episode_seconds=20),
        policy_kwargs={"net_arch": [16, 16]},
        learning_starts=50,
        batch_size=32,
        train_freq=1,
        gradient_steps=1,
        seed=0,
    )
    model.learn(300)
    model.save(folder / "model.zip")
    model.save_replay_buffer(folder / "buffer.pkl")
    other = DiscreteSAC("MultiInputPolicy", gym.make(ENV), policy_kwargs={"net_arch": [8]}, seed=1)
    other.save(folder / "other.zip")
    return {
        "model": folder / "model.zip",
        "buffer": folder / "buffer.pkl",
        "other": folder / "other.zip",
    }


def _weights(path: Path) -> dict[str, np.ndarray]:
    model = DiscreteSAC.load(path)
    return {k: v.numpy().copy() for k, v in model.policy.state_dict().items()}


def _rewrite(src: Path, dst: Path, member: str, data: bytes) -> Path:
    """``src`` with ``member``'s content replaced by ``data`` (deflated, like a real save)."""
    with zipfile.ZipFile(src) as old, zipfile.ZipFile(dst, "w", zipfile.ZIP_DEFLATED) as new:
        for info in old.infolist():
            new.writestr(info.filename, data if info.filename == member else old.read(info))
    return dst


def _with_meta(src: Path, dst: Path, change) -> Path:
    meta = json.loads(zipfile.ZipFile(src).read(JSON_MEMBER))
    change(meta)
    return _rewrite(src, dst, JSON_MEMBER, json.dumps(meta).encode())


# --- a failed save ----------------------------------------------------------------------------
_FULL_DISK = """
import resource, signal, sys
import gymnasium as gym
import rov_envs
from sb3_pnn import DiscreteSAC
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit fails with EFBIG
source, target, what = sys.argv[1:]
model = DiscreteSAC.load(source, env=gym.make("{env}"))
if what == "buffer":
    model.load_replay_buffer(target)
resource.setrlimit(resource.RLIMIT_FSIZE, (2000, 2000))  # as if the disk filled up
try:
    if what == "model":
        model.save(target)
    else:
        model.save_replay_buffer(target)
except OSError as error:
    print("save failed:", error)
    sys.exit(0)
sys.exit("the save did not fail")
"""


@pytest.mark.parametrize("what", ["model", "buffer"])
def test_a_failed_save_leaves_the_previous_file_intact(
    what: str, saved: dict[str, Path], tmp_path: Path
) -> None:
    target = tmp_path / ("model.zip" if what == "model" else "buffer.pkl")
    target.write_bytes(saved[what].read_bytes())
    before = target.read_bytes()
    script = textwrap.dedent(_FULL_DISK.format(env=ENV))
    result = subprocess.run(
        [sys.executable, "-c", script, str(saved["other"]), str(target), what],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert "save failed" in result.stdout
    assert target.read_bytes() == before  # the previous file, untouched
    assert [p.name for p in tmp_path.iterdir()] == [target.name]  # no temporary file left
    if what == "model":
        assert _weights(target).keys() == _weights(saved["model"]).keys()
    else:
        model = DiscreteSAC.load(saved["model"], env=gym.make(ENV))
        model.load_replay_buffer(target)
        assert model.replay_buffer.size() > 0


# --- corrupt is not unsafe --------------------------------------------------------------------
@pytest.mark.parametrize("fraction", [0.1, 0.5, 0.9, 0.99])
def test_a_truncated_checkpoint_is_called_corrupt(
    fraction: float, saved: dict[str, Path], tmp_path: Path
) -> None:
    data = saved["model"].read_bytes()
    cut = tmp_path / "cut.zip"
    cut.write_bytes(data[: int(len(data) * fraction)])
    with pytest.raises(ValueError, match="truncated or corrupt") as error:
        DiscreteSAC.load(cut)
    assert not isinstance(error.value, UnsafeCheckpointError)
    assert "trust_pickle" not in str(error.value) and "unpickl" not in str(error.value)


@pytest.mark.parametrize("fraction", [0.1, 0.5, 0.9])
def test_a_truncated_replay_buffer_is_called_corrupt(
    fraction: float, saved: dict[str, Path], tmp_path: Path
) -> None:
    data = saved["buffer"].read_bytes()
    cut = tmp_path / "cut.pkl"
    cut.write_bytes(data[: int(len(data) * fraction)])
    model = DiscreteSAC.load(saved["model"], env=gym.make(ENV))
    with pytest.raises(ValueError, match="truncated or corrupt") as error:
        model.load_replay_buffer(cut)
    assert not isinstance(error.value, UnsafeCheckpointError)
    assert "trust_pickle" not in str(error.value)


def test_an_sb3_zip_without_the_json_member_is_unsafe(saved: dict[str, Path], tmp_path: Path):
    plain = tmp_path / "sb3.zip"
    with zipfile.ZipFile(saved["model"]) as old, zipfile.ZipFile(plain, "w") as new:
        for info in old.infolist():
            if info.filename != JSON_MEMBER:
                new.writestr(info.filename, old.read(info))
    with pytest.raises(UnsafeCheckpointError, match="trust_pickle=True"):
        DiscreteSAC.load(plain)


# --- bounded loads ----------------------------------------------------------------------------
def test_a_json_member_that_inflates_is_refused_before_reading(
    saved: dict[str, Path], tmp_path: Path
) -> None:
    bomb = _rewrite(saved["model"], tmp_path / "bomb.zip", JSON_MEMBER, b" " * (40 << 20))
    assert bomb.stat().st_size < 1 << 20  # a small file ...
    with pytest.raises(ValueError, match="inflate"):  # ... refused by its declared size
        DiscreteSAC.load(bomb)


def test_a_prior_whose_data_member_inflates_is_refused(saved: dict[str, Path], tmp_path: Path):
    bomb = _rewrite(saved["model"], tmp_path / "bomb.zip", "data", b" " * (40 << 20))
    with pytest.raises(ValueError, match="inflate"):
        load_prior(bomb)
    with pytest.raises(ValueError, match="inflate"):
        DiscreteSAC(ProgressivePolicy, gym.make(ENV), policy_kwargs={"priors": [str(bomb)]})


@pytest.mark.parametrize(
    ("change", "needle"),
    [
        (lambda m: m["hyperparameters"].update(buffer_size=10**13), "buffer_size"),
        (lambda m: m["hyperparameters"].update(batch_size="256"), "batch_size"),
        (lambda m: m["hyperparameters"].update(gamma=7.0), "gamma"),
        (
            lambda m: m["hyperparameters"]["policy_kwargs"].update(net_arch=[200000, 200000]),
            "net_arch",
        ),
        (lambda m: m["hyperparameters"]["policy_kwargs"].update(colour="red"), "colour"),
        (lambda m: m["hyperparameters"].update(replay_buffer_kwargs={"bogus": 1}), "bogus"),
        (lambda m: m["state"].update(num_timesteps="xx"), "num_timesteps"),
        (lambda m: m["state"].update(_n_updates=-5), "_n_updates"),
        (lambda m: m["observation_space"]["spaces"][0][1].update(shape=[10**9]), "shape"),
    ],
)
def test_a_checkpoint_that_lies_is_refused_naming_the_value(
    change, needle: str, saved: dict[str, Path], tmp_path: Path
) -> None:
    liar = _with_meta(saved["model"], tmp_path / "liar.zip", change)
    with pytest.raises(ValueError, match=needle):
        DiscreteSAC.load(liar)


def test_json_nested_a_hundred_thousand_deep_is_refused(saved: dict[str, Path], tmp_path: Path):
    meta = zipfile.ZipFile(saved["model"]).read(JSON_MEMBER).decode()
    deep = meta.replace(
        '"policy_kwargs": {', '"policy_kwargs": {"x": ' + "[" * 100_000 + "]" * 100_000 + ", ", 1
    )
    liar = _rewrite(saved["model"], tmp_path / "deep.zip", JSON_MEMBER, deep.encode())
    with pytest.raises(ValueError, match="nested"):
        DiscreteSAC.load(liar)


@pytest.mark.parametrize(
    ("key", "value"), [("n_envs", 0), ("buffer_size", 10**13), ("pos", -1), ("full", "yes")]
)
def test_a_replay_buffer_that_lies_is_refused(
    key: str, value, saved: dict[str, Path], tmp_path: Path
) -> None:
    with np.load(saved["buffer"], allow_pickle=False) as archive:
        arrays = {k: archive[k] for k in archive.files}
    meta = json.loads(str(arrays.pop("__meta__")))
    meta[key] = value
    liar = io.BytesIO()
    np.savez(liar, __meta__=np.array(json.dumps(meta)), **arrays)
    (tmp_path / "liar.pkl").write_bytes(liar.getvalue())
    model = DiscreteSAC.load(saved["model"], env=gym.make(ENV))
    with pytest.raises(ValueError, match=key):
        model.load_replay_buffer(tmp_path / "liar.pkl")
