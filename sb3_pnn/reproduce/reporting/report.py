"""``report.md``: our measurements beside the paper's (section 4.3), with how they were made.

Everything in the report is computed from the finished runs in the study folder; the paper's
numbers are quoted constants
(:data:`.figures.PAPER_SUCCESS`). Statements of agreement are derived from
the measurements by :func:`claims`, never written by hand, and only for a real budget: a
smoke-sized one (``--quick``, :data:`SMOKE_BUDGETS`) is marked as a smoke test and gives no
verdicts. The end reasons in the tables are explained from rov_envs' constants
(:func:`end_reasons`).
"""

from __future__ import annotations

import math
import os
import platform
import sys
import time
from pathlib import Path
from typing import Any

from sb3_pnn.reproduce.planning.plan import (
    AGENT_LABELS,
    AGENTS,
    EVAL_TASKS,
    PLANNING_ENVS,
    PRIOR_ENVS,
    StudyConfig,
)
from sb3_pnn.reproduce.planning.setups import TrainingSetup
from sb3_pnn.reproduce.reporting.figures import (
    GENERALIZATION,
    PAPER_SUCCESS,
    per_run_success,
    run_kind,
)
from sb3_pnn.reproduce.reporting.stats import (
    SMOOTH_WINDOW,
    episodes_to_first_success,
    episodes_to_threshold,
    success_interval,
    summarize_reached,
)
from sb3_pnn.reproduce.running.results import StudyResults

#: Return threshold = this fraction of the adaptive PID's mean evaluation return on the task.
THRESHOLD_FRACTION = 0.8
#: Training episodes at the end of each run whose end reasons the report counts.
LAST_EPISODES = 20
#: Budgets that only check that the study runs end to end: their report gives no verdicts.
SMOKE_BUDGETS = frozenset({"quick", "tiny"})
TASK_TITLES = {
    "original": "original planning task",
    "path_following": "path following, no obstacles",
    "uniform": "new: uniform obstacles",
    "dense": "new: dense obstacles",
}


def versions() -> dict[str, str]:
    """Versions of Python and the libraries the study ran with."""
    from importlib import metadata

    out = {"python": platform.python_version()}
    for dist, module in (
        ("torch", "torch"),
        ("stable-baselines3", "stable_baselines3"),
        ("gymnasium", "gymnasium"),
        ("numpy", "numpy"),
        ("numba", "numba"),
        ("sb3-pnn", "sb3_pnn"),
    ):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            mod = sys.modules.get(module) or __import__(module)
            out[dist] = (
                str(getattr(mod, "__version__", "unknown")) + " (not installed as a distribution)"
            )
    return out


def machine() -> str:
    return (
        f"{platform.system()} {platform.machine()}, {os.cpu_count()} logical cores "
        f"({len(os.sched_getaffinity(0)) if hasattr(os, 'sched_getaffinity') else '?'} usable), "
        f"{platform.processor() or 'cpu'}"
    )


def _pct(pairs: list[tuple[int, int]]) -> str:
    """Pooled rate [interval] (episodes), the interval from :func:`.stats.success_interval`."""
    if not pairs:
        return "-"
    rate, lo, hi = success_interval(pairs)
    n = sum(n for _, n in pairs)
    return f"{100 * rate:.0f} % [{100 * lo:.0f}, {100 * hi:.0f}] (n={n})"


def _per_seed(pairs: list[tuple[int, int]]) -> str:
    """Each run's success rate (%), in seed order."""
    return " ".join(f"{100 * k / n:.0f}" for k, n in pairs) if pairs else "-"


#: The episode ends of eq. 21 (a failure, with its terminal reward).
FAILURE_ENDS = ("off_path", "heading", "collision")


