"""``train --help`` / ``enjoy --help``: one help text with one usage, every flag described once."""

from __future__ import annotations

import re

import pytest

from sb3_pnn.zoo.cli import ENJOY_PROG, TRAIN_PROG, enjoy_main, train_main


@pytest.mark.parametrize(
    ("main", "prog", "ours", "zoos"),
    [
        (train_main, TRAIN_PROG, "--priors", "--n-trials"),
        (enjoy_main, ENJOY_PROG, "--record", "--load-best"),
    ],
)
def test_help_has_one_usage_and_describes_each_flag_once(main, prog, ours, zoos, capsys) -> None:
    main(["--help"])
    text = capsys.readouterr().out
    assert text.startswith(f"usage: {prog} ") and text.count("usage:") == 1
    usage = text.split("\n\n")[0]
    assert f"[{ours} " in usage and f"[{zoos}" in usage  # ours and rl_zoo3's in one usage
    for flag in (ours, zoos):
        described = re.findall(rf"^  {flag}\b(?!,)", text, flags=re.MULTILINE)
        assert len(described) == 1, (flag, described)
