"""Adopt finished runs of an older study folder into a new one.

Runs finished before the configuration hash included ``rov_envs.sim.tasks.TASKS_REVISION`` carry a
*legacy* hash (the same SHA-256 of the run's spec, without the revision), which today's study
refuses: the hash alone cannot tell which task definitions they were trained on. Someone who
knows (from the commit that made them) states it with ``--made-with-tasks-revision``; a run is
then copied into the new folder only when

* its stored spec equals, field for field, the spec the new study plans under that run id, and
* its stored hash is the legacy hash of that spec (or already today's hash), and
* every run it depends on (its prior columns, ``RunSpec.deps``) passes the same two checks in
  the old folder: a run's hash covers its own spec, which names its priors by run id only, so
  a transfer run trained on a prior that the new study plans differently (another
  ``oa_layout``, say) would otherwise be adopted although its prior is retrained,

and the stated revision is today's. Its manifest keeps the legacy hash and the stated revision
under ``adopted``, so report readers can see which runs were adopted. Nothing is retrained or
changed otherwise; runs that do not match are listed with the reason and left to the study.

A run whose stored spec differs from the planned one only in how the study evaluates its
trained policy (:data:`EVALUATION_ONLY_FIELDS`: ``play``, e.g. a changed
``spnn_play_no_reversal``) is adopted too, its stored hash checked against its own stored spec:
its files are copied and its kept model is evaluated again as the new spec plays it (a new
``eval.json``; ``adopted.evaluated_again`` names the play before and after). Training is
deterministic only on one machine, so this keeps the very policy the old study evaluated, where
training it again would draw another run on another machine.

Usage (the study's own arguments after ``--``, as for ``python -m sb3_pnn.reproduce``)::

    python -m sb3_pnn.reproduce.running.adopt --from OLD --made-with-tasks-revision 2 -- \
        --seeds 5 --set updates=step:4 --out NEW
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sb3_pnn.reproduce.planning.plan import RunSpec, json_hash
from sb3_pnn.reproduce.running.store import MANIFEST, RunStore, write_json_atomic


def legacy_hash(spec: RunSpec) -> str:
    """The configuration hash runs had before it included the tasks' revision."""
    return json_hash(spec.to_dict())


#: Spec fields that say only how the study evaluates a trained policy: a run whose stored spec
#: differs from the planned one in these alone is adopted and evaluated again.
EVALUATION_ONLY_FIELDS: tuple[str, ...] = ("play",)


def _changed_fields(old: dict[str, Any], spec: RunSpec) -> list[str]:
    stored, planned = old.get("spec") or {}, spec.to_dict()
    return sorted(k for k in stored.keys() | planned.keys() if stored.get(k) != planned.get(k))


def _why_not(old: dict[str, Any] | None, spec: RunSpec) -> str | None:
    if old is None:
        return "not in the old folder"
    if old.get("status", "done") != "done":
        return f"status {old.get('status')!r}"
    changed = _changed_fields(old, spec)
    if not set(changed) <= set(EVALUATION_ONLY_FIELDS):
        return f"spec differs in {', '.join(changed)}"
    made = RunSpec.from_dict(old["spec"]) if changed else spec
    if old.get("config_hash") not in (legacy_hash(made), made.config_hash()):
        return f"stored hash {old.get('config_hash')} is neither the legacy nor today's hash"
    return None


def evaluate_again(spec: RunSpec, folder: Path) -> dict[str, Any]:
    """Evaluate the kept model in ``folder`` as ``spec`` plays it; writes ``eval.json`` there
    and returns the manifest fields of the evaluation (:func:`work.evaluate`)."""
    from sb3_pnn import DiscreteSAC
    from sb3_pnn.reproduce.running.work import evaluate, played

    model = DiscreteSAC.load(folder / "model.zip", device="cpu")
    return evaluate(spec, played(spec.play, model), folder)


def _why_not_deps(spec: RunSpec, verdicts: dict[str, str | None]) -> str | None:
    """Why ``spec``'s old run was trained on other priors than the new study plans, or None;
    ``verdicts`` holds :func:`_why_not` of every run planned before it (its priors included:
    the plan lists a run's priors first)."""
    for dep in spec.deps:
        if dep not in verdicts:
            return f"its prior {dep} is not in the new study's plan"
        if verdicts[dep] is not None:
            return f"its prior {dep} would not be adopted ({verdicts[dep]})"
    return None


def check_revision(revision: int) -> None:
    """ValueError unless ``revision`` is today's ``TASKS_REVISION``."""
    from rov_envs.sim.tasks import TASKS_REVISION

    if revision != TASKS_REVISION:
        raise ValueError(
            f"--made-with-tasks-revision {revision}: today's task definitions are revision "
            f"{TASKS_REVISION}; runs made with other definitions cannot be adopted"
        )