def end_reasons(heading_rule: str = "goal") -> dict[str, str]:
    """What each ``end_reason`` of the env means, with the numbers read from rov_envs;
    ``heading_rule`` is what the planning tasks' heading failure reads (the set-up's)."""
    from rov_envs.sim.config import TARGET_RADIUS, TIME_LIMIT_FACTOR, U_REF
    from rov_envs.sim.rewards import COLLISION_DISTANCE, END_REASONS, HALF_PI
    from rov_envs.sim.tasks import task_of_env

    d_l = ", ".join(
        f"{task_of_env(env_id).d_L:g} m on the {path} path"
        for path, env_id in PLANNING_ENVS.items()
    )
    text = {
        "success": f"reached the target (within {TARGET_RADIUS:g} m of it, or past the path's end)",
        "collision": f"came within {COLLISION_DISTANCE:g} m of an obstacle's surface",
        "heading": (
            f"the heading deviation from the goal's bearing reached {math.degrees(HALF_PI):g} "
            "deg (it turned away from where the route goes)"
            if heading_rule == "goal"
            else f"the heading deviation |a_c| from the path direction reached "
            f"{math.degrees(HALF_PI):g} deg (it turned away from the path)"
        ),
        "off_path": f"the distance from the path |g| reached d_L ({d_l})",
        "time_limit": f"none of these within {TIME_LIMIT_FACTOR:g} x the path's arc length at "
        f"{U_REF:g} m/s (truncated)",
        "missed_target": "reached the path's end farther from the target point than the task's "
        "arrival gate (only with rov_envs' arrival_gate: factors planning_arrival_gate, "
        "pf_arrival_gate)",
    }
    return {reason: text[reason] for reason in END_REASONS if reason != "none"}


def end_reasons_text(heading_rule: str = "goal") -> str:
    """One line explaining the end reasons in the report's tables."""
    from rov_envs.sim.rewards import FAILURE_REWARD

    meanings = end_reasons(heading_rule).items()
    return (
        "how episodes end (the 'ended by' columns): "
        + "; ".join(f"`{reason}`: {meaning}" for reason, meaning in meanings)
        + f". {', '.join(FAILURE_ENDS)} are the failures of eq. 21 ({FAILURE_REWARD:+g})"
    )


#: The policies of the success tables, in row order: the learners, then the baselines.
TABLE_ROWS: tuple[str, ...] = (*AGENTS, "adaptive_pid", "pid")


def success_table(results: StudyResults) -> list[str]:
    """Figure 20 beside the paper, plus the original tasks and path following."""
    lines = [
        "| policy | "
        + " | ".join(f"{g[2]} (ours)" for g in GENERALIZATION)
        + " | paper (same order) |",
        "|---|" + "---|" * (len(GENERALIZATION) + 1),
    ]
    for agent in TABLE_ROWS:
        cells = []
        for path, label, _ in GENERALIZATION:
            cells.append(_pct(per_run_success(results.select(run_kind(agent), agent, path), label)))
        paper = PAPER_SUCCESS.get(agent)
        paper_s = " / ".join(f"{v:g} %" for v in paper) if paper else "not reported"
        lines.append(f"| {AGENT_LABELS[agent]} | " + " | ".join(cells) + f" | {paper_s} |")
    lines += [
        "",
        "Original tasks and path following without obstacles (success, pooled over seeds):",
        "",
    ]
    cols = [(p, label) for p in ("straight", "sine") for label in ("original", "path_following")]
    lines.append("| policy | " + " | ".join(f"{p}: {TASK_TITLES[lb]}" for p, lb in cols) + " |")
    lines.append("|---|" + "---|" * len(cols))
    for agent in TABLE_ROWS:
        cells = [
            _pct(per_run_success(results.select(run_kind(agent), agent, p), lb)) for p, lb in cols
        ]
        lines.append(f"| {AGENT_LABELS[agent]} | " + " | ".join(cells) + " |")
    tasks = [(p, "original") for p in ("straight", "sine")] + [(g[0], g[1]) for g in GENERALIZATION]
    lines += [
        "",
        "Success per training seed (%, seeds in order; whole runs succeed or fail, which is why "
        "the intervals above also cover the spread between seeds):",
        "",
        "| policy | " + " | ".join(f"{p}: {TASK_TITLES[lb]}" for p, lb in tasks) + " |",
        "|---|" + "---|" * len(tasks),
    ]
    for agent in AGENTS:
        cells = [
            _per_seed(per_run_success(results.select("transfer", agent, p), lb)) for p, lb in tasks
        ]
        lines.append(f"| {AGENT_LABELS[agent]} | " + " | ".join(cells) + " |")
    return lines


