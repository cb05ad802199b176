"""tools.spnn_switch_distance's command line: bad arguments and missing runs stop with a message."""

from __future__ import annotations

import pytest

from sb3_pnn.reproduce.tools.spnn_switch_distance import main


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--hysteresis", "-1"], "argument --hysteresis: -1 is not allowed"),
        (["--hysteresis", "inf"], "argument --hysteresis: inf is not allowed"),
        (["--hysteresis", "far"], "argument --hysteresis: far is not allowed"),
        (["--d-th", "nan"], "--d-th nan is not allowed"),
        (["--seeds", "-2"], "--seeds [-2] is not allowed"),
        (["--episodes", "0"], "--episodes 0 is not allowed"),
    ],
)
def test_bad_arguments_stop_with_a_message(tmp_path, capsys, args, message) -> None:
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), *args])
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


def test_a_missing_run_stops_with_a_message(tmp_path, capsys) -> None:
    with pytest.raises(SystemExit):
        main([str(tmp_path), "--seeds", "0"])
    assert "spnn-straight-s0/model.zip does not exist" in capsys.readouterr().err
