"""Specifications of the silhouette tracker on real footage: one player among other
things that move, a first-frame guess that may be furniture, the Pose2Sim reference."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from bodyplay.trackers.silhouette.window import farthest_person, feet_like, select_person

REPO = Path(__file__).resolve().parents[2]


def _blob(mask: np.ndarray, r0: int, r1: int, c0: int, c1: int) -> None:
    mask[r0:r1, c0:c1] = 1


def test_select_person_keeps_the_largest_blob_and_its_pieces_and_drops_a_far_one() -> None:
    m = np.zeros((240, 320), np.uint8)
    _blob(m, 40, 200, 100, 140)   # the player
    _blob(m, 60, 70, 143, 170)    # an arm, split off by the clean-up
    _blob(m, 200, 230, 280, 300)  # a lamp flickering in a corner
    out = select_person(m, None)
    assert out[100, 120] and out[65, 160]
    assert not out[210, 290].any()


def test_select_person_follows_the_blob_the_track_touches_not_the_largest() -> None:
    m = np.zeros((240, 320), np.uint8)
    _blob(m, 40, 200, 20, 90)     # a second person, larger
    _blob(m, 60, 200, 220, 250)   # the tracked player
    near = np.zeros(m.shape, bool)
    near[50:210, 210:260] = True  # where the last estimate was
    out = select_person(m, near)
    assert out[100, 230] and not out[100, 50]


def test_select_person_leaves_a_single_blob_alone() -> None:
    m = np.zeros((60, 80), np.uint8)
    _blob(m, 10, 50, 30, 40)
    assert np.array_equal(select_person(m, None), m)


def test_feet_like_accepts_two_feet_and_rejects_a_treadmill_front() -> None:
    mpp = 0.036
    person = np.zeros((80, 60), np.uint8)
    _blob(person, 20, 45, 25, 35)          # torso
    _blob(person, 45, 72, 25, 29)          # legs
    _blob(person, 45, 72, 31, 35)
    _blob(person, 69, 72, 22, 25)          # feet
    _blob(person, 69, 72, 35, 38)
    assert feet_like(person, mpp)
    furniture = person.copy()
    for k in range(8):  # a treadmill's front corner widening upwards, as seen on cam02
        furniture[77 - k, max(0, 30 - 3 * k - 1): 30 + 3 * k + 1] = 1
    assert not feet_like(furniture, mpp)
    assert not feet_like(np.zeros((80, 60), np.uint8), mpp)


def test_pose2sim_reference_masks_and_landmarks_cover_every_frame(shared_data) -> None:  # type: ignore[no-untyped-def]
    import sys

    sys.path.insert(0, str(REPO / "benchmarks"))
    from silhouette_real import REFERENCE, reference_masks

    ref = np.load(REFERENCE)
    for cam in ("cam01", "cam02", "cam03", "cam04"):
        masks = reference_masks(ref, cam)
        assert masks.shape == (100, 480, masks.shape[2]) and masks.shape[2] in (270, 272)
        share = masks.mean(axis=(1, 2))
        assert share.min() > 0.02 and share.max() < 0.15  # one person, every frame
        lm = ref[f"{cam}_landmarks"]
        assert lm.shape == (100, 33, 3) and np.isfinite(lm).all()


@pytest.mark.slow
def test_pose2sim_landmarks_triangulate_consistently_with_the_calibration(
        shared_data, tmp_path) -> None:  # type: ignore[no-untyped-def]
    import sys

    sys.path.insert(0, str(REPO / "benchmarks"))
    from bodyplay.capture.external import import_capture
    from bodyplay.capture.sources import open_source
    from silhouette_real import CAMS, P2S, REFERENCE, triangulate

    ref = np.load(REFERENCE)
    cams = {}
    for c in CAMS:
        src = open_source(import_capture(P2S, tmp_path / c, cameras=[c]))
        assert src.cameras is not None
        cams[c] = src.cameras[0]
    J, px = triangulate(cams, {c: ref[f"{c}_landmarks"][:10] for c in CAMS})
    assert px < 20.0
    # standing on the treadmill: ankles near the floor, head 1.3-1.9 m up
    assert np.nanmedian(J[:, 13, 1]) < 0.25 and 1.3 < np.nanmedian(J[:, 4, 1]) < 1.9


def test_farthest_person_follows_the_focal_length_and_resolution() -> None:
    from bodyplay.capture.camera import Camera

    webcam = Camera.from_fov("cam0", 640, 480, hfov_deg=60.0)
    d = farthest_person(webcam, 240, 80.0)
    assert 5.0 < d < 7.0  # the old fixed 6 m for the synthetic captures' camera
    tele = Camera.from_fov("cam0", 1768, 994, hfov_deg=38.6)  # Sports2D's f of 2520 px
    assert farthest_person(tele, 240, 80.0) > 11.0  # its walker is about 10 m away
    assert farthest_person(webcam, 240, 40.0) == pytest.approx(2 * d)


def test_max_distance_zero_means_from_the_calibration_and_negative_is_rejected() -> None:
    from bodyplay.errors import ConfigError
    from bodyplay.trackers.silhouette import SilhouetteOptions

    assert SilhouetteOptions().max_distance == 0.0
    with pytest.raises(ConfigError, match="max_distance"):
        SilhouetteOptions(max_distance=-1.0)


def test_select_person_prefers_a_blob_standing_on_the_floor_to_a_larger_one_in_the_sky() -> None:
    m = np.zeros((240, 427), np.uint8)
    _blob(m, 5, 60, 40, 160)      # a patch of sky a first-frame guess took for the figure
    _blob(m, 120, 220, 300, 330)  # the walker
    out = select_person(m, None, stands=lambda blob: bool(np.nonzero(blob)[0].max() > 150))
    assert out[200, 310] and not out[30, 100]


def test_background_drop_guess_stops_resolving_the_first_frame_guess() -> None:
    from bodyplay.trackers.silhouette.background import BackgroundModel

    rng = np.random.default_rng(3)
    base = rng.integers(40, 220, (60, 80, 3)).astype(np.uint8)
    room = np.kron(base, np.ones((8, 8, 1), np.uint8))
    room[200:470, 250:400] = (30, 30, 35)  # a dark treadmill-like block, still for ever
    model = BackgroundModel()
    for k in range(12):
        img = room.copy()
        img[120:420, 300 + 4 * k: 360 + 4 * k] = (200, 150, 120)  # the player moving
        model.apply(img)
    model.drop_guess()
    for k in range(12, 24):
        img = room.copy()
        img[120:420, 300 + 4 * k: 360 + 4 * k] = (200, 150, 120)
        sil = model.apply(img)
    assert model.player is None
    assert sil.foreground.shape == sil.unknown.shape


def test_real_footage_error_split_reports_a_back_view_as_a_half_turn_and_ignores_placement(
        ) -> None:
    import sys

    sys.path.insert(0, str(REPO / "benchmarks"))
    from bodyplay.body.joints import JOINT_NAMES
    from bodyplay.body.skeleton import Skeleton
    from silhouette_real import _aligned_and_heading

    truth = Skeleton.from_shape("m").joint_positions(Skeleton.from_shape("m").rest_pose())
    moved = truth + np.array([0.3, 0.0, -0.5])
    aligned, heading = _aligned_and_heading(moved, truth)
    assert aligned < 1e-9 and heading < 1e-6
    # the back seen as the front: mirrored through the body's frontal plane, the
    # labels of the left and right joints kept
    mirrored = truth.copy()
    mirrored[:, 2] = 2 * truth[0, 2] - truth[:, 2]
    swap = [JOINT_NAMES.index(n.replace("l_", "#").replace("r_", "l_").replace("#", "r_"))
            for n in JOINT_NAMES]
    turned = mirrored[swap]
    _, heading = _aligned_and_heading(turned, truth)
    assert heading > 170
    no_hips = truth.copy()
    no_hips[11] = np.nan
    assert all(np.isnan(v) for v in _aligned_and_heading(truth, no_hips))


def _player_leaving_a_treadmill(k: int) -> np.ndarray:
    """Frame ``k``: a textured room, a dark treadmill-like block, and a player who
    steps to the right over the first 10 frames, then sways a little."""
    rng = np.random.default_rng(3)
    base = rng.integers(40, 220, (60, 80, 3)).astype(np.uint8)
    img = np.kron(base, np.ones((8, 8, 1), np.uint8))
    img[380:470, 180:470] = (30, 30, 35)
    x = 250 + 10 * min(k, 10) + (4 if k > 10 and k % 2 else 0)
    img[120:420, x : x + 50] = (200, 150, 120)
    return img


def _after_a_dropped_guess(redo: bool) -> tuple[np.ndarray, np.ndarray]:
    from bodyplay.trackers.silhouette.background import BackgroundModel

    model = BackgroundModel()
    model.apply(_player_leaving_a_treadmill(0))
    model.drop_guess()
    assert model.dropped and not model.guessing
    box = np.zeros((240, 320), bool)
    box[40:215, 80:260] = True  # where a person standing at the floor point can be
    for k in range(1, 40):
        sil = model.apply(_player_leaving_a_treadmill(k))
        if k == 12 and redo:
            assert model.guess_in(box, grabcut=False)
            assert model.guessing and model.known is not None
            assert not model.known[box].any() and model.known[:, :60].all()
    return sil.foreground > 0, box


def test_background_dropped_guess_made_again_as_the_box_turns_the_player_left_behind_into_a_ghost(
        ) -> None:
    # the first frame's copy of the player (x 125-150 at the working resolution) stays
    # foreground once the guess is dropped; the box made the guess again is resolved
    # by what moved since: the copy is a ghost, the player (x 175-200) is foreground
    fg, _ = _after_a_dropped_guess(redo=False)
    assert fg[70:180, 128:147].mean() > 0.9
    fg, _ = _after_a_dropped_guess(redo=True)
    assert fg[70:180, 128:147].mean() < 0.1
    assert fg[70:180, 180:195].mean() > 0.9


def test_silhouette_options_box_redo_is_on_by_default() -> None:
    from bodyplay.trackers.silhouette.options import SilhouetteOptions

    assert SilhouetteOptions().box_redo
