"""The colour-shirt tracker's start: which combination of candidate regions starts a
track (start.choose_start), on stand-in regions and fits."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any, cast

import numpy as np

from bodyplay.trackers.colorshirt.start import (
    MOVED_SHARE,
    START_PATCHES,
    STILL_PATCHES,
    StartFit,
    choose_start,
)
from bodyplay.trackers.colorshirt.views import CameraView

_BAND = (0.5, 1.5)


def _region(camera: int, name: str) -> CameraView:
    return cast(CameraView, SimpleNamespace(index=camera, name=name))


def _fits(table: dict[frozenset[str], tuple[float, int, float]]) -> Any:
    def fit(chosen: list[CameraView]) -> StartFit | None:
        key = frozenset(cast(Any, v).name for v in chosen)
        if key not in table:
            return None
        height, patches, residual = table[key]
        return np.array([0.0, height, 3.0]), patches, residual
    return fit


def test_start_prefers_the_combination_both_cameras_see() -> None:
    a, b = _region(0, "a"), _region(1, "b")
    fit = _fits({frozenset("a"): (1.0, 10, 0.01), frozenset("ab"): (1.0, 10, 0.05)})
    start = choose_start([[a], [b]], [], None, lambda v: True, fit, _BAND, True)
    assert start.views == [a, b]


def test_start_rejects_a_fit_that_is_not_upright() -> None:
    a = _region(0, "a")
    fit = _fits({frozenset("a"): (0.2, 12, 0.01)})  # the root 0.2 m above the floor
    start = choose_start([[a]], [], None, lambda v: True, fit, _BAND, True)
    assert start.views is None and start.held == []


def test_start_holds_a_still_region_whose_fit_anchors_too_little_of_the_shirt() -> None:
    poster = _region(0, "poster")
    fit = _fits({frozenset(["poster"]): (1.0, STILL_PATCHES - 1, 0.01)})
    start = choose_start([[poster]], [], None, lambda v: False, fit, _BAND, True)
    assert start.views is None and start.held == [poster]


def test_one_camera_starts_on_a_still_player_who_shows_enough_of_the_shirt() -> None:
    player = _region(0, "player")
    fit = _fits({frozenset(["player"]): (1.0, STILL_PATCHES + 2, 0.05)})
    start = choose_start([[player]], [], None, lambda v: False, fit, _BAND, True)
    assert start.views == [player]


def test_one_camera_ranks_regions_by_patches_before_residual() -> None:
    piece, player = _region(0, "piece"), _region(0, "player")
    fit = _fits({frozenset(["piece"]): (1.0, START_PATCHES, 0.001),
                 frozenset(["player"]): (1.0, START_PATCHES + 4, 0.08)})
    start = choose_start([[piece, player]], [], None, lambda v: True, fit, _BAND, True)
    assert start.views == [player]


def test_a_lone_cameras_track_is_kept_in_every_combination() -> None:
    tracked, other = _region(0, "tracked"), _region(1, "other")
    fit = _fits({frozenset(["tracked", "other"]): (1.0, 10, 0.05)})
    start = choose_start([[tracked], [other]], [tracked], 0, lambda v: True, fit, _BAND, True)
    assert start.views == [tracked, other]


def test_one_camera_never_starts_on_a_still_region_learned_as_the_empty_room() -> None:
    rug = _region(0, "rug")
    fit = _fits({frozenset(["rug"]): (1.0, STILL_PATCHES + 2, 0.01)})
    start = choose_start([[rug]], [], None, lambda v: False, fit, _BAND, True,
                         seen_empty=lambda v: True)
    assert start.views is None and start.held == []  # not held: the plates learn it


def test_a_region_that_moved_starts_where_the_room_was_seen_empty() -> None:
    player = _region(0, "player")
    fit = _fits({frozenset(["player"]): (1.0, START_PATCHES + 2, 0.05)})
    start = choose_start([[player]], [], None, lambda v: True, fit, _BAND, True,
                         seen_empty=lambda v: True)
    assert start.views == [player]


def test_one_camera_ranks_a_region_lying_in_what_moved_before_one_anchoring_more() -> None:
    """Draw 2's fruit room: a shelf of fruit in the shirt's colours anchors more patches
    than the player beside it (8 against 7) and started the track (164 cm, a pose on 1%
    of frames); once the room plate saw the player move, the region lying in what moved
    ranks first, whatever it anchors."""
    shelf, player = _region(0, "shelf"), _region(0, "player")
    fit = _fits({frozenset(["shelf"]): (1.0, START_PATCHES + 2, 0.05),
                 frozenset(["player"]): (1.0, START_PATCHES + 1, 0.05)})
    share = {"shelf": 0.0, "player": MOVED_SHARE + 0.3}
    start = choose_start([[shelf, player]], [], None, lambda v: True, fit, _BAND, True,
                         moved_share=lambda v: share[cast(Any, v).name])
    assert start.views == [player]


def test_one_camera_without_anything_that_moved_still_ranks_by_patches() -> None:
    """A lone camera's first frame (nothing seen to change yet) or a player waiting
    still: every region scores zero, none is refused for it, and the most patches
    anchored win as before."""
    poster, player = _region(0, "poster"), _region(0, "player")
    fit = _fits({frozenset(["poster"]): (1.0, START_PATCHES, 0.05),
                 frozenset(["player"]): (1.0, START_PATCHES + 3, 0.05)})
    start = choose_start([[poster, player]], [], None, lambda v: True, fit, _BAND, True,
                         moved_share=lambda v: 0.0)
    assert start.views == [player]


def test_two_cameras_ignore_what_moved_in_one_camera() -> None:
    """With two cameras the start is as before: the combination both see wins, what one
    camera's room plate saw move does not rank it."""
    a, b, c = _region(0, "a"), _region(1, "b"), _region(0, "c")
    fit = _fits({frozenset(["a", "b"]): (1.0, 8, 0.05), frozenset(["c", "b"]): (1.0, 8, 0.04)})
    share = {"a": 1.0, "b": 1.0, "c": 0.0}
    start = choose_start([[a, c], [b]], [], None, lambda v: True, fit, _BAND, True,
                         moved_share=lambda v: share[cast(Any, v).name])
    assert start.views == [c, b]  # the lower residual, as without the scores
