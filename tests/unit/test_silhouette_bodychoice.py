"""The silhouette tracker's body-size choice (bodychoice.BodyChoice), on its readings."""

from __future__ import annotations

from typing import cast

from bodyplay.trackers.silhouette import SilhouetteOptions
from bodyplay.trackers.silhouette.bodychoice import BodyChoice
from bodyplay.trackers.silhouette.hierarchy import ShapeTree
from bodyplay.trackers.silhouette.window import WindowGeometry

_TREE = cast(ShapeTree, None)  # best() and clear() read no templates


def _choice(cue: str = "stature", chosen: str | None = None) -> BodyChoice:
    return BodyChoice(["s", "m", "l"], _TREE, WindowGeometry(),
                      SilhouetteOptions(body_cue=cue), chosen)


def test_body_choice_keeps_the_best_fit_among_presets_of_the_players_stature() -> None:
    choice = _choice()
    choice.scores = {"s": [0.10, 0.10], "m": [0.20, 0.20], "l": [0.15, 0.15]}
    px = 0.01 / WindowGeometry().mpp(2)  # 1 cm in level-3 window pixels
    choice.tops = {"s": [20 * px, 20 * px], "m": [1 * px, -1 * px], "l": [3 * px, 2 * px]}
    # "s" fits best but its head top is 20 cm off; "m" and "l" are within 5 cm
    assert choice.best() == "l"


def test_body_choice_by_distance_alone_keeps_the_best_fit() -> None:
    choice = _choice(cue="distance")
    choice.scores = {"s": [0.10], "m": [0.20], "l": [0.15]}
    assert choice.best() == "s"


def test_body_choice_once_chosen_reports_the_chosen_preset() -> None:
    choice = _choice(chosen="m")
    choice.scores = {"s": [0.10], "m": [0.20], "l": [0.15]}
    assert choice.best() == "m"


def test_body_choice_clear_forgets_the_readings_so_far() -> None:
    choice = _choice()
    choice.scores["m"].append(0.2)
    choice.tops["m"].append(1.0)
    choice.clear()
    assert choice.frames == 0 and not choice.tops["m"]
