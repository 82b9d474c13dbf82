"""Specifications of the floor cue: background plate, feet, depth of the feet."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.capture.camera import Camera, look_at
from bodyplay.trackers.colorshirt.floor import (
    BackgroundPlate,
    FeetPoint,
    FloorWatch,
    feet_points,
    floor_depth,
    person_region,
)
from bodyplay.trackers.colorshirt.locate import BackgroundMask
from bodyplay.trackers.colorshirt.views import CameraState

SHIRT = (280, 120, 360, 240)  # full-resolution box of the shirt


def _room(seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    tile = rng.integers(60, 200, (24, 32, 3)).astype(np.uint8)
    return np.kron(tile, np.ones((20, 20, 1), np.uint8))  # 480x640 blocks of colour


def _person(room: np.ndarray, feet_v: int = 420, gain: float = 1.0) -> np.ndarray:
    img = np.clip(room.astype(np.float64) * gain, 0, 255).astype(np.uint8)
    x0, y0, x1, y1 = SHIRT
    img[y0:y1, x0:x1] = (200, 40, 40)  # shirt
    img[y1:feet_v, x0 + 6: x0 + 32] = (20, 20, 60)  # left leg
    img[y1:feet_v, x1 - 32: x1 - 6] = (20, 20, 60)  # right leg
    return img


def _learned(room: np.ndarray, frames: int = 10) -> BackgroundPlate:
    plate = BackgroundPlate()
    for _ in range(frames):
        plate.learn(plate.small(room))
    return plate


def _watching(room: np.ndarray, player: np.ndarray, frames: int = 10) -> FloorWatch:
    """A floor watch that learned ``room`` and then saw ``player`` in the shirt's box."""
    watch = FloorWatch()
    for _ in range(frames):
        watch.start(room)
        watch.no_shirt()
    watch.start(player)
    watch.shirt_at(SHIRT)
    return watch


