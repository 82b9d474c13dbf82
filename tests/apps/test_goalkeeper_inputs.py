"""The goalkeeper's image inputs: a capture without the shirt is a clear error."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from apps.goalkeeper.game import GoalkeeperGame, GoalkeeperOptions

from bodyplay.app import make_game_options, run_game
from bodyplay.capture.camera import Camera, look_at, write_calib
from bodyplay.capture.video import VideoWriter
from bodyplay.errors import CaptureError

pytestmark = pytest.mark.gl


def _empty_room(folder: Path, seconds: float = 1.5) -> None:
    """A capture folder of a room with nobody in it (a noisy grey wall)."""
    folder.mkdir()
    R, t = look_at((0.0, 1.2, 3.0), (0.0, 1.0, 0.0))
    write_calib(folder / "calib.json", [Camera.from_fov("cam0", 320, 240, 60.0, R, t)])
    rng = np.random.default_rng(0)
    with VideoWriter(folder / "cam0.mp4", 30.0) as video:
        for _ in range(int(seconds * 30)):
            video.write(np.clip(rng.normal(120, 6, (240, 320, 3)), 0, 255).astype(np.uint8))


def test_capture_without_the_shirt_stops_with_a_message_naming_the_default(
    tmp_path: Path,
) -> None:
    _empty_room(tmp_path / "room")
    opts = make_game_options(input=str(tmp_path / "room"), headless=True, out=tmp_path / "o",
                             video=False, progress=False, no_player_seconds=1.0)
    with pytest.raises(CaptureError) as info:
        run_game(GoalkeeperGame(GoalkeeperOptions(shots=2)), opts)
    msg = str(info.value)
    assert "no player found" in msg and "shirt" in msg and "--input virtual" in msg


def test_a_mocap_clip_as_pose_input_plays_a_round(tmp_path: Path) -> None:
    run_game(GoalkeeperGame(GoalkeeperOptions(shots=2)),
             make_game_options(input="pose:13_29", headless=True, out=tmp_path, video=False,
                               progress=False, seconds=5.0))
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["game"] == "goalkeeper" and s["input"].startswith("clip 13_29")
    assert s["frames"] > 100 and s["tracking_share"] == 1.0
    assert s["shots"] == 2 and s["game_seconds"] <= 5.0
    assert (tmp_path / "goalkeeper_hands.png").exists()


def test_a_recording_plays_a_round(tmp_path: Path) -> None:
    from bodyplay.record import record_session
    from bodyplay.runtime import ClipPoseSource, FixedClock, create_session

    src = ClipPoseSource("13_29", fps=30.0, upper_body_only=True)
    session = create_session(source=src, clock=FixedClock(1 / 30))
    rec = record_session(session, tmp_path / "keeper.jsonl")
    session.run(max_frames=200)
    rec.close()
    session.close()
    out = tmp_path / "out"
    run_game(GoalkeeperGame(GoalkeeperOptions(shots=2)),
             make_game_options(input=str(tmp_path / "keeper.jsonl"), headless=True, out=out,
                               video=False, progress=False))
    s = json.loads((out / "summary.json").read_text())
    assert s["input"].startswith("recording") and 100 < s["frames"] <= 200
    assert s["shots"] == 2 and s["tracking_share"] == 1.0
