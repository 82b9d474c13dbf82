"""Specifications of the joints' systematic offsets (benchmarks/colorshirt_offsets.py)."""

from __future__ import annotations

from collections.abc import Callable
from types import ModuleType

import numpy as np
import pytest

from bodyplay.body import Skeleton
from bodyplay.body.joints import JOINT_INDEX


@pytest.fixture(scope="module")
def offsets(script_loader: Callable[..., ModuleType]) -> ModuleType:
    return script_loader("benchmarks/colorshirt_offsets.py", with_neighbours=True)


def _truth(yaw: float = 0.0) -> np.ndarray:
    sk = Skeleton()
    q = sk.rest_pose()
    q[3:6] = (0.0, yaw, 0.0)  # the pelvis's rotation: the whole body turns about Y
    return sk.joint_positions(q)


def test_offsets_frame_is_the_players_left_up_and_facing(offsets) -> None:  # type: ignore[no-untyped-def]
    np.testing.assert_allclose(offsets.body_frame(_truth()), np.eye(3), atol=1e-9)
    turned = offsets.body_frame(_truth(np.pi / 2))  # facing +X: the left is -Z
    np.testing.assert_allclose(turned[0], [0.0, 0.0, -1.0], atol=1e-9)
    np.testing.assert_allclose(turned[2], [1.0, 0.0, 0.0], atol=1e-9)


def test_offsets_read_a_pelvis_ahead_of_the_truth_as_facing_whatever_the_heading(  # type: ignore[no-untyped-def]
        offsets) -> None:
    for yaw in (0.0, 0.7, -2.0):
        truth = _truth(yaw)
        facing = offsets.body_frame(truth)[2]
        joints = truth.copy()
        joints[JOINT_INDEX["pelvis"]] += 0.03 * facing
        d, _ = offsets.frame_offsets(joints, truth)
        np.testing.assert_allclose(d[JOINT_INDEX["pelvis"]], [0.0, 0.0, 0.03], atol=1e-9)
        assert np.abs(np.delete(d, JOINT_INDEX["pelvis"], axis=0)).max() < 1e-12


def test_offsets_read_a_short_forearm_as_a_wrist_short_along_it(offsets) -> None:  # type: ignore[no-untyped-def]
    truth = _truth()
    joints = truth.copy()
    el, wr = JOINT_INDEX["l_elbow"], JOINT_INDEX["l_wrist"]
    along = (truth[wr] - truth[el]) / np.linalg.norm(truth[wr] - truth[el])
    joints[wr] -= 0.02 * along
    _, arm = offsets.frame_offsets(joints, truth)
    named = dict(zip(offsets._ARM_COLUMNS, arm, strict=True))
    assert named["l_wrist_along"] == pytest.approx(-0.02)
    assert named["l_fore_len"] == pytest.approx(-0.02)
    assert named["l_upper_len"] == pytest.approx(0.0, abs=1e-12)
    assert named["r_wrist_along"] == pytest.approx(0.0, abs=1e-12)
