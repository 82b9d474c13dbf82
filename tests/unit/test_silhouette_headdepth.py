"""The head-top depth cue of the silhouette tracker (trackers/silhouette/headdepth.py)."""

from __future__ import annotations

import pytest

from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette import SilhouetteOptions
from bodyplay.trackers.silhouette.headdepth import RunningMedian, head_depth_offset

CAM_H, MPP, D, FLOOR = 1.2, 0.009, 3.0, 220.0


def _row(height: float, true_distance: float) -> float:
    """Window row of a point at ``height`` seen from ``true_distance`` in a window
    built for the floor point at distance ``D`` (level camera at ``CAM_H``)."""
    return FLOOR - CAM_H / MPP + (D / MPP) * (CAM_H - height) / true_distance


def test_head_depth_offset_recovers_a_player_standing_nearer_than_the_floor_point_says() -> None:
    template_top = _row(1.75, D)
    observed_top = _row(1.75, 2.8)
    off = head_depth_offset(observed_top, template_top, FLOOR, MPP, D, CAM_H)
    assert off is not None
    assert off == pytest.approx(-0.2, abs=0.02)


def test_head_depth_offset_says_farther_when_the_observed_head_is_lower() -> None:
    off = head_depth_offset(_row(1.75, 3.3), _row(1.75, D), FLOOR, MPP, D, CAM_H)
    assert off is not None and off == pytest.approx(0.3, abs=0.03)


def test_head_depth_offset_skips_a_head_near_the_camera_height() -> None:
    assert head_depth_offset(_row(1.3, 2.8), _row(1.3, D), FLOOR, MPP, D, CAM_H) is None


def test_head_depth_median_forgets_cues_older_than_its_window() -> None:
    h = RunningMedian(window=0.5)
    assert h.add(0.0, None) == 0.0
    h.add(0.0, 1.0)
    h.add(0.1, 0.2)
    assert h.add(0.2, 0.4) == pytest.approx(0.4)
    assert h.add(0.55, None) == pytest.approx(0.3)  # the cue of t=0 is gone


def test_silhouette_options_reject_a_head_depth_weight_outside_zero_to_one() -> None:
    with pytest.raises(ConfigError):
        SilhouetteOptions(head_depth_weight=1.5)
    with pytest.raises(ConfigError):
        SilhouetteOptions(head_min_lever=0.0)