def _mean_and_seeds(rates: list[float]) -> str:
    """Mean success over runs (%) and each run's, in seed order."""
    if not rates:
        return "-"
    per_seed = " ".join(f"{100 * r:.0f}" for r in rates)
    return f"{100 * sum(rates) / len(rates):.0f} % ({per_seed})"


def validation_table(results: StudyResults) -> list[str]:
    """Each agent's best validation check (the policy kept and evaluated above) beside its last
    (the policy at the end of the budget, which a study without ``keep_best`` would report)."""
    checked = [r for r in results.select("transfer") if r.validation and r.validation["history"]]
    if not checked:
        return []
    first = checked[0].validation
    assert first is not None
    lines = [
        f"Validation checks (every {first['every']} training episodes, {first['n_episodes']} "
        f"episodes each with the evaluation's start noise, seeds {first['seed']}+, apart from the "
        "evaluation's): the best check's policy is the one kept and evaluated above; the last "
        "check is the policy at the end of the budget. Mean over the runs (each run's, in seed "
        "order):",
        "",
        "| policy | straight: best check | straight: last check | sine: best check | "
        "sine: last check |",
        "|---|---|---|---|---|",
    ]
    for agent in AGENTS:
        cells = []
        for path in ("straight", "sine"):
            histories = [
                r.validation["history"]
                for r in results.select("transfer", agent, path)
                if r.validation and r.validation["history"]
            ]
            best = [max(check["success_rate"] for check in h) for h in histories]
            cells += [
                _mean_and_seeds(best),
                _mean_and_seeds([h[-1]["success_rate"] for h in histories]),
            ]
        lines.append(f"| {AGENT_LABELS[agent]} | " + " | ".join(cells) + " |")
    return lines


#: A source column whose kept policy passes less of its own task than this is named in the
#: report: its learners read a prior that does not do the task it stands for.
WEAK_COLUMN = 0.5


def columns_table(results: StudyResults) -> list[str]:
    """The source columns the learners read (each candidate set's kept column where columns are
    the best of several runs), on their own task's evaluation episodes, per column set; and a
    line for each column below :data:`WEAK_COLUMN` and for each column trained again
    (``prior_retries``). A seed's column can fail its task while
    its training runs to the end, and its learners then start from a prior that does not do
    the task it stands for: the learners' results of that seed are read with it."""
    rows, weak = [], []
    for name, env_id in PRIOR_ENVS.items():
        runs = [r for r in results.select("select") if r.spec.env_id == env_id] or [
            r for r in results.select("prior") if r.spec.env_id == env_id
        ]
        rates = [(r, r.evals["own"]["success_rate"]) for r in runs if "own" in r.evals]
        if not rates:
            continue
        rows.append(f"| {name} | {_mean_and_seeds([rate for _, rate in rates])} |")
        weak += [
            f"- `{r.spec.run_id}` passes {100 * rate:.0f} % of its own task: the learners that "
            f"read column set {r.spec.seed} start from a prior that does not do it "
            "(`--set prior_retries=1` trains a column that passes no validation check again)."
            for r, rate in rates
            if rate < WEAK_COLUMN
        ]
        weak += [
            f"- `{r.spec.run_id}` was trained {len(tried)} times (seeds "
            + ", ".join(str(a["seed"]) for a in tried)
            + "): an attempt that passes no validation check is trained again (prior_retries)."
            for r, _ in rates
            if len(tried := r.manifest.get("attempts", [])) > 1
        ]
    if not rows:
        return []
    return [
        "Source columns on their own tasks (evaluation episodes; mean, and each column set's "
        "in order):",
        "",
        "| column | success |",
        "|---|---|",
        *rows,
        *([""] + weak if weak else []),
    ]


