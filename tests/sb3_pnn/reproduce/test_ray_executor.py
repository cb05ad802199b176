"""The study on a (local) Ray cluster gives the runs the local process pool gives, bit for bit,
and commits them into the study folder as the local pool does: a study begun on Ray is finished
locally."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from sb3_pnn.reproduce.planning.plan import StudyConfig, build_plan
from sb3_pnn.reproduce.running.executor import execute
from sb3_pnn.reproduce.running.store import RunStore
from sb3_pnn.reproduce.running.work import run_work
from sb3_pnn.reproduce.tools.same_runs import differences, finished

ray = pytest.importorskip("ray")
pytestmark = pytest.mark.slow

#: The quick budget, one seed, the straight path: priors, baselines and the four agents.
CONFIG = StudyConfig(budget_name="quick", seeds=1, paths=("straight",))


@pytest.fixture(scope="module")
def local_ray():
    from sb3_pnn.reproduce.running.ray_pool import connect

    connected = connect(None, num_cpus=2)
    yield connected
    ray.shutdown()


def _study(folder: Path, pool=None, max_new_runs: int | None = None, config=CONFIG):
    store = RunStore(folder)
    store.open()
    try:
        return execute(
            build_plan(config), store, run_work, 2, quiet=True, max_new_runs=max_new_runs,
            pool=pool,
        )  # fmt: skip
    finally:
        store.close()


def test_ray_and_the_local_pool_give_the_same_runs(local_ray, tmp_path: Path) -> None:
    from sb3_pnn.reproduce.running.ray_pool import RayPool

    plan = build_plan(CONFIG)
    on_ray = tmp_path / "ray"
    # begun on Ray, stopped after three runs ...
    store = RunStore(on_ray)
    first = _study(on_ray, RayPool(store, run_work, local_ray), max_new_runs=3)
    assert len(first.done) == 3 and not first.failed
    # ... finished on Ray: nothing finished is redone
    second = _study(on_ray, RayPool(store, run_work, local_ray))
    assert sorted(second.skipped_finished) == sorted(first.done)
    assert len(second.done) == len(plan) - 3 and not second.failed
    local = tmp_path / "local"
    assert not _study(local).failed
    assert finished(on_ray) == finished(local) == {spec.run_id for spec in plan}
    for run_id in sorted(finished(local)):
        assert differences(on_ray / "runs" / run_id, local / "runs" / run_id) == [], run_id
        for name in ("model.zip", "eval.json"):
            ray_file, local_file = on_ray / "runs" / run_id / name, local / "runs" / run_id / name
            assert ray_file.exists() == local_file.exists()
        manifest = json.loads((on_ray / "runs" / run_id / "manifest.json").read_text())
        assert manifest["config_hash"] == next(s for s in plan if s.run_id == run_id).config_hash()


def test_a_run_that_fails_on_ray_is_recorded_and_blocks_its_dependents(
    local_ray, tmp_path: Path
) -> None:
    from sb3_pnn.reproduce.running.ray_pool import RayPool

    def broken_prior(spec, tmp, deps):
        if spec.kind == "prior":
            raise RuntimeError("disk on fire")
        return run_work(spec, tmp, deps)

    store = RunStore(tmp_path)
    pnn_only = StudyConfig(  # the paper's PNN: the path-following column alone
        budget_name="quick",
        seeds=1,
        paths=("straight",),
        agents=("pnn",),
        setup_changes=(("pnn_avoidance_column", "neither"),),
    )
    summary = _study(tmp_path, RayPool(store, broken_prior, local_ray), config=pnn_only)
    assert list(summary.failed) == ["prior-pf_straight-s0"]
    assert summary.blocked == {"pnn-straight-s0": "prior-pf_straight-s0"}
    failure = json.loads((tmp_path / "failures" / f"{next(iter(summary.failed))}.json").read_text())
    assert "disk on fire" in failure["error"]


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["--executor", "ray", "--ray-address", "127.0.0.1:1"], "no Ray cluster answers there"),
        (["--executor", "ray", "--ray-address", "nonsense"], "expected HOST:PORT"),
        (["--ray-address", "127.0.0.1:6379"], "--ray-address goes with --executor ray"),
    ],
)
def test_bad_cluster_arguments_stop_before_any_run(argv, needle, tmp_path, capsys) -> None:
    from sb3_pnn.reproduce.cli import main

    assert main(["--quick", "--out", str(tmp_path), *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0]
    assert not list((tmp_path / "runs").glob("*"))


def test_a_cluster_without_a_free_cpu_stops_before_any_run(
    local_ray, tmp_path, capsys, monkeypatch
) -> None:
    from sb3_pnn.reproduce.cli import main

    monkeypatch.setattr(ray, "cluster_resources", lambda: {"CPU": 0.0})
    assert main(["--quick", "--out", str(tmp_path), "--executor", "ray"]) == 2
    assert "has 0 CPUs: each run needs one" in capsys.readouterr().err