def adopt_runs(
    old_out: Path, store: RunStore, plan: Sequence[RunSpec], revision: int
) -> tuple[list[str], dict[str, str]]:
    """Copy the matching finished runs of ``old_out`` into ``store``.

    Returns (adopted run ids, {run id: why it was not adopted}).
    """
    check_revision(revision)
    old_store = RunStore(old_out)
    adopted: list[str] = []
    skipped: dict[str, str] = {}
    verdicts: dict[str, str | None] = {}  # run id -> _why_not of its old run (read once)
    for spec in plan:
        old = old_store.manifest(spec.run_id)
        verdicts[spec.run_id] = _why_not(old, spec)
        if store.run_dir(spec.run_id).exists():
            skipped[spec.run_id] = "already in the new folder"
            continue
        why = verdicts[spec.run_id] or _why_not_deps(spec, verdicts)
        if why is not None:
            skipped[spec.run_id] = why
            continue
        assert old is not None
        tmp = store.begin(spec)
        for item in old_store.run_dir(spec.run_id).iterdir():
            if item.name != MANIFEST:
                copy = shutil.copytree if item.is_dir() else shutil.copy2
                copy(item, tmp / item.name)
        note: dict[str, Any] = {
            "from": str(old_out.resolve() / "runs" / spec.run_id),
            "stored_hash": old["config_hash"],
            "stated_tasks_revision": revision,
        }
        manifest = dict(old)
        if _changed_fields(old, spec):  # evaluation-only fields: evaluate the kept model again
            try:
                manifest.update(evaluate_again(spec, tmp))
            except Exception as error:  # noqa: BLE001 - reported per run, the others go on
                shutil.rmtree(tmp, ignore_errors=True)
                skipped[spec.run_id] = f"its evaluation as newly played failed: {error}"
                continue
            note["evaluated_again"] = {
                "play_before": (old.get("spec") or {}).get("play", {}),
                "play": spec.play,
            }
        if store.commit(spec, tmp, {**manifest, "adopted": note}):
            adopted.append(spec.run_id)
        else:
            skipped[spec.run_id] = "appeared in the new folder meanwhile"
    return adopted, skipped


def main(argv: Sequence[str] | None = None) -> int:
    from sb3_pnn.reproduce.cli import SESSIONS, out_folder, parse_study_args
    from sb3_pnn.reproduce.planning.plan import build_plan
    from sb3_pnn.reproduce.running.store import open_store_or_exit

    argv = list(sys.argv[1:] if argv is None else argv)
    cut = argv.index("--") if "--" in argv else len(argv)
    own, study = argv[:cut], argv[cut + 1 :]
    parser = argparse.ArgumentParser(
        prog="python -m sb3_pnn.reproduce.running.adopt",
        description=__doc__.split("\n\n")[0],
        epilog="The study's own arguments follow '--' (python -m sb3_pnn.reproduce --help).",
    )
    parser.add_argument("--from", dest="old", required=True, help="the older study folder")
    parser.add_argument(
        "--made-with-tasks-revision",
        type=int,
        required=True,
        help="the TASKS_REVISION of the code that made the old runs (from its commit)",
    )
    args = parser.parse_args(own)
    study_parser, study_args, config = parse_study_args(study)
    old = Path(args.old)
    if not (old / "runs").is_dir():
        parser.error(f"--from {args.old!r} is not a study folder (it has no runs/)")
    out = out_folder(study_args)
    if out.resolve() == old.resolve():
        parser.error("--from and --out are the same folder")
    try:  # before the new folder is created
        check_revision(args.made_with_tasks_revision)
    except ValueError as error:
        parser.error(str(error))
    store = open_store_or_exit(study_parser, out)
    import torch

    torch.set_num_threads(1)  # a run evaluated again: one thread, as the study's workers
    try:
        adopted, skipped = adopt_runs(old, store, build_plan(config), args.made_with_tasks_revision)
    finally:
        store.close()
    if adopted and (old / SESSIONS).is_file():
        # The old invocations' wall clock belongs to the adopted runs' cost. Adopting from a
        # second folder adds its invocations that the new folder does not list yet (a folder
        # that itself adopted from the first one lists the first one's too).
        known = json.loads((out / SESSIONS).read_text()) if (out / SESSIONS).exists() else []
        seen = {s.get("started") for s in known}
        sessions = json.loads((old / SESSIONS).read_text())
        added = [{**s, "adopted_from": str(old)} for s in sessions if s.get("started") not in seen]
        if added:
            write_json_atomic(out / SESSIONS, known + added)
    print(f"adopted {len(adopted)} run(s) from {old} into {out}: {', '.join(adopted) or '-'}")
    for run_id, why in skipped.items():
        print(f"  not adopted: {run_id}: {why}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
