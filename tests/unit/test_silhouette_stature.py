"""The body-size reading of the silhouette tracker: head tops, or shoulders where the
room took the head."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette import SilhouetteOptions
from bodyplay.trackers.silhouette.stature import shoulder_row, stature_reading


def _figure(top: int, h: int = 120, w: int = 80, head: bool = True) -> np.ndarray:
    """A front-view stick figure whose head top is at row ``top``: a 10 px wide head
    of 14 rows, a 6 px neck of 4 rows, 30 px wide shoulders and torso below, legs."""
    m = np.zeros((h, w), np.uint8)
    c = w // 2
    if head:
        m[top:top + 14, c - 5:c + 5] = 1
    m[top + 14:top + 18, c - 3:c + 3] = 1
    m[top + 18:top + 60, c - 15:c + 15] = 1
    m[top + 60:h - 2, c - 12:c - 4] = 1
    m[top + 60:h - 2, c + 4:c + 12] = 1
    return m


def test_shoulder_row_is_the_first_row_as_wide_as_shoulders_below_head_and_neck() -> None:
    assert shoulder_row(_figure(10), wide=20) == 28.0


def test_shoulder_row_ignores_a_raised_arm_beside_the_head() -> None:
    m = _figure(20)
    m[0:40, 52:56] = 1  # a forearm raised above the shoulder, apart from the head
    assert shoulder_row(m, wide=20) == 38.0


def test_shoulder_row_is_none_for_a_silhouette_narrower_than_shoulders() -> None:
    assert shoulder_row(_figure(10), wide=40) is None


def test_stature_reading_compares_head_tops_when_the_observed_head_shows() -> None:
    observed = _figure(12)
    template = _figure(10)  # a body whose head top reaches 2 rows higher
    assert stature_reading(observed, template, (0, 0), 20, 0.5) == (-2.0, True)


def test_stature_reading_compares_shoulders_when_the_room_took_the_head() -> None:
    observed = _figure(12, head=False)  # the same player, the head lost to the wall
    template = _figure(12)
    # the head tops differ by the whole head (14 rows), the shoulders not at all
    assert stature_reading(observed, template, (0, 0), 20, 0.5) == (0.0, False)
    assert stature_reading(observed, template, (0, 0), 20, 0.0) == (-14.0, True)


def test_stature_reading_places_the_template_by_its_fitted_shift() -> None:
    observed = _figure(12, head=False)
    template = _figure(10)
    assert stature_reading(observed, template, (0, 2), 20, 0.5) == (0.0, False)
    assert stature_reading(_figure(12), template, (0, 2), 20, 0.5) == (0.0, True)


def test_stature_reading_is_none_for_an_empty_observation() -> None:
    assert stature_reading(np.zeros((120, 80), np.uint8), _figure(10), (0, 0), 20, 0.5) is None


@pytest.mark.parametrize("field, value", [("head_gap", -0.1), ("head_gap", 1.5),
                                          ("shoulder_width", 0.05), ("shoulder_width", 1.0)])
def test_silhouette_options_reject_a_head_gap_or_shoulder_width_out_of_range(
        field: str, value: float) -> None:
    with pytest.raises(ConfigError):
        SilhouetteOptions(**{field: value})


def test_silhouette_options_read_the_head_top_alone_by_default() -> None:
    # the shoulder reading did not carry over to the report rooms: opt-in only
    o = SilhouetteOptions()
    assert o.head_gap == 0.0
    observed, template = _figure(12, head=False), _figure(12)
    assert stature_reading(observed, template, (0, 0), 20, o.head_gap) == (-14.0, True)
