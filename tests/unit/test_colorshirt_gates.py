"""What a colour-shirt fit must pass to be reported (gates.py)."""

from __future__ import annotations

import numpy as np

from bodyplay.trackers.colorshirt.gates import SpeedGate

_AT = np.array([0.0, 0.9, 3.0])
_FAR = np.array([0.0, 0.9, 6.9])  # 3.9 m too deep


def test_speed_gate_rejects_a_root_that_crossed_the_room_since_the_last_pose() -> None:
    gate = SpeedGate(max_speed=3.0, good_residual=0.09)
    gate.report(0.0, _AT)
    assert not gate.admits(1 / 30, _FAR, residual=0.01)
    assert gate.admits(1 / 30, _AT + 0.05, residual=0.5)


def test_speed_gate_lets_two_good_fits_in_a_row_outvote_an_outlier_reported_before() -> None:
    gate = SpeedGate(max_speed=3.0, good_residual=0.09)
    gate.report(0.0, _FAR)  # the outlier that got reported
    assert not gate.admits(1 / 30, _AT, residual=0.05)  # the first right fit: rejected
    assert gate.admits(2 / 30, _AT, residual=0.05)  # the second agrees with it: taken
    assert gate.reported is None


def test_speed_gate_does_not_let_poor_fits_outvote_the_pose_reported() -> None:
    gate = SpeedGate(max_speed=3.0, good_residual=0.09)
    gate.report(0.0, _AT)
    assert not gate.admits(1 / 30, _FAR, residual=0.3)
    assert not gate.admits(2 / 30, _FAR, residual=0.3)


def test_speed_gate_forgets_a_pose_reported_over_a_second_ago() -> None:
    gate = SpeedGate(max_speed=3.0, good_residual=0.09)
    gate.report(0.0, _AT)
    assert gate.admits(1.5, _FAR, residual=0.3)
    gate.clear()
    assert gate.reported is None and gate.admits(1.6, _AT, residual=0.3)


def test_speed_gate_does_not_let_one_camera_of_several_outvote_the_pose_reported() -> None:
    gate = SpeedGate(max_speed=3.0, good_residual=0.09)
    gate.report(0.0, _AT)  # placed by both cameras
    assert not gate.admits(1 / 30, _FAR, residual=0.05, confirmed=False)
    assert not gate.admits(2 / 30, _FAR, residual=0.05, confirmed=False)
    assert gate.reported is not None and gate.unreached is None


def test_speed_gate_reports_one_camera_of_several_within_reach_of_the_pose() -> None:
    gate = SpeedGate(max_speed=3.0, good_residual=0.09)
    gate.report(0.0, _AT)
    assert gate.admits(1 / 30, _AT + 0.05, residual=0.3, confirmed=False)


def test_speed_gate_lets_two_cameras_outvote_a_pose_one_camera_placed() -> None:
    gate = SpeedGate(max_speed=3.0, good_residual=0.09)
    gate.report(0.0, _FAR)  # one camera's depth, reported
    assert not gate.admits(1 / 30, _AT, residual=0.05)
    assert gate.admits(2 / 30, _AT, residual=0.05)
