"""What the planning task's reward pays for a route: a wider detour round the obstacles earns
more return (eq. 20's charges near them) and keeps a wider route; bad options are refused."""

from __future__ import annotations

import pytest
from reproduce_helpers import pid_baseline_run

from sb3_pnn.reproduce.tools.reward_route import best, main, within_mark


def _rows(out: str) -> dict[float, list[str]]:
    rows = {}
    for line in out.splitlines():
        if line.startswith("| adaptive PID, clearance "):
            cells = [c.strip() for c in line.strip("|").split("|")]
            rows[float(cells[0].split()[3])] = cells[1:]
    return rows


def test_a_wider_detour_earns_more_return_and_keeps_a_wider_route(tmp_path, capsys) -> None:
    """On PlanningStraight a PID passing obstacles at 2.5 m spends its passes inside eq. 20's
    -4 / -2 zones (within 5 / 8 m of a surface); passing at 10 m it avoids most of them and
    earns more, at a wider route."""
    pid_baseline_run(tmp_path)
    argv = [str(tmp_path), "--agents", "--clearances", "2.5", "10", "--triggers", "18"]
    assert main([*argv, "--episodes", "3", "--parts"]) == 0
    out = capsys.readouterr().out
    measured, parts = out.split("the return's terms")
    rows, terms = _rows(measured), _rows(parts)
    tight, wide = rows[2.5], rows[10.0]
    assert tight[0] == wide[0] == "100 %"
    assert float(wide[1]) > float(tight[1]) + 50  # return
    assert float(wide[3]) > float(tight[3])  # mean abs(g)
    assert "highest return: clearance 10 m, trigger 18 m" in out
    for clearance in (2.5, 10.0):  # the terms add up to the return of the same episodes
        r_c, r_v, terminal = (float(v) for v in terms[clearance][:3])
        assert r_c + r_v + terminal == pytest.approx(float(rows[clearance][1]), abs=0.15)
        assert terminal == 200.0  # every episode ends with the success bonus
    # the wide detour spends fewer steps in eq. 20's zone and pays less of its charge
    assert float(terms[10.0][4]) < float(terms[2.5][4])
    assert float(terms[10.0][1]) > float(terms[2.5][1])


def test_best_needs_success_and_the_marks() -> None:
    rows = [
        {"success": 1.0, "return": 300.0, "g": 2.5, "ac": 25.0, "clearance": 10.0},
        {"success": 0.9, "return": 400.0, "g": 1.0, "ac": 10.0, "clearance": 12.0},
        {"success": 1.0, "return": 250.0, "g": 1.5, "ac": 15.0, "clearance": 4.5},
    ]
    assert best(rows, in_mark=False)["clearance"] == 10.0  # the 400 fails too often
    assert best(rows, in_mark=True)["clearance"] == 4.5
    assert not within_mark({"g": 1.9, "ac": 20.5})
    assert best(rows[1:2], in_mark=False) is None


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--clearances", "2.5", "0"], "--clearances [2.5, 0.0] is not allowed"),
        (["--triggers", "-1"], "--triggers [-1.0] is not allowed"),
        (["--gamma", "1.5"], "--gamma must be a number in (0, 1] (a discount), got '1.5'"),
    ],
)
def test_bad_options_are_refused_by_name(tmp_path, capsys, argv, message) -> None:
    pid_baseline_run(tmp_path)
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), *argv])
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


def test_a_study_without_the_pid_run_is_refused(tmp_path, capsys) -> None:
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), "--path", "sine"])
    assert stop.value.code == 2
    assert "adaptive PID's run on the sine path" in capsys.readouterr().err