def _feet(plate: BackgroundPlate, image: np.ndarray) -> tuple[FeetPoint, ...]:
    small = plate.small(image)
    h, w = small.shape[:2]
    region = tuple(c // 2 for c in person_region(SHIRT, w * 2, h * 2))
    fg = plate.foreground(small, region)  # type: ignore[arg-type]
    assert fg is not None
    return feet_points(fg, SHIRT, plate.downscale)


def test_plate_is_not_ready_until_enough_empty_room_frames() -> None:
    room = _room()
    plate = _learned(room, frames=3)
    assert not plate.ready
    assert plate.foreground(plate.small(room), (0, 0, 10, 10)) is None
    assert _learned(room, frames=8).ready


def test_feet_points_finds_the_bottom_of_both_legs() -> None:
    room = _room()
    feet = _feet(_learned(room), _person(room, feet_v=420))
    assert len(feet) == 2
    us = sorted(f.u for f in feet)
    assert abs(us[0] - 299) < 6 and abs(us[1] - 341) < 6
    assert all(abs(f.v - 420) <= 2 for f in feet)


def test_feet_survive_a_change_of_light_over_the_whole_room() -> None:
    room = _room()
    feet = _feet(_learned(room), _person(room, feet_v=400, gain=0.55))
    assert len(feet) == 2 and all(abs(f.v - 400) <= 2 for f in feet)


def test_a_player_standing_still_does_not_fade_into_the_plate() -> None:
    room = _room()
    plate = _learned(room)
    frame = _person(room, feet_v=410)
    small = plate.small(frame)
    region = tuple(c // 2 for c in person_region(SHIRT, 640, 480))
    for _ in range(300):
        plate.update_around(small, region)  # type: ignore[arg-type]
    assert len(_feet(plate, frame)) == 2


def test_the_plate_behind_the_player_follows_a_lamp_switched_off_while_tracking() -> None:
    room = _room()
    plate = _learned(room)
    frame = _person(room, feet_v=410, gain=0.55)  # the room darkens while the player is seen
    small = plate.small(frame)
    region = tuple(c // 2 for c in person_region(SHIRT, 640, 480))
    for _ in range(200):  # the surroundings have long since followed the new light
        plate.update_around(small, region)  # type: ignore[arg-type]
    fg = plate.foreground(small, region)  # type: ignore[arg-type]
    assert fg is not None
    x0, y0, x1, y1 = region
    room_behind = fg[y0:y1, x0:x1].copy()
    sx0, sy0, sx1, sy1 = (c // 2 for c in SHIRT)
    room_behind[sy0 - y0:, sx0 - x0: sx1 - x0] = False  # the player's shirt and legs
    assert room_behind.mean() < 0.02
    assert len(_feet(plate, frame)) == 2


def test_no_feet_when_the_legs_leave_the_image_or_the_plate_does_not_fit() -> None:
    room = _room()
    plate = _learned(room)
    assert _feet(plate, _person(room, feet_v=480)) == ()
    wrong = _learned(_person(room, feet_v=420))  # the "empty room" had the player in it
    assert _feet(wrong, _person(room, feet_v=420)) == ()


def test_floor_depth_is_the_depth_of_the_floor_point_under_the_pixel() -> None:
    R, t = look_at((0.3, 0.9, 3.0), (0.0, 0.9, 0.0))
    cam = Camera.from_fov("cam0", 640, 480, 60.0, R, t)
    point = np.array([[0.1, 0.0, 0.2]])
    u, v = cam.project(point)[0]
    depth = float(cam.world_to_camera(point)[0, 2])
    assert floor_depth(cam, FeetPoint(float(u), float(v))) == pytest.approx(depth, abs=1e-6)
    assert floor_depth(cam, FeetPoint(320.0, 100.0)) is None  # above the horizon


def test_floor_watch_learns_the_room_until_the_shirt_appears_then_finds_feet() -> None:
    room = _room()
    player = _person(room, feet_v=415)
    watch = _watching(room, player)
    assert watch.last_feet == ()  # nothing searched yet
    assert len(watch.feet()) == 2 and watch.last_feet == watch.feet()
    watch.start(player)
    watch.no_shirt()  # the shirt was seen: a lost frame does not teach the plate the player
    watch.start(player)
    watch.shirt_at(SHIRT)
    assert len(watch.feet()) == 2


def test_crop_foreground_masks_the_room_next_to_the_shirt_at_the_crop_size() -> None:
    room = _room()
    unready = _watching(room, _person(room), frames=1)
    assert unready.crop_foreground((240, 80, 400, 280), (64, 80)) is None  # no plate yet
    watch = _watching(room, _person(room))
    mask = watch.crop_foreground((240, 80, 400, 280), (64, 80))  # 160 x 200 px -> 64 x 80
    assert mask is not None and mask.shape == (80, 64) and mask.dtype == bool
    # the crop's x 240..400 maps to 0..64: the shirt (280..360) is 16..48, rows 120..240 -> 16..64
    assert mask[24:60, 20:44].all()
    assert not mask[:10].any() and not mask[:, :12].any() and not mask[:, 52:].any()


def test_crop_foreground_is_none_for_a_box_outside_the_image() -> None:
    room = _room()
    watch = _watching(room, _person(room))
    assert watch.crop_foreground((700, 500, 800, 600), (32, 32)) is None


@pytest.mark.parametrize(("room_level", "found"), [(110, False), (40, True)])
def test_plate_threshold_shrinks_with_the_rooms_light(room_level: int, found: bool) -> None:
    # a face 30 levels (summed over R, G, B) brighter than the wall behind it: below
    # the threshold in a mid-gray room, foreground in a dim one where every
    # difference is smaller
    room = np.full((120, 160, 3), room_level, np.uint8)
    person = room.copy()
    person[40:80, 60:100] = room_level + 10
    plate = _learned(room)
    fg = plate.foreground(plate.small(person), (0, 0, 80, 60))
    assert fg is not None
    assert bool(fg[25:35, 35:45].all()) is found


def _stance(room: np.ndarray, left_v: int, right_v: int) -> np.ndarray:
    img = room.copy()
    x0, y0, x1, y1 = SHIRT
    img[y0:y1, x0:x1] = (200, 40, 40)
    img[y1:left_v, x0 + 6: x0 + 32] = (20, 20, 60)
    img[y1:right_v, x1 - 32: x1 - 6] = (20, 20, 60)
    return img


@pytest.mark.parametrize("right_v, staggered", [(420, False), (440, True), (470, None)])
def test_floor_reading_tells_how_far_apart_in_depth_the_feet_stand(
        right_v: int, staggered: bool | None) -> None:
    from types import SimpleNamespace

    from bodyplay.trackers.colorshirt import ColorShirtOptions
    from bodyplay.trackers.colorshirt.floor import floor_reading

    R, t = look_at((0.0, 1.25, 3.0), (0.0, 0.9, 0.0))
    cam = Camera.from_fov("cam0", 640, 480, 60.0, R, t)
    room = _room()
    state = CameraState(BackgroundMask(), floor=_watching(room, _stance(room, 420, right_v)))
    view = SimpleNamespace(index=0)
    reading = floor_reading((cam,), (state,), (view,), ColorShirtOptions(), 0.9)  # type: ignore[arg-type]
    assert reading.depth is not None
    if staggered is None:  # the far foot is above the lowest tenth: one foot found
        assert reading.stagger is None
        return
    assert reading.stagger is not None
    near, far = (floor_depth(cam, FeetPoint(320.0, v)) for v in (right_v + 1, 421))
    assert near is not None and far is not None
    assert reading.stagger == pytest.approx(far - near, abs=0.03)
    assert (reading.stagger > ColorShirtOptions().body_choice_max_stagger) == staggered
    two = floor_reading((cam, cam), (state, state), (view, view), ColorShirtOptions(), 0.9)  # type: ignore[arg-type]
    assert two.depth is None and two.stagger is None  # two cameras see depth themselves


def test_floor_reading_is_the_depth_of_the_root_above_the_feet_for_a_camera_looking_down(
) -> None:
    from types import SimpleNamespace

    from bodyplay.trackers.colorshirt import ColorShirtOptions
    from bodyplay.trackers.colorshirt.floor import floor_reading

    R, t = look_at((0.0, 1.25, 3.0), (0.0, 0.9, 0.0))
    cam = Camera.from_fov("cam0", 640, 480, 60.0, R, t)
    room = _room()
    state = CameraState(BackgroundMask(), floor=_watching(room, _stance(room, 420, 420)))
    feet = state.floor.feet()
    assert feet
    depth = floor_depth(cam, feet[0])
    assert depth is not None
    ray = np.linalg.solve(cam.K, np.array([feet[0].u, feet[0].v, 1.0]))
    root = cam.R.T @ (ray * depth) + cam.center + np.array([0.0, 0.9, 0.0])
    options = ColorShirtOptions(floor_offset=0.0)
    reading = floor_reading((cam,), (state,), (SimpleNamespace(index=0),), options, 0.9)  # type: ignore[arg-type]
    assert reading.depth == pytest.approx(float(cam.world_to_camera(root)[2]), abs=0.02)
    # the camera looks down: the root 0.9 m up is nearer along its axis than the feet
    assert reading.depth < depth - 0.05


def test_a_foot_split_by_the_threshold_still_reaches_down_to_its_toes() -> None:
    room = _room()
    player = _stance(room, 420, 420)
    x0, _, x1, _ = SHIRT
    player[398:402, x0 + 6: x0 + 32] = room[398:402, x0 + 6: x0 + 32]  # instep = floor
    feet = _feet(_learned(room), player)
    assert len(feet) == 2
    assert all(f.v >= 416 for f in feet)  # the toes below the gap, not the instep


def test_within_reach_rejects_a_root_that_crossed_the_room_since_the_last_pose() -> None:
    from bodyplay.trackers.colorshirt.gates import within_reach

    last = (1.0, np.array([0.0, 0.9, 0.0]))
    assert within_reach(None, 1.0, np.array([5.0, 0.9, 0.0]), 2.0)  # nothing reported yet
    assert within_reach(last, 1.1, np.array([0.4, 0.9, 0.0]), 2.0)  # 0.25 + 2 * 0.1 m
    assert not within_reach(last, 1.1, np.array([0.5, 0.9, 0.0]), 2.0)
    assert within_reach(last, 2.5, np.array([5.0, 0.9, 0.0]), 2.0)  # over a second ago


def _room_plate_masks(feet_v: int, unknown_to: int) -> tuple[np.ndarray, np.ndarray]:
    """Plate-resolution (foreground, known) of a player in view: the room plate knows
    every pixel but those of the player's grown silhouette, which reaches down to
    row ``unknown_to`` (full resolution); the feet end at ``feet_v``."""
    h, w = 240, 320
    x0, y0, x1, y1 = (c // 2 for c in SHIRT)
    known = np.ones((h, w), bool)
    known[y0 - 10: unknown_to // 2, x0 - 10: x1 + 10] = False  # the grown silhouette
    fg = ~known  # unknown pixels may be the player
    fg[y1: feet_v // 2, x0 + 3: x0 + 16] = True  # the legs, unlike the plate where known
    fg[y1: feet_v // 2, x1 - 16: x1 - 3] = True
    return fg, known


def test_feet_from_the_room_plate_count_only_where_the_plate_knows_the_floor_under_them(
) -> None:
    # a player who stood still since the first frame: the floor around the feet was
    # never uncovered, and the edge of the unknown silhouette is not a foot
    fg, known = _room_plate_masks(feet_v=400, unknown_to=440)
    assert feet_points(fg, SHIRT, 2, known) == ()
    assert len(feet_points(fg, SHIRT, 2)) > 0  # without ``known`` that edge read as feet
    # a player who walked onto floor the plate has seen: the feet are seen on it
    fg, known = _room_plate_masks(feet_v=420, unknown_to=380)
    feet = feet_points(fg, SHIRT, 2, known)
    assert len(feet) == 2 and all(abs(f.v - 420) <= 2 for f in feet)


def test_floor_watch_reads_the_feet_from_the_room_plate_without_an_empty_room() -> None:
    room = _room()
    state = CameraState(BackgroundMask(downscale=2), floor=FloorWatch(BackgroundPlate()))
    assert state.floor.room is state.room
    small = state.floor.plate.small(room)
    for _ in range(10):  # the room around the player, learned while tracking
        state.room.start(small)
        state.room.learn(None, everywhere=True)
    player = _person(room, feet_v=420)
    state.room.start(state.floor.plate.small(player))
    state.floor.start(player)
    state.floor.shirt_at(SHIRT)  # the player in view from the first frame: no plate
    assert not state.floor.plate.ready
    feet = state.floor.feet()
    assert len(feet) == 2 and all(abs(f.v - 420) <= 2 for f in feet)
