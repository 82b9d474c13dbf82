"""Specification of ``bodyplay show-clip``: a real clip rendered on the actor to a video."""

from __future__ import annotations

from pathlib import Path

import cv2
import pytest

from bodyplay.cli import main

pytestmark = pytest.mark.gl


def test_show_clip_renders_the_actor_in_the_shirt_to_a_video(synth_gl: object,
                                                             tmp_path: Path) -> None:
    out = tmp_path / "clip.mp4"
    still = tmp_path / "still.png"
    code = main(["show-clip", "13_29", "--start", "20", "--seconds", "0.4", "--size", "320x240",
                 "--out", str(out), "--still", str(still)])
    assert code == 0
    cap = cv2.VideoCapture(str(out))
    n = int(cap.get(cv2.CAP_PROP_FRAME_COUNT))
    cap.release()
    assert n in (12, 13)  # 0.4 s at 30 fps, end frame included or not
    image = cv2.imread(str(still))[:, :, ::-1].astype(int)
    # the shirt's saturated colors are visible against the gray gravel background
    saturation = image.max(axis=2) - image.min(axis=2)
    assert (saturation > 120).mean() > 0.01


def test_show_clip_rejects_a_start_beyond_the_clip(tmp_path: Path) -> None:
    assert main(["show-clip", "13_29", "--start", "999", "--out", str(tmp_path / "x.mp4")]) == 2
