"""The room plate learned from what the player uncovers (colorshirt/plate.py)."""

from __future__ import annotations

import numpy as np

from bodyplay.trackers.colorshirt.plate import RoomPlate, column_median

H, W = 60, 80


def _room(seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    room = np.zeros((H, W, 3), np.float32)
    room[:] = (150, 140, 120)
    room[10:30, 50:70] = (30, 60, 220)  # a blue poster
    return room + rng.normal(0, 2, room.shape).astype(np.float32)


def _player(room: np.ndarray, x: int) -> tuple[np.ndarray, np.ndarray]:
    frame = room.copy()
    frame[15:50, x:x + 12] = (240, 120, 20)  # an orange shirt
    person = np.zeros((H, W), bool)
    person[12:53, x - 3:x + 15] = True  # the pose's silhouette, grown
    return frame, person


def test_room_plate_learns_the_room_the_player_uncovers_and_masks_it() -> None:
    plate, room = RoomPlate(), _room()
    for k in range(30):
        x = 54 - (k // 6) * 9  # starts in front of the poster, then steps away
        frame, person = _player(room, x)
        plate.start(frame)
        plate.learn(person)
    fg = plate.foreground()
    assert fg is not None
    assert not fg[10:30, 52:68].any()  # the poster the player stood in front of is room
    assert fg[20:45, x + 2:x + 10].all()  # the player is not
    assert plate.known is not None and plate.known.mean() > 0.6


def test_room_plate_never_learns_a_player_who_stands_still() -> None:
    plate, room = RoomPlate(), _room()
    frame, person = _player(room, 30)
    for _ in range(60):
        plate.start(frame)
        plate.learn(person)
    fg = plate.foreground()
    assert fg is not None and fg[15:50, 30:42].all()


def test_room_plate_forgets_what_moves_and_gives_no_mask_before_it_knows_anything() -> None:
    plate, room = RoomPlate(), _room()
    plate.start(room)
    assert plate.foreground() is None
    for _ in range(10):
        plate.start(room)
        plate.learn(None, everywhere=True)  # an empty room before the first pose
    known = plate.known
    assert known is not None and known.all()
    frame, _ = _player(room, 30)  # the player walks in where no pose covers them yet
    plate.start(frame)
    plate.learn(None)
    known = plate.known
    assert known is not None and not known[15:50, 30:42].any() and known[:, :20].all()


def test_room_plate_follows_a_lamp_switched_off() -> None:
    plate, room = RoomPlate(), _room()
    for _ in range(10):
        plate.start(room)
        plate.learn(None, everywhere=True)
    dim = room * np.float32(0.55)
    plate.start(dim)
    fg = plate.foreground()
    assert fg is not None and fg.mean() < 0.05


def test_room_plate_remembers_only_the_room_it_saw_before_the_player_appeared() -> None:
    """Pixels learned on empty-room frames (``learn(None, everywhere=True)``) are the
    empty room; pixels learned beside a player are not (the tracker keeps the
    shirt's whole box as foreground only over the empty room)."""
    plate, room = RoomPlate(), _room()
    for _ in range(3):  # a start with the player in view: nothing seen empty
        frame, person = _player(room, 30)
        plate.start(frame)
        plate.learn(person)
    assert plate.empty_room is None
    empty = RoomPlate()
    for _ in range(5):
        empty.start(room)
        empty.learn(None, everywhere=True)
    seen = empty.empty_room
    assert seen is not None and seen.all()


def test_room_plate_never_learns_an_ambiguous_region_as_the_empty_room_until_it_moves() -> None:
    """Before the first pose a start region that fits a shirt but never moved may be
    a player standing still: the frames teach the room around it, never it, until
    the plate sees it change (the player steps away and uncovers the room)."""
    plate, room = RoomPlate(), _room()
    frame, person = _player(room, 30)
    for _ in range(20):  # the player waits, still, before any pose is reported
        plate.start(frame)
        plate.learn(None, everywhere=True, ambiguous=person)
    fg = plate.foreground()
    assert fg is not None and fg[15:50, 30:42].all()  # still the player
    assert not fg[:, :20].any()  # the room beside is known
    for _ in range(10):  # the player has left: the plate sees the room change there
        plate.start(room)
        plate.learn(None, everywhere=True, ambiguous=person)
    fg = plate.foreground()
    assert fg is not None and not fg[15:50, 30:42].any()


def test_column_median_equals_numpys_median_for_odd_and_even_counts() -> None:
    rng = np.random.default_rng(3)
    for n in (1, 2, 3, 100, 4799, 4800):
        x = (rng.random((n, 3)) * 255).astype(np.float32)
        x[: n // 3] = np.round(x[: n // 3])  # ties, as in integer images
        got = column_median(x)
        assert got.dtype == np.float32
        np.testing.assert_array_equal(got, np.median(x, axis=0))


def _waving(room: np.ndarray, k: int) -> np.ndarray:
    """A player whose trunk stands still at x 30-42 while a forearm waves above it."""
    frame = room.copy()
    frame[20:50, 30:42] = (240, 120, 20)  # the still trunk
    x = 30 + 3 * (k % 4)
    frame[8:20, x:x + 4] = (30, 200, 60)  # the forearm, moving
    return frame


def test_room_plate_does_not_read_a_cameras_noise_as_a_player_who_moved() -> None:
    """An empty room whose camera changes scattered single pixels and pairs from frame
    to frame (draw 2's empty second: hundreds of them) has not seen a player move and
    has no moved zone; a moving limb has."""
    rng = np.random.default_rng(5)
    plate, room = RoomPlate(), _room()
    for _ in range(30):
        frame = room.copy()
        ys, xs = rng.integers(0, room.shape[0], 6), rng.integers(0, room.shape[1] - 1, 6)
        frame[ys, xs] = 255 - frame[ys, xs]  # single pixels
        frame[ys, xs + 1] = 255 - frame[ys, xs + 1]  # and pairs
        plate.start(frame)
        plate.learn(None, everywhere=True)
    assert not plate.saw_a_player_move() and plate.moved_zone() is None
    for k in range(3):
        plate.start(_waving(room, k))
        plate.learn(None, everywhere=True)
    assert plate.saw_a_player_move()


def test_room_plates_moved_zone_holds_a_still_trunk_under_a_waving_arm_not_a_poster_beside(
) -> None:
    """Where a player who moved may be: the hull of what changed and everything under it
    holds the still trunk under the waving forearm; the still poster beside the player,
    in the shirt's colours, lies outside (a start region there scores zero)."""
    plate, room = RoomPlate(), _room()
    assert plate.moved_zone() is None  # before any frame
    for k in range(6):
        plate.start(_waving(room, k))
        plate.learn(None)
    zone = plate.moved_zone()
    assert zone is not None
    assert zone[8:20, 31:42].all()  # the waving forearm
    assert zone[20:50, 32:41].all()  # the still trunk under it
    assert not zone[10:30, 50:70].any()  # the poster beside the player
