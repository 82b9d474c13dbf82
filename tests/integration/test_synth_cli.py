"""Specifications of `bodyplay synth`: the capture folder it writes, repeatability, errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

from bodyplay.capture.camera import read_calib
from bodyplay.capture.jsonl import read_pose_jsonl
from bodyplay.capture.sources import CaptureFolderSource
from bodyplay.cli import main

pytestmark = pytest.mark.gl

ARGS = ["--clip", "13_29", "--start", "3", "--frames", "4", "--size", "320x240",
        "--format", "png", "--seed", "11", "--noise", "medium"]


def test_synth_writes_a_capture_folder_whose_truth_lands_on_the_actor(synth_gl, tmp_path):
    out = tmp_path / "cap"
    assert main(["synth", *ARGS, "--background", "plain", "--cameras", "2", "--out",
                 str(out)]) == 0
    cams = read_calib(out)
    truth = read_pose_jsonl(out / "truth.jsonl")
    assert [c.name for c in cams] == ["cam0", "cam1"]
    assert list(truth.frames) == [0, 1, 2, 3]
    assert np.allclose(truth.t, np.arange(4) / 30.0)
    with CaptureFolderSource(out) as src:
        sets = list(src)
    assert len(sets) == 4
    for fs, joints in zip(sets, truth.joints, strict=True):
        for frame, cam in zip(fs, cams, strict=True):
            uv = np.round(cam.project(joints)).astype(int)
            assert np.all((uv >= 0) & (uv < [cam.width, cam.height]))
            wall = np.median(frame.image.reshape(-1, 3), axis=0)
            diff = np.abs(frame.image.astype(int) - wall).sum(axis=2)
            on_actor = diff[uv[:, 1], uv[:, 0]] > 25
            assert on_actor.mean() >= 0.9, f"{cam.name}: {on_actor}"
    meta = json.loads((out / "meta.json").read_text())
    assert meta["options"]["cameras"] == 2 and meta["run"]["clip"] == "13_29"
    assert meta["frames"] == 4


def test_lead_in_renders_the_empty_room_first_with_null_truth(synth_gl, tmp_path):
    out = tmp_path / "cap"
    assert main(["synth", *ARGS, "--background", "plain", "--lead-in", "0.1", "--out",
                 str(out)]) == 0
    truth = read_pose_jsonl(out / "truth.jsonl")
    assert list(truth.frames) == list(range(7))  # 3 empty-room frames, then the 4 of the clip
    assert np.allclose(truth.t, np.arange(7) / 30.0)
    assert not truth.reported[:3].any() and truth.reported[3:].all()
    with CaptureFolderSource(out) as src:
        images = [fs.frames[0].image.astype(int) for fs in src]
    wall = np.median(images[0].reshape(-1, 3), axis=0)
    assert np.abs(images[0] - wall).sum(axis=2).max() < 40  # nobody there
    assert (np.abs(images[3] - wall).sum(axis=2) > 40).mean() > 0.01  # the actor
    assert json.loads((out / "meta.json").read_text())["run"]["lead_in"] == 0.1


def test_same_seed_gives_same_png_bytes_and_repeat_from_meta_too(synth_gl, tmp_path):
    a, b, c = tmp_path / "a", tmp_path / "b", tmp_path / "c"
    assert main(["synth", *ARGS, "--lighting", "switch", "--out", str(a)]) == 0
    assert main(["synth", *ARGS, "--lighting", "switch", "--out", str(b)]) == 0
    assert main(["synth", "--repeat", str(a / "meta.json"), "--out", str(c)]) == 0
    for i in range(4):
        name = f"cam0/{i:06d}.png"
        assert (a / name).read_bytes() == (b / name).read_bytes() == (c / name).read_bytes()
    assert (a / "truth.jsonl").read_text() == (c / "truth.jsonl").read_text()
    assert json.loads((a / "meta.json").read_text())["options"] == json.loads(
        (c / "meta.json").read_text()
    )["options"]


def test_synth_writes_mp4_by_default(synth_gl, tmp_path):
    out = tmp_path / "mp4"
    args = [a for a in ARGS if a not in ("--format", "png")]
    assert main(["synth", *args, "--occlude", "0:0.05", "--out", str(out)]) == 0
    with CaptureFolderSource(out) as src:
        assert src.frame_count == 4 and src.fps == pytest.approx(30.0)


@pytest.mark.parametrize(
    ("extra", "message"),
    [(["--lighting", "disco"], "unknown lighting preset"),
     (["--size", "640by480"], "WIDTHxHEIGHT"),
     (["--noise", "loud"], "unknown noise level"),
     (["--occlude", "soon"], "START:SECONDS")],
)
def test_synth_bad_options_exit_2_with_a_clear_message(tmp_path, capsys, extra, message):
    assert main(["synth", *ARGS, *extra, "--out", str(tmp_path / "x")]) == 2
    assert message in capsys.readouterr().err


def test_synth_unreadable_clip_is_a_clear_error(tmp_path, capsys):
    bad = tmp_path / "broken.bvh"
    bad.write_text("HIERARCHY\nROOT hips {\n")
    assert main(["synth", "--clip", str(bad), "--out", str(tmp_path / "x")]) == 2
    assert "broken.bvh" in capsys.readouterr().err
    assert main(["synth", "--clip", "no_such_clip", "--out", str(tmp_path / "y")]) == 2
    assert "no_such_clip" in capsys.readouterr().err
