"""Specifications of the silhouette tracker's check that it follows the player: a track
that keeps what stands still while what it drops moves is guessed again."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.capture.camera import Camera, look_at
from bodyplay.errors import CaptureError, ConfigError
from bodyplay.trackers.silhouette.background import BackgroundModel, Silhouette
from bodyplay.trackers.silhouette.options import BackgroundOptions, SilhouetteOptions
from bodyplay.trackers.silhouette.stilltrack import TrackMotion

FPS = 30.0
PIXELS = 320 * 240


def _feed(motion: TrackMotion, seconds: float, kept: int, dropped: int) -> None:
    for i in range(int(seconds * FPS)):
        motion.add(i / FPS, kept, dropped, PIXELS)


def test_track_motion_flags_a_track_that_stands_still_while_the_dropped_foreground_moves(
) -> None:
    motion = TrackMotion(1.0, 0.002)
    _feed(motion, 1.2, kept=5, dropped=400)  # 0.5% of the image moves, not in the track
    assert motion.wrong()


def test_track_motion_keeps_a_track_whose_own_foreground_moves() -> None:
    motion = TrackMotion(1.0, 0.002)
    _feed(motion, 1.2, kept=300, dropped=400)  # the track's waving arm moves too
    assert not motion.wrong()
    slow = TrackMotion(1.0, 0.002)
    _feed(slow, 1.2, kept=40, dropped=3000)  # a player swaying beside a big mover
    assert not slow.wrong()


def test_track_motion_ignores_small_motion_elsewhere() -> None:
    motion = TrackMotion(1.0, 0.002)
    _feed(motion, 1.2, kept=0, dropped=50)  # codec specks, a flicker: under 0.2%
    assert not motion.wrong()


def test_track_motion_waits_for_a_full_window_and_forgets_on_clear() -> None:
    motion = TrackMotion(1.0, 0.002)
    _feed(motion, 0.5, kept=0, dropped=1000)  # half a second is not enough evidence
    assert not motion.wrong()
    _feed(motion, 1.2, kept=0, dropped=1000)
    assert motion.wrong()
    motion.clear()
    assert motion.span == 0.0 and not motion.wrong()
    assert not TrackMotion(0.0, 0.002).wrong()  # window 0: off


def test_track_motion_flags_a_still_track_that_fits_no_pose_beside_another_candidate(
) -> None:
    motion = TrackMotion(1.0, 0.002, poor_fit=0.5)
    for i in range(36):  # nothing moves; the track fits at 1.0, a still player stands apart
        motion.add(i / FPS, 0, 0, PIXELS, fit=1.0, others=0.03)
    assert motion.wrong()


def test_track_motion_keeps_a_poorly_fitting_track_that_moves_or_has_no_rival() -> None:
    moving = TrackMotion(1.0, 0.002, poor_fit=0.5)
    alone = TrackMotion(1.0, 0.002, poor_fit=0.5)
    fitting = TrackMotion(1.0, 0.002, poor_fit=0.5)
    for i in range(36):
        # the player with a broken silhouette (legs resolved as the floor): it moves
        moving.add(i / FPS, 200, 0, PIXELS, fit=1.0, others=0.03)
        # the player standing still, fitting badly, with nothing else in view
        alone.add(i / FPS, 0, 0, PIXELS, fit=1.0, others=0.0)
        # a still track that fits like a person
        fitting.add(i / FPS, 0, 0, PIXELS, fit=0.1, others=0.03)
    assert not moving.wrong() and not alone.wrong() and not fitting.wrong()


def test_options_reject_a_negative_still_window() -> None:
    with pytest.raises(ConfigError, match="still_window"):
        SilhouetteOptions(still_window=-1.0)
    with pytest.raises(ConfigError, match="still_motion"):
        SilhouetteOptions(still_motion=0.0)


def _room() -> np.ndarray:
    base = np.random.default_rng(3).integers(40, 220, (60, 80, 3)).astype(np.uint8)
    return np.kron(base, np.ones((8, 8, 1), np.uint8))  # 480x640 blocky texture


def _photo_and_player(room: np.ndarray, i: int) -> np.ndarray:
    img = room.copy()
    img[150:420, 120:200] = (230, 230, 230)  # a still figure (a photo), guessed as player
    x = 380 + 6 * (i % 20)
    img[150:420, x:x + 70] = (200, 40, 40)  # the player, walking to and fro
    return img


def test_background_release_learns_a_still_figure_as_the_room() -> None:
    room = _room()
    model = BackgroundModel(BackgroundOptions(learn_after=1000,
                                               relearn_after=1000))  # none learned by stillness
    for i in range(11):
        sil = model.apply(_photo_and_player(room, i))
    photo = np.zeros(sil.foreground.shape, bool)
    photo[75:210, 60:100] = True  # working resolution (320x240)
    assert model.player is not None and model.player[photo].mean() > 0.5  # taken for the body
    assert sil.foreground[photo].mean() > 0.5
    model.release(photo)
    assert model.known is not None and model.known[photo].all()
    assert not model.player[photo].any()
    sil = model.apply(_photo_and_player(room, 11))
    assert sil.foreground[photo].mean() < 0.05  # the photo is the room now
    with pytest.raises(CaptureError, match="release mask"):
        model.release(np.zeros((10, 10), bool))


def _twins(room: np.ndarray, i: int = 0) -> np.ndarray:
    img = room.copy()
    img[150:420, 120:200] = (230, 230, 230)  # a still photo of a figure
    img[150:420, 300:370] = (230, 230, 230)  # the player in the same clothes, still ...
    y = 200 + 8 * (i % 6)
    img[y:y + 24, 370:440] = (230, 230, 230)  # ... but for an arm
    return img


def test_background_release_resolves_again_the_guess_learned_under_the_wrong_track() -> None:
    room = _room()
    model = BackgroundModel(BackgroundOptions())
    for _ in range(6):
        sil = model.apply(_twins(room))  # both in the first guess
    assert model.known is not None and model.occupied.any()
    since = model.frames
    # a wrong track on the photo: its estimate makes the still player sure background
    protect = np.zeros(sil.foreground.shape, bool)
    protect[60:225, 45:115] = True
    for i in range(30):
        model.apply(_twins(room, i), protect)
    player = np.zeros(protect.shape, bool)
    player[80:205, 155:180] = True  # the still player (working resolution)
    assert model.known[player].mean() > 0.9  # learned as the room under the wrong track
    photo = np.zeros(protect.shape, bool)
    photo[75:210, 60:100] = True
    model.release(photo, since)
    assert model.known[photo].all()
    assert not model.known[player].any()  # unknown again, to be resolved anew
    assert model.player is not None and model.player[player].all()  # probably the player
    for i in range(5):
        sil = model.apply(_twins(room, 30 + i))  # no estimate: the tracker guesses again
    assert sil.foreground[player].mean() > 0.8 and sil.foreground[photo].mean() < 0.05


def _camera() -> Camera:
    R, t = look_at((0.0, 1.2, 3.0), (0.0, 0.9, 0.0))
    return Camera.from_fov("cam0", 640, 480, 60.0, R, t)


def test_tracker_guesses_again_when_its_track_stands_still_while_the_player_moves(
        silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette import create_silhouette_tracker
    from bodyplay.trackers.silhouette.tracker import _Last

    tracker = create_silhouette_tracker(SilhouetteOptions(arm_candidates=0), (_camera(),),
                                        tree=silhouette_tree)
    fg = np.zeros((240, 320), np.uint8)
    fg[75:210, 60:100] = 1  # the still figure the track follows
    fg[75:210, 200:235] = 1  # the player, apart, moving
    protect = np.zeros(fg.shape, bool)
    protect[60:225, 45:115] = True
    tracker._started = 0.0
    tracker.background.apply(_room())  # a model of the working size
    moving = np.zeros(fg.shape, bool)
    moving[75:210, 200:210] = True  # 1,350 px (1.8% of the image) move in the player
    tracker.background.moving = moving
    sil = Silhouette(fg, np.zeros_like(fg), 0.5, None)
    stands = tracker._stands_factory(0.5)
    for i in range(int(1.2 * FPS)):
        tracker._last = _Last(np.zeros((17, 3)), np.zeros(10), i / FPS, protect=protect)
        kept = fg & protect
        person, near = tracker._check_still(i / FPS, sil, kept, stands)
        if near is None:
            break
    assert tracker.reguesses == 1 and near is None and tracker._last is None
    assert person[75:210, 200:235].all() and not person[:, :120].any()  # now the mover
    assert tracker.background.known is not None
    assert tracker.background.known[75:210, 60:100].all()  # the figure is learned as room
    assert tracker.body_name is None  # the body is chosen again, on the player
