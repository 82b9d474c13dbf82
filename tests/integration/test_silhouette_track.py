"""The silhouette tracker end to end on a short synthetic capture (player in view from
frame 0, no empty room), with the tiny hierarchy of the ``silhouette_tree`` fixture."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.capture.jsonl import read_pose_jsonl
from bodyplay.capture.sources import open_source
from bodyplay.cli import main
from bodyplay.errors import TimestampError
from bodyplay.trackers.silhouette import SilhouetteOptions, create_silhouette_tracker

pytestmark = pytest.mark.gl


def test_silhouette_tracker_follows_a_synthetic_walk(synth_gl, tmp_path, silhouette_tree):
    out = tmp_path / "cap"
    assert main(["synth", "--clip", "131_01", "--frames", "40", "--out", str(out)]) == 0
    truth = read_pose_jsonl(out / "truth.jsonl")
    src = open_source(out)
    assert src.cameras is not None
    tracker = create_silhouette_tracker(SilhouetteOptions(body="m"), src.cameras[:1],
                                        tree=silhouette_tree)
    errs, found, last = [], 0, None
    with src:
        for fs in src:
            r = tracker.process(fs)
            last = fs
            assert r.extras["silhouette"].dtype == np.uint8  # the mask, for overlays
            if r.found:
                found += 1
                errs.append(np.linalg.norm(r.joints - truth.joints[fs.index], axis=1).mean())
                assert set(r.state) <= {"tracked", "inferred"}
    assert found >= 0.9 * len(truth.frames)
    assert float(np.median(errs)) < 0.35  # a tiny tree: coarse, but on the player
    assert last is not None
    with pytest.raises(TimestampError):
        tracker.process(last)


@pytest.fixture(scope="module")
def three_body_tree(tmp_path_factory):  # type: ignore[no-untyped-def]
    """A small hierarchy (one short CMU clip) rendered for three body presets."""
    from bodyplay.trackers.silhouette import HierarchyOptions, load_or_build_tree

    opts = HierarchyOptions(clips=("131_01",), yaw_offsets_deg=(0.0,), random_share=0.05,
                            bodies=("xs", "m", "xl"), thresholds=(0.06, 0.04, 0.03),
                            max_poses=400)
    return load_or_build_tree(opts, tmp_path_factory.mktemp("silhouette_cache3"))


@pytest.mark.slow
@pytest.mark.parametrize("body", ["xs", "xl"])
def test_automatic_body_choice_picks_the_actors_preset(synth_gl, tmp_path, three_body_tree,
                                                       body):
    # the player in view from the first frame; the distance alone picked xl for every
    # actor before (unknown pixels near the player were free to a larger template)
    out = tmp_path / "cap"
    assert main(["synth", "--clip", "131_01", "--frames", "60", "--body", body,
                 "--out", str(out)]) == 0
    src = open_source(out)
    assert src.cameras is not None
    tracker = create_silhouette_tracker(SilhouetteOptions(select_frames=30), src.cameras[:1],
                                        tree=three_body_tree)
    with src:
        for fs in src:
            tracker.process(fs)
    assert tracker.body_name == body


@pytest.mark.slow
def test_body_choice_waits_for_the_player_to_move(synth_gl, tmp_path, three_body_tree):
    # the player stands still in view for a second (the first frame repeated): the
    # silhouette is only the first frame's colour segmentation, so the body is not
    # chosen then, however many frames pass; it is chosen once the player has moved
    from bodyplay.capture.frames import Frame, FrameSet

    out = tmp_path / "cap"
    assert main(["synth", "--clip", "131_01", "--frames", "45", "--body", "xs",
                 "--out", str(out)]) == 0
    src = open_source(out)
    assert src.cameras is not None
    tracker = create_silhouette_tracker(SilhouetteOptions(select_frames=10, select_wait=5.0),
                                        src.cameras[:1], tree=three_body_tree)
    with src:
        frames = list(src)
    first = frames[0].frames[0].image
    for i in range(30):
        tracker.process(FrameSet((Frame(first, i / 30, i),), i / 30, i))
    assert tracker.body_name is None
    for fs in frames[1:]:
        f = fs.frames[0]
        tracker.process(FrameSet((Frame(f.image, 1.0 + fs.t, 30 + fs.index),),
                                 1.0 + fs.t, 30 + fs.index))
    assert tracker.body_name == "xs"


def test_facing_away_reports_the_front_track_reflected(synth_gl, tmp_path, silhouette_tree):
    # "away" (a camera behind the player) changes what is reported, not what is
    # tracked: every frame's joints are the front track's reflected (same rays, left
    # and right swapped) and its template (what the IoU is measured on) is the same
    from bodyplay.trackers.silhouette.facing import LR_SWAP, reflect_joints

    out = tmp_path / "cap"
    assert main(["synth", "--clip", "131_01", "--frames", "30", "--out", str(out)]) == 0
    src = open_source(out)
    assert src.cameras is not None
    cam = src.cameras[0]
    trackers = [create_silhouette_tracker(SilhouetteOptions(body="m", facing=f),
                                          src.cameras[:1], tree=silhouette_tree)
                for f in ("front", "away")]
    found = 0
    with src:
        for fs in src:
            front, away = (t.process(fs) for t in trackers)
            assert front.found == away.found
            if not front.found:
                continue
            found += 1
            assert np.allclose(away.joints, reflect_joints(front.joints, cam.center))
            assert np.allclose(cam.project(away.joints), cam.project(front.joints[LR_SWAP]))
            assert np.array_equal(away.extras["template"], front.extras["template"])
            assert away.state == tuple(front.state[k] for k in LR_SWAP)
            assert away.extras["facing"] == "away" and front.extras["facing"] == "front"
    assert found >= 20
