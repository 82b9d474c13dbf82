"""Specifications of the validation set's tag comparison (benchmarks/colorshirt_compare.py)."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

import pytest


@pytest.fixture(scope="module")
def compare(script_loader: Callable[..., ModuleType]) -> ModuleType:
    return script_loader("benchmarks/colorshirt_compare.py")


def _row(tag: str, clip: str, cm: float, found: float = 1.0, draw: int = 0,
         setting: str = "steady-2-view") -> dict[str, object]:
    return {"tag": tag, "clip": clip, "setting": setting, "mpjpe_cm": cm, "found": found,
            "draw": draw}


def test_compare_counts_only_clips_both_tags_ran_and_those_that_moved(compare) -> None:  # type: ignore[no-untyped-def]
    rows = [_row("main", "a", 4.0), _row("main", "b", 6.0), _row("main", "c", 10.0),
            _row("new", "a", 3.0), _row("new", "b", 6.1, found=0.9)]
    c = compare.compare(rows, "main", "new", "steady-2-view", threshold=0.2)
    assert c.clips == 2
    assert c.base == pytest.approx((5.0, 6.0, 5.0))
    assert c.new == pytest.approx((4.55, 6.1, 4.55))
    assert (c.better, c.worse) == (1, 0)
    assert c.found_new == pytest.approx((0.95, 0.9))


def test_compare_counts_a_clip_without_any_pose_apart_from_the_errors(compare) -> None:  # type: ignore[no-untyped-def]
    rows = [_row("main", "a", 4.0), _row("main", "b", float("nan"), found=0.0),
            _row("new", "a", 5.0), _row("new", "b", 30.0, found=0.5)]
    c = compare.compare(rows, "main", "new", "steady-2-view")
    assert c.base == pytest.approx((4.0, 4.0, 4.0))
    assert c.new == pytest.approx((17.5, 30.0, 17.5))
    assert c.lost == (1, 0)
    assert (c.better, c.worse) == (0, 1)


def test_compare_keeps_draws_apart(compare) -> None:  # type: ignore[no-untyped-def]
    rows = [_row("main", "a", 4.0, draw=0), _row("new", "a", 3.0, draw=1)]
    assert compare.compare(rows, "main", "new", "steady-2-view", draw=0) is None
    assert compare.compare(rows, "main", "new", "steady-2-view", draw=1) is None


def test_compare_reads_rows_of_several_files_and_prints_a_table(compare, tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    a, b = tmp_path / "a.jsonl", tmp_path / "b.jsonl"
    a.write_text(json.dumps(_row("main", "x", 5.0, draw=1)) + "\n")
    b.write_text(json.dumps(_row("new", "x", 4.0, draw=1)) + "\n")
    assert compare.main(["--results", f"{a},{b}", "--base", "main", "--tags", "new",
                         "--draw", "1", "--per-clip"]) == 0
    out = capsys.readouterr().out
    assert ("| steady-2-view | new | 1 | 5.00 / 5.00 / 5.00 | 4.00 / 4.00 / 4.00 | 1 / 0 | "
            "0 -> 0 |") in out
    assert "5.00 ->   4.00 (-1.00)" in out


def test_compare_names_a_missing_results_file(compare, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(SystemExit, match="no such results file"):
        compare.main(["--results", str(tmp_path / "nope.jsonl"), "--base", "m", "--tags", "n"])
