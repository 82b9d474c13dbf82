"""End to end: the default headless ninja run, through the synthetic camera and the
default tracker (the paper's silhouette tracker), and the same with the color-shirt
tracker, each checked against the virtual ninja's own script."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest


def _check_a_whole_fight_won_with_every_motion_recognized(out: Path) -> dict[str, Any]:
    s: dict[str, Any] = json.loads((out / "summary.json").read_text())
    assert (out / "ninja.mp4").stat().st_size > 50_000
    assert s["result"] == "won" and s["health"]["opponent"] == 0
    kinds = {a["kind"] for a in s["attacks"] if a["outcome"] != "pending"}
    assert kinds == {"high", "sweep"}
    assert all(a["outcome"] in ("dodged", "pending") for a in s["attacks"])
    check = s["script_check"]
    performed = {m["gesture"] for m in check["motions"]}
    assert performed == {"transfigure", "crouch", "step_left", "step_right", "hit",
                         "double_hit"}
    assert check["missed"] == [] and check["unexpected"] == []
    assert all(m["latency"] <= 0.6 for m in check["motions"])
    return s


@pytest.mark.slow
@pytest.mark.gl
def test_default_headless_run_wins_a_whole_fight_with_every_motion_recognized_in_time(
        tmp_path, synth_gl):
    from apps.ninja.__main__ import default_tracker, main

    assert default_tracker() == "silhouette"  # the paper's setup
    code = main(["--headless", "--out", str(tmp_path), "--no-progress"])
    assert code == 0
    s = _check_a_whole_fight_won_with_every_motion_recognized(tmp_path)
    assert "silhouette tracker" in s["input"]


@pytest.mark.slow
@pytest.mark.gl
def test_color_shirt_run_wins_a_whole_fight_with_every_motion_recognized_in_time(
        tmp_path, synth_gl):
    from apps.ninja.__main__ import main

    code = main(["--headless", "--tracker", "colorshirt", "--out", str(tmp_path),
                 "--no-progress"])
    assert code == 0
    s = _check_a_whole_fight_won_with_every_motion_recognized(tmp_path)
    assert "colorshirt tracker" in s["input"]
