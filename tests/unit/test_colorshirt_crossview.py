"""The room seen alike by two cameras (colorshirt/crossview.py)."""

from __future__ import annotations

import cv2
import numpy as np

from bodyplay.trackers.colorshirt.crossview import CrossView
from bodyplay.trackers.colorshirt.plate import RoomPlate

H, W = 240, 320
SHIFT = 12
"""Pixels the room moves by from camera 0 to camera 1 (its homography: a shift)."""


def _wall(seed: int = 0) -> np.ndarray:
    """A textured room wider than the frames: rectangles of many colours."""
    rng = np.random.default_rng(seed)
    wall = np.full((H, W + 2 * SHIFT, 3), 160, np.uint8)
    for _ in range(160):
        x, y = int(rng.integers(0, W + SHIFT)), int(rng.integers(0, H - 10))
        w, h = int(rng.integers(6, 30)), int(rng.integers(6, 30))
        color = tuple(int(c) for c in rng.integers(0, 255, 3))
        cv2.rectangle(wall, (x, y), (x + w, y + h), color, -1)
    return wall


def _frames(player_shift: int) -> tuple[np.ndarray, np.ndarray]:
    """The two cameras' frames: the room shifted by SHIFT, an orange-and-blue player
    who stands in front of it (shifted by ``player_shift`` between the views)."""
    wall = _wall()
    a = wall[:, SHIFT: SHIFT + W].copy()
    b = wall[:, 2 * SHIFT:].copy()
    for img, x in ((a, 150), (b, 150 - player_shift)):
        img[60:180, x: x + 20] = (240, 120, 20)
        img[60:180, x + 20: x + 40] = (30, 60, 220)
    return a, b


def test_cross_view_finds_the_room_both_cameras_see_and_not_the_player_before_it() -> None:
    a, b = _frames(player_shift=40)  # the player nearer than the wall: another shift
    same = CrossView(2).room([a, b], [None, None], 2)
    assert same[0] is not None and same[1] is not None
    player = np.zeros((H, W), bool)
    player[60:180, 150:190] = True
    border = np.zeros((H, W), bool)
    border[:, : SHIFT + 4] = True  # camera 1 does not see the room left of camera 0's
    room = ~cv2.dilate(player.astype(np.uint8), np.ones((9, 9), np.uint8)).astype(bool)
    assert same[0][room & ~border].mean() > 0.9
    assert same[0][player].mean() < 0.05


def test_cross_view_answers_only_the_cameras_that_need_it_the_same() -> None:
    a, b = _frames(player_shift=40)
    full = CrossView(2).room([a, b], [None, None], 2)
    view = CrossView(2)
    assert view.room([a, b], [None, None], 2, [False, False]) == [None, None]
    part = view.room([a, b], [None, None], 2, [False, True])
    assert part[0] is None and part[1] is not None and full[1] is not None
    assert np.array_equal(part[1], full[1])


def test_cross_view_gives_nothing_with_one_camera_or_a_player_against_the_wall() -> None:
    a, b = _frames(player_shift=SHIFT)  # the player maps exactly like the room
    assert CrossView(1).room([a], [None], 2) == [None]
    torso = (2 * 150, 2 * 60, 2 * 190, 2 * 180)  # full-resolution box of the last torso
    same = CrossView(2).room([a, b], [torso, None], 2)
    assert same[0] is None  # the cue cannot tell the player from the room there
    assert same[1] is not None  # no last pose in camera 1: used


def test_room_plate_counts_pixels_seen_alike_as_room_where_it_knows_no_room() -> None:
    plate = RoomPlate()
    frame = np.full((H, W, 3), 100, np.uint8)
    alike = np.zeros((H, W), bool)
    alike[:, :100] = True
    plate.start(frame, alike)
    fg = plate.foreground()  # nothing learned yet: only the other camera's word
    assert fg is not None and not fg[:, 5:95].any() and fg[:, 105:].all()
    plate.start(frame)
    assert plate.foreground() is None
    for _ in range(10):  # an empty room: the plate knows it
        plate.start(frame)
        plate.learn(None, everywhere=True)
    player = frame.copy()
    player[50:150, 40:60] = (240, 120, 20)
    plate.start(player, alike)
    fg = plate.foreground()
    assert fg is not None and fg[55:145, 45:55].all()  # where it knows, its word stands
