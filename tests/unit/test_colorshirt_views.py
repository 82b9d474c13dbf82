"""Specifications of the classification clean-up (views.clean_ids)."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.trackers.colorshirt.views import WHITE_ID, clean_ids, nonzero_box

RED, ORANGE, YELLOW, GREEN, CYAN, BLUE, PURPLE = 1, 2, 3, 5, 6, 7, 8


def _torso(ids: np.ndarray) -> None:
    """A 50 x 40 two-color torso at rows 20..70, columns 40..80."""
    ids[20:70, 40:60] = RED
    ids[20:70, 60:80] = ORANGE


def test_arm_cut_off_by_a_white_shoulder_cap_stays_with_the_shirt() -> None:
    ids = np.zeros((100, 120), np.uint8)
    _torso(ids)
    ids[18:24, 30:40] = WHITE_ID          # the white cap between torso and arm
    ids[24:40, 29:35] = CYAN              # upper arm, 5 px from the torso
    ids[40:56, 29:35] = PURPLE            # forearm
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1)
    assert np.count_nonzero(out == CYAN) == np.count_nonzero(ids == CYAN)
    assert np.count_nonzero(out == PURPLE) == np.count_nonzero(ids == PURPLE)
    assert np.count_nonzero(out == WHITE_ID) > 0


def test_arm_joined_to_the_shirt_only_through_a_wide_white_cap_is_kept() -> None:
    # the gap (12 px) is wider than the attach reach (5 px) and the arm is 12% of
    # the torso: only the white cap ties it to the shirt
    ids = np.zeros((100, 120), np.uint8)
    _torso(ids)
    ids[18:30, 22:40] = WHITE_ID          # a wide white shoulder cap
    ids[30:46, 22:28] = CYAN              # upper arm, 12 px left of the torso
    ids[46:62, 22:28] = PURPLE            # forearm
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1)
    assert np.count_nonzero(out == CYAN) == np.count_nonzero(ids == CYAN)
    assert np.count_nonzero(out == PURPLE) == np.count_nonzero(ids == PURPLE)
    ids[18:30, 22:40] = 0                 # without the cap it is a stray blob
    assert not np.any(clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1) == CYAN)


def test_arm_beside_the_body_was_dropped_without_the_attach_rule() -> None:
    ids = np.zeros((100, 120), np.uint8)
    _torso(ids)
    ids[24:40, 29:35] = CYAN
    ids[40:56, 29:35] = PURPLE
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.0)
    assert not np.any(out == CYAN)


def test_small_colorful_blob_far_from_the_shirt_is_dropped() -> None:
    ids = np.zeros((100, 120), np.uint8)
    _torso(ids)
    ids[85:95, 100:105] = CYAN            # a poster in the room, 15 px below the shirt
    ids[85:95, 105:110] = PURPLE
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1)
    assert not np.any(out[75:, 90:])
    assert np.count_nonzero(out) == 2000


def test_one_colored_object_alone_is_not_a_shirt() -> None:
    ids = np.zeros((60, 60), np.uint8)
    ids[10:50, 10:50] = CYAN
    assert not np.any(clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1))


def test_one_colored_blob_next_to_the_shirt_is_dropped() -> None:
    # skin above the collar classified as orange must not join the shirt
    ids = np.zeros((100, 120), np.uint8)
    _torso(ids)
    ids[6:15, 55:65] = ORANGE             # the face, 5 px above the torso
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1)
    assert not np.any(out[:18])


def test_lone_forearm_next_to_the_shirt_is_kept_in_its_sleeve_color() -> None:
    # the upper arm hidden behind the body: only the purple forearm shows, 5 px away
    ids = np.zeros((100, 120), np.uint8)
    _torso(ids)
    ids[40:60, 29:35] = PURPLE
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1)
    assert np.count_nonzero(out == PURPLE) == 120


RAISED_SHIRT = (130, 120)


def _shirt_with_raised_arms(ids: np.ndarray) -> None:
    """A 50 x 40 two-color torso at rows 50..100, columns 40..80, and both upper arms
    raised from its shoulders (rows 36..50): the shirt spans 63 px, so the attach
    reach is 6 px and the sleeve reach 12 px."""
    ids[50:100, 40:60] = RED
    ids[50:100, 60:80] = ORANGE
    ids[36:50, 41:45] = CYAN
    ids[36:50, 75:79] = GREEN


def _forearms_over_the_head(ids: np.ndarray, left: int, right: int) -> None:
    """Both forearms raised together, crossed over the head: one blob in two colors
    at rows 20..27, 9 px above the elbows (the head between the upper arms)."""
    ids[20:28, 50:60] = left
    ids[20:28, 60:70] = right


def test_both_forearms_over_the_head_are_kept_within_the_sleeve_reach() -> None:
    ids = np.zeros(RAISED_SHIRT, np.uint8)
    _shirt_with_raised_arms(ids)
    _forearms_over_the_head(ids, BLUE, PURPLE)
    # 9 px is beyond the attach reach (10% of the 63 px shirt: 6 px) ...
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1)
    assert not np.any(out[:34])
    # ... and within the sleeve reach (20%: 12 px) of the raised upper arms
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1, sleeve_attach=0.2)
    assert np.count_nonzero(out == BLUE) == 80
    assert np.count_nonzero(out == PURPLE) == 80


def test_sleeve_reach_drops_a_blob_over_the_shoulder_when_no_upper_arm_is_raised() -> None:
    # fruit on a shelf just above the shoulder (the validation set's kick clip, side
    # camera): sleeve colors over the shirt, within the sleeve reach of the torso and
    # of the top of a hanging arm, but no raised upper arm for forearms to hang from
    ids = np.zeros(RAISED_SHIRT, np.uint8)
    ids[50:100, 40:60] = RED
    ids[50:100, 60:80] = ORANGE
    ids[50:80, 34:38] = CYAN              # an arm hanging beside the torso
    ids[35:43, 40:48] = BLUE              # the fruit, 8 px above the shoulder
    ids[35:43, 48:56] = GREEN
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1, sleeve_attach=0.2)
    assert not np.any(out[:46])
    assert np.count_nonzero(out == CYAN) == 120
    # raise the upper arm and the same blob is a forearm over the head
    ids[50:80, 34:38] = 0
    ids[44:50, 41:45] = CYAN
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1, sleeve_attach=0.2)
    assert np.count_nonzero(out == BLUE) == 64


def test_sleeve_reach_keeps_only_blobs_in_two_sleeve_colors() -> None:
    ids = np.zeros(RAISED_SHIRT, np.uint8)
    _shirt_with_raised_arms(ids)
    _forearms_over_the_head(ids, RED, YELLOW)  # torso colors there: not an arm
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1, sleeve_attach=0.2)
    assert not np.any(out[:34])
    ids[:34] = 0
    ids[20:28, 55:65] = PURPLE                # one sleeve color alone: not kept that far
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1, sleeve_attach=0.2)
    assert not np.any(out[:34])
    ids[20:24, 53:55] = ORANGE                # nor with a speck of a torso color
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1, sleeve_attach=0.2)
    assert not np.any(out[:34])


def test_sleeve_reach_keeps_only_blobs_over_the_shirt() -> None:
    # the same two sleeve colors 9 px above the raised arms but beside the shirt's
    # columns: a poster by the player's head, not forearms over it
    ids = np.zeros(RAISED_SHIRT, np.uint8)
    _shirt_with_raised_arms(ids)
    ids[20:28, 82:92] = BLUE
    ids[20:28, 92:102] = PURPLE
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1, sleeve_attach=0.2)
    assert not np.any(out[:34])
    # and below the shirt's top (beside the torso) it is no forearm over the head
    ids[:34] = 0
    ids[60:70, 28:32] = BLUE              # 8 px left of the torso
    ids[70:80, 28:32] = PURPLE
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1, sleeve_attach=0.2)
    assert not np.any(out[:, :38])


def test_sleeve_colored_poster_beyond_the_sleeve_reach_is_dropped() -> None:
    ids = np.zeros(RAISED_SHIRT, np.uint8)
    _shirt_with_raised_arms(ids)
    ids[115:125, 100:105] = CYAN          # 16 px below the shirt
    ids[115:125, 105:110] = PURPLE
    out = clean_ids(ids, blob_fraction=0.15, attach_fraction=0.1, sleeve_attach=0.2)
    assert not np.any(out[105:, 90:])


def test_prior_penalty_slope_is_the_papers_under_a_mild_balance_and_grows_with_its_gain(
) -> None:
    from bodyplay.trackers.colorshirt.views import prior_penalty_slope

    s = 120.0
    paper = 6.0 / s
    assert prior_penalty_slope(6.0, s, np.eye(3), 2.0) == pytest.approx(paper)
    # a balance that darkens never weakens the prior below the paper's
    assert prior_penalty_slope(6.0, s, 0.5 * np.eye(3), 2.0) == pytest.approx(paper)
    # a balance amplifying the image 1.7 times (dim light): C grows by 1.7 ** 2
    W = np.diag([1.2, 1.7, 1.7**3 / (1.2 * 1.7)])
    assert prior_penalty_slope(6.0, s, W, 2.0) == pytest.approx(paper * 1.7**2)
    assert prior_penalty_slope(6.0, s, W, 0.0) == pytest.approx(paper)


def test_options_reject_a_negative_prior_gain_power() -> None:
    from bodyplay.errors import ConfigError
    from bodyplay.trackers.colorshirt import ColorShirtOptions

    with pytest.raises(ConfigError, match="prior_gain_power"):
        ColorShirtOptions(prior_gain_power=-1.0)


def test_nonzero_box_is_the_bounds_of_np_nonzero() -> None:
    rng = np.random.default_rng(0)
    for _ in range(50):
        mask = rng.random((int(rng.integers(1, 40)), int(rng.integers(1, 40)))) < 0.02
        ys, xs = np.nonzero(mask)
        expected = (xs.min(), ys.min(), xs.max(), ys.max()) if len(xs) else None
        assert nonzero_box(mask) == expected
