"""The stance cue for the silhouette tracker's root depth (trackers/silhouette/stance.py)."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette import SilhouetteOptions
from bodyplay.trackers.silhouette.stance import feet_rows, stance_offset

CAM_H, MPP, D, FLOOR = 1.2, 0.009, 3.0, 220


def _legs(left_bottom: int, right_bottom: int) -> np.ndarray:
    """A window mask of two legs ending at the given rows (x 140-150 and 170-180)."""
    m = np.zeros((240, 320), np.uint8)
    m[40:left_bottom + 1, 140:151] = 1
    m[40:right_bottom + 1, 170:181] = 1
    return m


def _row_of(distance: float) -> float:
    """Window row of the floor at ``distance`` in the window built for ``D``."""
    return FLOOR + CAM_H * (D / distance - 1.0) / MPP


def test_feet_rows_gives_each_foots_lowest_row() -> None:
    assert feet_rows(_legs(220, 200), band=28) == (220.0, 200.0)
    assert feet_rows(np.zeros((10, 10), np.uint8), band=3) is None


def test_stance_offset_puts_a_template_with_a_foot_back_nearer_for_feet_together() -> None:
    # the template's back foot stands 0.4 m behind its front one; the player's feet
    # are side by side at G: the player's feet (and body) are 0.2 m nearer
    back = int(round(_row_of(D + 0.4)))
    off = stance_offset(_legs(FLOOR, FLOOR), _legs(FLOOR, back), FLOOR, MPP, D, CAM_H, 28)
    assert off is not None
    assert off == pytest.approx(-0.2, abs=0.02)


def test_stance_offset_is_zero_when_the_stances_agree() -> None:
    m = _legs(FLOOR, FLOOR - 10)
    assert stance_offset(m, m, FLOOR, MPP, D, CAM_H, 28) == pytest.approx(0.0)


def test_stance_offset_rejects_an_implausible_spread() -> None:
    # a "foot" 60 rows up is a shadow or a limb, not a stance 1 m deep
    assert stance_offset(_legs(FLOOR, FLOOR), _legs(FLOOR, FLOOR - 60), FLOOR, MPP, D, CAM_H,
                         80) is None


def test_silhouette_options_reject_a_stance_weight_outside_zero_to_one() -> None:
    with pytest.raises(ConfigError):
        SilhouetteOptions(stance_weight=-0.1)
    with pytest.raises(ConfigError):
        SilhouetteOptions(stance_window=-1.0)
    with pytest.raises(ConfigError):
        SilhouetteOptions(stance_deadband=-0.01)
