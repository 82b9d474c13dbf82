"""End to end: the default headless ninja run, through the synthetic camera and the
default tracker, checked against the virtual ninja's own script."""

from __future__ import annotations

import json

import pytest


@pytest.mark.slow
@pytest.mark.gl
def test_default_headless_run_wins_a_whole_fight_with_every_motion_recognized_in_time(
        tmp_path, synth_gl):
    from apps.ninja.__main__ import default_tracker, main

    code = main(["--headless", "--out", str(tmp_path), "--no-progress"])
    assert code == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert (tmp_path / "ninja.mp4").stat().st_size > 50_000
    assert f"{default_tracker()} tracker" in s["input"]  # colorshirt: see docs/ninja.md
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