def route_table(results: StudyResults) -> list[str]:
    """Mean |g| and |a_c| per policy and task (means over seeds of the evaluation means)."""
    lines = [
        "| path | task | policy | mean abs(g) (m) | max abs(g) (m) | mean abs(a_c) (deg) "
        "| time to target (s) | collisions | episodes ended by |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for path, tasks in EVAL_TASKS.items():
        for label, _, _ in tasks:
            for agent in TABLE_ROWS:
                evs = [
                    r.evals[label]
                    for r in results.select(run_kind(agent), agent, path)
                    if label in r.evals
                ]
                if not evs:
                    continue

                def avg(key: str, evs: list[dict[str, Any]] = evs) -> str:
                    vals = [e[key] for e in evs if e.get(key) is not None]
                    return f"{sum(vals) / len(vals):.2f}" if vals else "-"

                he = [
                    e["mean_abs_heading_error"]
                    for e in evs
                    if e.get("mean_abs_heading_error") is not None
                ]
                he_s = f"{math.degrees(sum(he) / len(he)):.1f}" if he else "-"
                coll = sum(int(e.get("collisions", 0)) for e in evs)
                end_counts: dict[str, int] = {}
                for e in evs:
                    for reason, count in (e.get("end_reasons") or {}).items():
                        end_counts[reason] = end_counts.get(reason, 0) + int(count)
                ends = ", ".join(
                    f"{k} {v}" for k, v in sorted(end_counts.items(), key=lambda kv: -kv[1])
                )
                n = sum(int(e["n_episodes"]) for e in evs)
                lines.append(
                    f"| {path} | {TASK_TITLES[label]} | {AGENT_LABELS[agent]} | "
                    f"{avg('mean_abs_cross_track')} | {avg('max_abs_cross_track')} | {he_s} | "
                    f"{avg('mean_time_to_target')} | {coll}/{n} | {ends} |"
                )
    return lines


def thresholds(results: StudyResults) -> dict[str, float | None]:
    """Per path: THRESHOLD_FRACTION x the adaptive PID's mean return on the original task."""
    out: dict[str, float | None] = {}
    for path in EVAL_TASKS:
        runs = results.select("baseline", "adaptive_pid", path)
        ev = runs[0].evals.get("original") if runs else None
        value = ev.get("mean_return") if ev else None
        out[path] = THRESHOLD_FRACTION * value if value is not None and value > 0 else None
    return out


def _end_counts(runs: list[Any]) -> str:
    counts: dict[str, int] = {}
    for r in runs:
        for reason in r.episodes["end_reasons"][-LAST_EPISODES:]:
            counts[reason] = counts.get(reason, 0) + 1
    return ", ".join(f"{k} {v}" for k, v in sorted(counts.items(), key=lambda kv: -kv[1]))


def learning_speed(
    results: StudyResults,
) -> tuple[list[str], dict[tuple[str, str], dict[str, Any]]]:
    """Episodes to the first success and to the return threshold, per agent and path."""
    thr = thresholds(results)
    lines = [
        f"Return threshold: {THRESHOLD_FRACTION:g} x the adaptive PID's mean evaluation return on "
        f"the original task, reached by the {SMOOTH_WINDOW}-episode moving average of the training "
        "return: "
        + ", ".join(f"{p}: {'n/a' if v is None else f'{v:.0f}'}" for p, v in thr.items())
        + ". Mean [95 % t-interval] over the seeds that reached it; 'reached' counts seeds. "
        "A return above the threshold does not imply success (an agent that stays on the path "
        "until the time limit also collects r_c every step): the last column shows how the final "
        f"{LAST_EPISODES} training episodes ended, over all seeds.",
        "",
        "| path | agent | budget (episodes) | first success: reached | first success: mean [CI] | "
        "return threshold: reached | return threshold: mean [CI] | last episodes ended by |",
        "|---|---|---|---|---|---|---|---|",
    ]
    table: dict[tuple[str, str], dict[str, Any]] = {}
    for path in EVAL_TASKS:
        for agent in AGENTS:
            runs = [r for r in results.select("transfer", agent, path) if r.episodes]
            if not runs:
                continue
            budget = runs[0].spec.episodes
            first = summarize_reached(
                [episodes_to_first_success(r.episodes["successes"]) for r in runs], budget
            )
            if thr[path] is None:
                reach = summarize_reached([None for _ in runs], budget)
            else:
                reach = summarize_reached(
                    [episodes_to_threshold(r.episodes["returns"], thr[path]) for r in runs], budget
                )
            table[(path, agent)] = {"first_success": first, "threshold": reach}

            def fmt(s: dict[str, Any]) -> str:
                if not s["reached"]:
                    return "-"
                lo, hi = s["ci95"]
                return f"{s['mean']:.0f} [{lo:.0f}, {hi:.0f}]"

            lines.append(
                f"| {path} | {AGENT_LABELS[agent]} | {budget} | "
                f"{first['reached']}/{first['runs']} | "
                f"{fmt(first)} | {reach['reached']}/{reach['runs']} | {fmt(reach)} | "
                f"{_end_counts(runs)} |"
            )
    return lines, table


def _rate(
    results: StudyResults, agent: str, path: str, label: str
) -> tuple[float | None, tuple[float, float]]:
    pairs = per_run_success(results.select(run_kind(agent), agent, path), label)
    if not pairs:
        return None, (math.nan, math.nan)
    rate, lo, hi = success_interval(pairs)
    return rate, (lo, hi)


def _compare(
    a: tuple[float | None, tuple[float, float]], b: tuple[float | None, tuple[float, float]]
) -> str:
    """Verdict on "rate a >= rate b" from the two intervals (:func:`.stats.success_interval`)."""
    (ra, (lo_a, hi_a)), (rb, (lo_b, hi_b)) = a, b
    if ra is None or rb is None:
        return "not measured"
    if lo_a > hi_b:
        return "agrees (intervals apart)"
    if hi_a < lo_b:
        return "does NOT agree (intervals apart)"
    if ra == rb:
        return "inconclusive (equal rates)"
    return f"{'agrees' if ra > rb else 'does not agree'} in the point estimate (intervals overlap)"


def _below_half(r: tuple[float | None, tuple[float, float]]) -> str:
    rate, (lo, hi) = r
    if rate is None:
        return "not measured"
    if hi < 0.5:
        return "agrees (interval below 50 %)"
    if lo > 0.5:
        return "does NOT agree (interval above 50 %)"
    return f"inconclusive (interval {100 * lo:.0f}-{100 * hi:.0f} % spans 50 %)"


def claims(results: StudyResults, speed: dict[tuple[str, str], dict[str, Any]]) -> list[str]:
    """The paper's main claims, each with our measurement and a verdict derived from it.

    Success-rate claims are judged on the 95 % intervals of the pooled rates, which also cover the
    spread between seeds (:func:`.stats.success_interval`): "agrees" /
    "does NOT agree" when the intervals are apart, a point-estimate verdict marked "intervals
    overlap" otherwise. Learning-speed claims compare how many seeds reached the return threshold
    and then the mean episode at which they did.
    """
    rows = ["| paper's claim | our measurement | verdict |", "|---|---|---|"]

    def mean_text(r: dict[str, Any]) -> str:
        return f"mean episode {r['mean']:.0f}" if r["reached"] else "never within the budget"

    # 1. transfer learns faster than SAC-Single (episodes to the return threshold)
    for path in EVAL_TASKS:
        for agent in ("pnn", "spnn"):
            a, b = speed.get((path, agent)), speed.get((path, "sac_single"))
            if not a or not b:
                continue
            ra, rb = a["threshold"], b["threshold"]
            if not ra["reached"] and not rb["reached"]:
                verdict = "not measured (neither reached the threshold)"
            elif ra["reached"] != rb["reached"]:
                verdict = "agrees" if ra["reached"] > rb["reached"] else "does NOT agree"
                verdict += (
                    " (more seeds reached it)"
                    if ra["reached"] > rb["reached"]
                    else " (fewer seeds reached it)"
                )
            else:
                verdict = "agrees" if ra["mean"] <= rb["mean"] else "does NOT agree"
            rows.append(
                f"| {AGENT_LABELS[agent]} reaches a good return in fewer episodes than "
                f"SAC-Single ({path}) | {AGENT_LABELS[agent]}: {ra['reached']}/{ra['runs']} "
                f"seeds, {mean_text(ra)}; SAC-Single: {rb['reached']}/{rb['runs']} seeds, "
                f"{mean_text(rb)} | {verdict} |"
            )
    # 2. SPNN generalizes best; 3. PNN beats the SAC agents; 4. adaptive PID fails on dense tasks
    for path, label, title in GENERALIZATION:
        rates = {a: _rate(results, a, path, label) for a in [*AGENTS, "adaptive_pid"]}
        if rates["spnn"][0] is None:
            continue
        txt = ", ".join(
            f"{AGENT_LABELS[a]} {100 * rates[a][0]:.0f} %" for a in rates if rates[a][0] is not None
        )
        for agent in ("pnn", "sac_single", "sac_multi", "adaptive_pid"):
            if rates[agent][0] is not None:
                rows.append(
                    f"| SPNN succeeds at least as often as {AGENT_LABELS[agent]} on '{title}' | "
                    f"{txt} | {_compare(rates['spnn'], rates[agent])} |"
                )
        for agent in ("sac_single", "sac_multi"):
            if rates["pnn"][0] is not None and rates[agent][0] is not None:
                rows.append(
                    f"| PNN succeeds at least as often as {AGENT_LABELS[agent]} on '{title}' | "
                    f"PNN {100 * rates['pnn'][0]:.0f} %, {AGENT_LABELS[agent]} "
                    f"{100 * rates[agent][0]:.0f} % | {_compare(rates['pnn'], rates[agent])} |"
                )
        if label == "dense" and rates["adaptive_pid"][0] is not None:
            rows.append(
                f"| The adaptive PID mostly fails on '{title}' "
                f"(paper: {'11' if path == 'straight' else '31'} %) | "
                f"{100 * rates['adaptive_pid'][0]:.0f} % | {_below_half(rates['adaptive_pid'])} |"
            )
    for path in EVAL_TASKS:
        pid = _rate(results, "pid", path, "original")
        if pid[0] is not None:
            rows.append(
                f"| A PID tuned for path following cannot finish the {path} planning task | "
                f"{100 * pid[0]:.0f} % success | {_below_half(pid)} |"
            )
    return rows


def _adopted_text(results: Any, study_folder: Path) -> str:
    """How many runs came from an older folder (``python -m sb3_pnn.reproduce.running.adopt``).

    The older folder is named relative to the study folder, so a report copied with its study
    (``../study_3_seeds``) does not carry this machine's absolute paths.
    """
    adopted = [r for r in results.runs.values() if "adopted" in r.manifest]
    if not adopted:
        return ""
    here = study_folder.resolve()
    origins = sorted(
        {os.path.relpath(Path(r.manifest["adopted"]["from"]).parent.parent, here) for r in adopted}
    )
    again = sum("evaluated_again" in r.manifest["adopted"] for r in adopted)
    how = (
        f"adopted unchanged ({again} of them evaluated again as newly played)"
        if again
        else "adopted unchanged"
    )
    return (
        f"; {len(adopted)} of them {how} from {', '.join(origins)} "
        "(`python -m sb3_pnn.reproduce.running.adopt`; their invocations are counted below)"
    )


def _sessions_text(sessions: list[dict[str, Any]]) -> str:
    return ", ".join(
        f"{s['wall_s'] / 60:.1f} min with --jobs {s['jobs']}"
        + (", stopped" if s.get("stopped") else "")
        for s in sessions
    )


def cost_table(results: StudyResults) -> list[str]:
    """Mean wall and CPU seconds per run, by kind and agent (what the budget is made of)."""
    groups: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in results.runs.values():
        key = (r.spec.kind, AGENT_LABELS.get(r.spec.agent, r.spec.agent))
        groups.setdefault(key, []).append(r.manifest)
    lines = [
        "## Cost per run",
        "",
        "| kind | agent | runs | mean wall (s) | mean CPU (s) | mean training steps |",
        "|---|---|---|---|---|---|",
    ]
    for (kind, agent), ms in sorted(groups.items()):
        wall = sum(float(m.get("wall_s", 0.0)) for m in ms) / len(ms)
        cpus = [float(m["cpu_s"]) for m in ms if "cpu_s" in m]
        cpu = f"{sum(cpus) / len(cpus):.1f}" if cpus else "-"
        steps = [int(m["timesteps"]) for m in ms if m.get("timesteps") is not None]
        steps_s = f"{sum(steps) / len(steps):.0f}" if steps else "-"
        lines.append(f"| {kind} | {agent} | {len(ms)} | {wall:.1f} | {cpu} | {steps_s} |")
    return lines


def setup_text(config: StudyConfig) -> str:
    """The study's training set-up in words: its name, ``--set`` changes, every factor."""
    from sb3_pnn.reproduce.planning.setups import FACTOR_LABELS, describe_value

    setup = config.setup
    name = f"`{config.setup_name}`"
    if config.setup_changes:
        name += " with --set " + " ".join(f"{k}={v}" for k, v in config.setup_changes)
    factors = "; ".join(
        f"{FACTOR_LABELS[k]} {describe_value(k, v)}" for k, v in setup.to_dict().items()
    )
    return f"{name} ({factors})"


def _selection_text(results: StudyResults, setup: TrainingSetup) -> str:
    """Which candidate became each source column (``prior_candidates`` > 1, or the straight
    path-following column's ``prior_candidates_pf_straight``), for the set-up."""
    counts = {name: setup.column_candidates(name) for name in PRIOR_ENVS}
    if max(counts.values()) == 1:
        return ""
    chosen = [
        f"{r.spec.run_id} = {r.manifest['chosen']}"
        for r in sorted(results.select("select"), key=lambda r: r.spec.run_id)
        if "chosen" in r.manifest
    ]
    if len(set(counts.values())) == 1:
        (k,) = set(counts.values())
        which = f"each column the best of {k} training runs"
    else:
        which = ", ".join(
            f"the {name} column the best of {k} training runs"
            for name, k in counts.items()
            if k > 1
        )
    return f", {which} on validation episodes of its own task" + (
        f" ({', '.join(chosen)})" if chosen else ""
    )


def _setup_lines(
    results: StudyResults, config: StudyConfig, sessions: list[dict[str, Any]], folder: Path
) -> list[str]:
    """The report's "Set-up" section: budgets, evaluation, set-up, runs, cost, machine."""
    budget = config.budget
    train_runs = [r for r in results.runs.values() if r.spec.kind != "baseline"]
    run_s = sum(float(r.manifest.get("wall_s", 0.0)) for r in results.runs.values())
    cpu_s = sum(float(r.manifest.get("cpu_s", 0.0)) for r in results.runs.values())
    cores = os.cpu_count() or 1
    total_wall = sum(float(s.get("wall_s", 0.0)) for s in sessions)
    prior_text = (
        "one set per seed"
        if config.prior_per_seed
        else "one set (seed 0) shared by all seeds, so the intervals below cover the agents' "
        "training seeds, not the draw of these columns (`--prior-per-seed` trains a set per seed)"
    ) + _selection_text(results, config.setup)
    seeds = sorted({r.spec.seed for r in results.runs.values() if r.spec.kind == "transfer"})
    column_episodes = {  # the set-up's (oa_budget scales the avoidance column's)
        name: config.setup.column_episodes(name, episodes)
        for name, episodes in budget.prior_episodes.items()
    }
    return [
        "## Set-up",
        "",
        f"- budget: `{config.budget_name}`; seeds: {config.seeds} (training seeds {seeds}); "
        f"priors: {prior_text}; learners: "
        + ", ".join(AGENT_LABELS[a] for a in config.agents)
        + ("" if len(config.agents) == len(AGENTS) else " (`--agents`: the others not trained)"),
        f"- training episodes: priors {column_episodes}; agents on the planning tasks "
        f"{budget.transfer_episodes} (paper: about 300 straight / 400 sine)",
        f"- evaluation: {budget.eval_episodes} episodes per policy and task, seeds 10000.., "
        "start pose "
        "perturbed by the evaluation library's default noise; success rates are pooled over "
        "seeds, each with a 95 % interval that is the hull of the pooled episodes' Wilson "
        "interval and the Student-t interval of the mean of the per-seed rates (a run's "
        "episodes are not independent draws; the per-seed rates are tabulated)",
        f"- training set-up: {setup_text(config)}",
        "- DiscreteSAC otherwise as the paper's Tables 2-3 (lr 3e-4, Polyak 0.005, gamma 0.99, "
        "alpha from 0.2, buffer 1e6, batch 256), learning_starts 256",
        f"- runs finished: {len(results.runs)} ({len(train_runs)} trained); "
        f"missing: {len(results.missing)}; "
        f"failed: {len(results.failures)}{_adopted_text(results, folder)}",
        f"- wall-clock: {total_wall / 60:.1f} min over {len(sessions)} invocation(s) "
        f"({_sessions_text(sessions)}); "
        f"sum of run wall times {run_s / 60:.1f} min; sum of run CPU times {cpu_s / 60:.1f} min, "
        f"so at least {cpu_s / 60 / cores:.1f} min on this machine's {cores} cores when it is "
        "otherwise idle (wall times grow when other work shares the cores); drawing the figures "
        "and this report comes on top (printed by the command)",
        f"- machine: {machine()}",
        "- versions: " + ", ".join(f"{k} {v}" for k, v in versions().items()),
        f"- {end_reasons_text(config.setup.heading_rule)}",
        "",
    ]


def _title_lines(config: StudyConfig) -> list[str]:
    """The title, what the report measures and, for a smoke-test budget, that it gives no
    verdicts."""
    budget = config.budget
    lines = [
        "# Reproduction of Pan et al. (2025), section 4.3 (Figures 10-20)",
        "",
        f"Generated {time.strftime('%Y-%m-%d %H:%M:%S UTC', time.gmtime())} by "
        "`python -m sb3_pnn.reproduce`. Everything below is measured in this study folder; "
        "the paper's numbers are quoted for comparison. Simulator: rov_envs (a Fossen-model "
        "BlueROV2, not the paper's Gazebo/UUV Simulator), so absolute returns differ from "
        "the paper's.",
        "",
    ]
    if config.budget_name in SMOKE_BUDGETS:
        lines += [
            f"**Smoke test** (budget `{config.budget_name}`: "
            f"{max(budget.transfer_episodes.values())} training episodes per agent, "
            f"{budget.eval_episodes} evaluation episodes per policy and task): it checks that "
            "the study runs end to end. Numbers this small cannot confirm or refute the paper, "
            "so this report gives no verdicts; the full study (`python -m sb3_pnn.reproduce`, "
            "without `--quick`) does.",
            "",
        ]
    return lines


def _failure_lines(results: StudyResults) -> list[str]:
    """Why each missing run is missing (empty when none is)."""
    if not (results.failures or results.missing):
        return []
    lines = ["## Failures and missing runs", ""]
    for run_id in results.missing:
        fail = results.failures.get(run_id)
        why = (
            fail["error"].strip().splitlines()[-1]
            if fail
            else "not run (dependency failed or study interrupted)"
        )
        lines.append(f"- `{run_id}`: {why}")
    return [*lines, ""]


def write_report(
    results: StudyResults,
    config: StudyConfig,
    figures: list[str],
    sessions: list[dict[str, Any]],
    path: Any,
    jobs: int,
) -> None:
    """Write report.md (atomically) to ``path``, a file in the study folder."""
    speed_lines, speed = learning_speed(results)
    smoke = config.budget_name in SMOKE_BUDGETS
    checks = validation_table(results)
    columns = columns_table(results)
    lines = [
        *_title_lines(config),
        *_setup_lines(results, config, sessions, Path(path).parent),
        *_failure_lines(results),
        *cost_table(results),
        "",
        "## Figure 20: success on the new tasks (ours beside the paper's)",
        "",
        *success_table(results),
        "",
        *checks,
        *([""] if checks else []),
        *columns,
        *([""] if columns else []),
        "## Learning speed (Figure 10)",
        "",
        *speed_lines,
        "",
        "## Do we agree with the paper?",
        "",
        *(["No verdicts from a smoke test (see the top)."] if smoke else claims(results, speed)),
        "",
        "## Route keeping (Figures 12, 13, 15-19)",
        "",
        *route_table(results),
        "",
        "## Figures",
        "",
    ]
    for name in figures:
        lines += [f"### {name}", "", f"![{name}](figures/{name})", ""]
    from sb3_pnn.common.atomic import write_text_atomic

    write_text_atomic(path, "\n".join(lines) + "\n")
