"""Specifications of the silhouette tracker in rooms where the first frame's guess fails:
the still body is held back from learning and the distance comes from the shape."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from bodyplay.capture.camera import Camera, look_at
from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette.background import BackgroundModel
from bodyplay.trackers.silhouette.options import BackgroundOptions, SilhouetteOptions
from bodyplay.trackers.silhouette.shapestart import shape_distance, window_at_distance
from bodyplay.trackers.silhouette.window import WindowGeometry, _homography


def _room(seed: int) -> np.ndarray:
    base = np.random.default_rng(seed).integers(40, 220, (60, 80, 3)).astype(np.uint8)
    return np.kron(base, np.ones((8, 8, 1), np.uint8))  # 480x640 blocky texture


def _arms_over_still_legs(model: BackgroundModel, frames: int) -> None:
    """A player whose legs stand still under arms that swing: no guess, no pose."""
    room = _room(5)
    for i in range(frames):
        img = room.copy()
        img[260:420, 290:350] = (30, 30, 60)  # still legs
        y = 150 + 6 * (i % 10)
        img[y : y + 30, 200:440] = (200, 60, 40)  # arms swinging up and down
        model.apply(img)


def test_background_holds_still_pixels_under_what_moves_until_a_pose() -> None:
    # no first guess: the still legs under the moving arms are not learned as the
    # room while the tracker has no pose (they would vanish from the silhouette)
    model = BackgroundModel(BackgroundOptions(bootstrap=False))
    _arms_over_still_legs(model, 30)
    assert model.known is not None and model.held is not None
    legs = (slice(135, 205), slice(150, 170))  # working resolution (320x240)
    assert not model.known[legs].any()
    assert model.held[legs].all()
    assert model.known[:, :60].all()  # the room far from the player is learned


def test_background_learns_still_legs_when_holding_below_is_off() -> None:
    model = BackgroundModel(BackgroundOptions(bootstrap=False, hold_below=False))
    _arms_over_still_legs(model, 30)
    assert model.known is not None and model.known[135:205, 150:170].mean() > 0.9


def _camera() -> Camera:
    R, t = look_at((0.0, 1.2, 3.0), (0.0, 0.9, 0.0))
    return Camera.from_fov("cam0", 640, 480, 60.0, R, t)


def _shown(tree, cam: Camera, leaf: int, distance: float) -> tuple[np.ndarray, float]:  # type: ignore[no-untyped-def]
    """A leaf's template seen by ``cam`` with its floor point ``distance`` m away, in
    the working image (320x240)."""
    geometry = WindowGeometry()
    scale = 0.5
    direction = np.array([0.0, 0.0, -1.0])
    g = cam.center + direction * distance
    g[1] = 0.0
    view = geometry.view(cam.center, g, 2)
    mask = tree.bodies["m"].runs[2].masks(np.array([leaf]))[0]
    H = _homography(cam, view, scale)
    img = cv2.warpPerspective(mask * np.uint8(255), np.linalg.inv(H), (320, 240)) >= 128
    return img.astype(np.uint8), scale


@pytest.mark.parametrize("distance", [2.2, 3.0, 3.8])
def test_shape_distance_finds_how_far_a_player_stands_from_the_upper_body_alone(
        silhouette_tree, distance: float) -> None:  # type: ignore[no-untyped-def]
    cam = _camera()
    tree = silhouette_tree
    leaf = tree.num_leaves // 3
    shown, scale = _shown(tree, cam, leaf, distance)
    rows = np.flatnonzero(shown.any(axis=1))
    cut = rows[0] + (rows[-1] - rows[0]) // 2
    upper = shown.copy()
    upper[cut:] = 0  # the still legs are not seen ...
    unknown = np.zeros_like(shown)
    unknown[cut:, :] = 1  # ... they are "don't care" below what moves
    d = shape_distance(tree.bodies["m"], WindowGeometry(), cam, upper, unknown, scale,
                       1.0, 6.0, steps=24)
    assert d is not None and abs(d - distance) < 0.2 * distance
    win = window_at_distance(WindowGeometry(), cam, upper, unknown, scale, d)
    assert win is not None and win.distance == pytest.approx(d)


def test_shape_distance_needs_a_silhouette() -> None:
    empty = np.zeros((240, 320), np.uint8)
    assert window_at_distance(WindowGeometry(), _camera(), empty, empty, 0.5, 2.0) is None


def test_options_reject_a_negative_shape_start() -> None:
    with pytest.raises(ConfigError, match="shape_frames"):
        SilhouetteOptions(shape_frames=-1)


def _tracker(tree):  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette import create_silhouette_tracker

    return create_silhouette_tracker(SilhouetteOptions(body="m", arm_candidates=0),
                                     (_camera(),), tree=tree)


def _feet_row(shown: np.ndarray) -> int:
    """The first row of the lowest eighth of a silhouette: its feet."""
    rows = np.flatnonzero(shown.any(axis=1))
    return int(rows[-1] - (rows[-1] - rows[0]) // 8)


def _at_three_metres(tree, still_feet: bool = False):  # type: ignore[no-untyped-def]
    """A tracker, its camera and the silhouette of a leaf standing 3 m away (with
    ``still_feet`` its feet left out: they stood still and the room took them), with
    the whole leaf's silhouette and its scale."""
    from bodyplay.trackers.silhouette.background import Silhouette

    cam = _camera()
    tracker = _tracker(tree)
    shown, scale = _shown(tree, cam, tree.num_leaves // 3, 3.0)
    moved = shown.copy()
    if still_feet:
        moved[_feet_row(shown):] = 0
    return tracker, cam, shown, scale, Silhouette(moved, np.zeros_like(moved), scale, None)


def _track_from(tracker, started: float, last: float) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette.tracker import _Last

    tracker._started = started
    tracker._last = _Last(np.zeros((17, 3)), np.zeros(10), last)
    tracker._distance = 5.0


def test_tracker_starts_over_when_its_first_track_is_lost_at_once(silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    # a pose at 0.0-0.2 s, then no person for longer than lost_after: that start was
    # wrong (it protected its own spot, and was never replaced)
    tracker = _tracker(silhouette_tree)
    _track_from(tracker, 0.0, 0.2)
    tracker._undo_failed_start(0.8)
    assert tracker._last is None and tracker._started is None and tracker._distance is None
    assert tracker._restarted


def test_tracker_keeps_a_track_that_held_when_the_person_is_lost(silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    tracker = _tracker(silhouette_tree)
    _track_from(tracker, 0.0, 1.5)  # tracked for 1.5 s: an occlusion, not a wrong start
    tracker._undo_failed_start(2.2)
    assert tracker._last is not None and tracker._started == 0.0 and not tracker._restarted
    _track_from(tracker, 0.0, 0.2)
    tracker._undo_failed_start(0.6)  # not lost yet (lost_after 0.5 s)
    assert tracker._last is not None


def test_after_a_failed_start_a_floor_point_counts_only_where_the_shape_agrees(
        silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    tracker, cam, shown, scale, sil = _at_three_metres(silhouette_tree)
    geometry = tracker.geometry
    far = window_at_distance(geometry, cam, shown, sil.unknown, scale, 4.5)
    near = window_at_distance(geometry, cam, shown, sil.unknown, scale, 3.2)
    assert far is not None and near is not None
    tracker._restarted = True
    tracker._started, tracker._t, tracker._shape_d = 1.0, 1.2, 3.0
    win, ok = tracker._from_shape(sil, far)  # 50% off the shape's 3 m: not the feet
    assert ok and win is not None and win.distance == pytest.approx(3.0)
    win, ok = tracker._from_shape(sil, near)  # within restart_agree (25%): the feet
    assert ok and win is near and not tracker._restarted
    tracker._restarted, tracker._shape_d = True, 3.0
    tracker._t = 1.0 + tracker.options.restart_doubt + 0.1  # the doubt has run out
    win, ok = tracker._from_shape(sil, far)
    assert win is far


def test_a_dropped_guess_is_made_again_in_a_box_that_reaches_the_still_feet(
        silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    # Pose2Sim cam02: the dropped guess left the still feet as room, so the floor
    # point (what moved: the shins) lies far behind the player; the box made again
    # there would keep the feet out for good. The box also covers where the
    # templates fit what moved, so the feet are in it.
    tracker, cam, shown, scale, sil = _at_three_metres(silhouette_tree, still_feet=True)
    feet, moved = _feet_row(shown), sil.foreground
    far = window_at_distance(tracker.geometry, cam, moved, sil.unknown, scale, 4.5)
    assert far is not None
    at_floor = tracker._person_box(far.ground, sil)
    on_feet = shown[feet:] > 0
    assert not at_floor[feet:][on_feet].any()  # the box at the floor point alone
    box = tracker._redo_box(far, sil)
    # most of the feet (the templates' distance is a grid step off the 3 m), and all of
    # the floor point's box
    assert box[feet:][on_feet].mean() > 0.5 and box[at_floor].all()


def test_a_dropped_guess_is_made_again_at_the_floor_point_where_the_templates_agree(
        silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    tracker, cam, shown, scale, sil = _at_three_metres(silhouette_tree)
    tree = silhouette_tree
    for metres in (3.0, 4.0):  # the feet seen; or nearer than where the templates fit
        d = shape_distance(tree.bodies["m"], tracker.geometry, cam, shown, sil.unknown,
                           scale, 1.0, tracker.max_distance, beta=tracker.options.beta,
                           level=1)
        assert d is not None
        win = window_at_distance(tracker.geometry, cam, shown, sil.unknown, scale,
                                 min(metres, d))
        assert win is not None
        assert np.array_equal(tracker._redo_box(win, sil),
                              tracker._person_box(win.ground, sil))


def test_options_reject_a_negative_restart() -> None:
    with pytest.raises(ConfigError, match="restart_within"):
        SilhouetteOptions(restart_within=-1.0)
    with pytest.raises(ConfigError, match="restart_agree"):
        SilhouetteOptions(restart_agree=0.0)


def test_smallest_template_area_is_a_whole_small_body(silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette.stature import smallest_template_area

    area = smallest_template_area(silhouette_tree, WindowGeometry())
    # body "m" standing or bending: a few tenths of a square metre, never an arm's worth
    assert 0.15 < area < 0.6
    masks = silhouette_tree.bodies["m"].runs[0].masks()
    assert area == pytest.approx(masks.reshape(len(masks), -1).sum(1).min()
                                 * WindowGeometry().mpp(0) ** 2)


def test_tracker_does_not_start_on_a_silhouette_smaller_than_any_body(silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    # an arm swung by a player who stands still (the rest learned as the room): the
    # ray through its lowest pixel meets the floor 4 m away, where the blob is as tall
    # as a person, but it covers a fraction of any body's area
    tracker = _tracker(silhouette_tree)
    assert tracker.min_start_area > 0
    cam = _camera()
    whole, scale = _shown(silhouette_tree, cam, silhouette_tree.num_leaves // 3, 3.0)
    win = window_at_distance(tracker.geometry, cam, whole, np.zeros_like(whole), scale, 3.0)
    assert win is not None and tracker._plausible(win)
    arm = np.zeros((240, 320), np.uint8)
    arm[60:160, 158:162] = 1
    win = window_at_distance(tracker.geometry, cam, arm, np.zeros_like(arm), scale, 4.0)
    assert win is not None and not tracker._plausible(win)
    tracker._started = 0.0  # a running track may shrink (parts hidden): not a start
    assert tracker._plausible(win)


def test_tracker_starts_on_small_silhouettes_when_the_area_check_is_off(silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette import create_silhouette_tracker

    tracker = create_silhouette_tracker(
        SilhouetteOptions(body="m", arm_candidates=0, start_area=0.0), (_camera(),),
        tree=silhouette_tree)
    assert tracker.min_start_area == 0.0
    arm = np.zeros((240, 320), np.uint8)
    arm[60:160, 158:162] = 1
    win = window_at_distance(tracker.geometry, _camera(), arm, np.zeros_like(arm), 0.5, 4.0)
    assert win is not None and tracker._plausible(win)


def test_options_reject_a_start_area_outside_a_share() -> None:
    with pytest.raises(ConfigError, match="start_area"):
        SilhouetteOptions(start_area=-0.1)
    with pytest.raises(ConfigError, match="start_area"):
        SilhouetteOptions(start_area=1.5)


def _player_in_a_cup(i: int) -> np.ndarray:
    """A player (red shirt, dark legs) standing still but for one swinging arm, in
    front of a bright object that fills most of the frame (the ``coffee`` photo's
    cup): the first frame's GrabCut takes the object with the player, over half the
    image, so there is no first guess."""
    img = np.zeros((480, 640, 3), np.uint8)
    img[:] = (120, 80, 50)  # a wooden table
    img[20:470, 40:600] = (230, 225, 215)  # the cup, most of the frame
    img[150:300, 290:350] = (200, 40, 40)  # the still torso
    img[300:420, 295:345] = (30, 30, 60)  # the still legs
    y = 150 + 6 * (i % 10)
    img[y : y + 20, 350:440] = (200, 40, 40)  # one arm swinging up and down
    return img


def test_box_guess_finds_the_figure_inside_the_box_and_nothing_outside() -> None:
    from bodyplay.trackers.silhouette.background import _small, box_guess, first_guess

    img = _player_in_a_cup(0)
    assert not first_guess(img, (320, 240)).any()  # the cup and the player: no figure
    box = np.zeros((240, 320), bool)
    box[60:215, 120:230] = True  # where a person standing there can be
    guess = box_guess(_small(img), box)
    player = np.zeros((240, 320), bool)
    player[78:208, 150:172] = True  # torso and legs, inside their edges
    assert guess[player].mean() > 0.9
    assert not guess[~box].any()
    assert guess[box & ~player].mean() < 0.5


def test_background_guess_in_a_box_holds_the_still_body_where_there_was_no_guess() -> None:
    # no first guess (the cup): the still torso and legs are "don't care" at best;
    # the guess made again in the box where the tracker puts the player is resolved
    # like a first guess, so the still body is the player and the cup beside it is not
    model = BackgroundModel(BackgroundOptions())
    for i in range(15):
        model.apply(_player_in_a_cup(i))
    assert not model.guessing
    box = np.zeros((240, 320), bool)
    box[60:215, 120:230] = True
    assert model.guess_in(box)
    assert model.guessing and model.known is not None
    assert model.known[~box].all()  # outside the box: the room, from the first frame
    for i in range(15, 40):
        sil = model.apply(_player_in_a_cup(i))
    fg = sil.foreground > 0
    assert fg[80:145, 150:170].mean() > 0.9  # the still torso
    assert fg[155:205, 152:168].mean() > 0.9  # the still legs
    assert fg[80:200, 125:140].mean() < 0.1  # the cup beside them, inside the box
    assert not model.guess_in(box)  # once per start


def test_background_guess_in_a_box_is_not_made_over_a_first_guess() -> None:
    model = BackgroundModel(BackgroundOptions())
    img = np.full((480, 640, 3), 128, np.uint8)  # a plain wall
    img[150:420, 290:350] = (200, 40, 40)
    model.apply(img)
    assert model.guessing  # GrabCut found the player in the first frame
    box = np.zeros((240, 320), bool)
    box[60:215, 120:230] = True
    assert not model.guess_in(box)


def test_person_box_holds_a_standing_person_and_not_the_room_beside() -> None:
    from bodyplay.trackers.silhouette.window import person_box

    cam = _camera()
    ground = np.array([0.0, 0.0, -1.0])  # 4 m in front of the camera
    box = person_box(cam, ground, (240, 320), 0.5, 0.9, 0.0, 2.3)

    def at(p: tuple[float, float, float]) -> bool:
        u, v = (cam.project(np.array([p]), distort=False)[0] + 0.5) * 0.5 - 0.5
        return bool(box[int(round(v)), int(round(u))])

    assert at((0.0, 1.8, -1.0)) and at((0.0, 0.05, -1.0))  # head and feet
    assert at((0.7, 1.4, -1.0)) and at((-0.7, 1.4, -1.0))  # hands held out
    assert not at((1.3, 1.0, -1.0)) and not at((-1.3, 1.0, -1.0))  # the room beside
    assert not at((0.0, 0.0, 0.0))  # the floor in front of the player's feet


def test_options_reject_a_negative_box_guess() -> None:
    with pytest.raises(ConfigError, match="box_guess"):
        SilhouetteOptions(box_guess=-0.5)
    with pytest.raises(ConfigError, match="box_guess"):
        SilhouetteOptions(box_top=0.0)
