"""The default goalkeeper run end to end: virtual keeper, synthetic camera, color shirt."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import pytest
from apps.goalkeeper.__main__ import main

pytestmark = [pytest.mark.slow, pytest.mark.gl]


def test_default_run_blocks_balls_on_tracked_poses_and_writes_its_files(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["--headless", "--out", str(tmp_path), "--shots", "4", "--no-progress"])
    out = capsys.readouterr().out
    assert code == 0 and "goalkeeper.mp4" in out and "summary.json" in out
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["input"].startswith("virtual player") and "colorshirt" in s["input"]
    assert s["tracking_share"] > 0.9
    assert s["shots"] == 4 and s["saves"] >= 2, s["shot_log"]
    for e in s["shot_log"]:
        if e["outcome"] == "save":
            assert e["group"] in ("hand", "arm", "body", "head")
    assert set(s["hand_motion"]) == {"l_wrist", "r_wrist"}
    assert (tmp_path / "goalkeeper_hands.png").exists()
    cap = cv2.VideoCapture(str(tmp_path / "goalkeeper.mp4"))
    assert int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) >= 30 * s["game_seconds"] - 2
    cap.release()
