"""Specifications of the fit's share on the room (benchmarks/colorshirt_clutter.py)."""

from __future__ import annotations

from collections.abc import Callable
from types import ModuleType

import numpy as np
import pytest


@pytest.fixture(scope="module")
def clutter(script_loader: Callable[..., ModuleType]) -> ModuleType:
    return script_loader("benchmarks/colorshirt_clutter.py", with_neighbours=True)


def test_room_pixels_are_those_like_the_empty_room_with_their_distance_from_the_player(
        clutter) -> None:  # type: ignore[no-untyped-def]
    room = np.full((40, 60, 3), 100.0, np.float32)
    image = np.full((40, 60, 3), 100, np.uint8)
    image[10:30, 20:30] = (200, 30, 30)  # the player
    uv = np.array([[25.5, 20.5], [35.5, 20.5], [50.5, 20.5]])  # on him, 6 px off, 21 px off
    on_room, distance = clutter.room_pixels(image, room, uv, 40.0)
    assert on_room.tolist() == [False, True, True]
    assert distance[0] == 0.0 and 5.0 <= distance[1] <= 7.0 and 20.0 <= distance[2] <= 22.0


def test_room_pixels_threshold_decides_what_counts_as_the_player(clutter) -> None:  # type: ignore[no-untyped-def]
    room = np.full((10, 10, 3), 100.0, np.float32)
    image = np.full((10, 10, 3), 110, np.uint8)  # 30 summed RGB from the room everywhere
    uv = np.array([[5.0, 5.0]])
    assert clutter.room_pixels(image, room, uv, 40.0)[0].tolist() == [True]
    assert clutter.room_pixels(image, room, uv, 20.0)[0].tolist() == [False]
