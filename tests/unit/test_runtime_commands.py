"""Specifications of the `events`, `record`, `replay` and `export` commands."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import pytest

from bodyplay.cli import main
from bodyplay.record import read_recording
from bodyplay.testing import ScriptedPlayer, Timeline


@pytest.fixture(scope="module")
def clip_bvh(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from bodyplay.motion.bvh import write_bvh

    tl = Timeline().hold("idle", 0.5).gesture("raise_both_hands").hold("idle", 0.5)
    player = ScriptedPlayer(tl, fps=30.0)
    poses = [q for _, q in player.poses()]
    path = tmp_path_factory.mktemp("clip") / "raise.bvh"
    import numpy as np

    write_bvh(path, tl.skeleton, np.stack(poses), 30.0)
    return path


def test_events_command_writes_one_json_event_per_line(clip_bvh: Path, tmp_path: Path) -> None:
    out = tmp_path / "events.jsonl"
    assert main(["events", "--clip", str(clip_bvh), "--out", str(out)]) == 0
    lines = [json.loads(x) for x in out.read_text().splitlines()]
    kinds = {d["type"] for d in lines}
    assert {"pose", "tracking"} <= kinds
    assert all({"type", "t", "emitted_t"} <= set(d) for d in lines)
    assert sum(d["type"] == "pose" for d in lines) == 76


def test_events_command_reports_a_missing_tracker_plugin(tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]
                                                         ) -> None:
    rc = main(["events", "--input", str(tmp_path), "--tracker", "nonesuch",
               "--out", str(tmp_path / "e.jsonl")])
    assert rc == 2
    assert "tracker 'nonesuch' is not installed" in capsys.readouterr().err


def test_record_replay_and_export_round_trip(clip_bvh: Path, tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    rec = tmp_path / "rec.jsonl"
    assert main(["record", "--clip", str(clip_bvh), "--out", str(rec), "--gestures",
                 "none", "--max-frames", "40"]) == 0
    assert len(read_recording(rec).poses) == 40
    video = tmp_path / "replay.mp4"
    assert main(["replay", str(rec), "--out", str(video), "--view", "90,10",
                 "--size", "320x240"]) == 0
    printed = capsys.readouterr().out
    assert "r_wrist: peak speed" in printed and "l_wrist: peak speed" in printed
    cap = cv2.VideoCapture(str(video))
    assert int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) == 40
    ok, frame = cap.read()
    assert ok and frame.shape[1] == 320 + 240
    bvh = tmp_path / "out.bvh"
    assert main(["export", str(rec), "--format", "bvh", "--out", str(bvh)]) == 0
    text = bvh.read_text()
    assert text.startswith("HIERARCHY") and "Frames: 40" in text
    poses = tmp_path / "poses.jsonl"
    assert main(["export", str(rec), "--format", "poses", "--out", str(poses)]) == 0
    first = json.loads(poses.read_text().splitlines()[0])
    assert first["frame"] == 0 and "r_wrist" in first["joints"]
