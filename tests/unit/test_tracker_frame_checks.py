"""Specifications of what every tracker checks of the frame sets it is fed
(``bodyplay.trackers.base.check_frame_set``): bad input is named, never a numba or
numpy error from inside a tracker."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.capture.camera import Camera
from bodyplay.capture.frames import Frame, FrameSet
from bodyplay.errors import CaptureError, TimestampError
from bodyplay.trackers.base import check_frame_set

CAMERA = Camera("cam0", 64, 48, np.array([[50.0, 0, 32], [0, 50.0, 24], [0, 0, 1]]))


def _frame_set(image: object, t: float = 0.0) -> FrameSet:
    return FrameSet((Frame(image, t, 0, "cam0"),), t, 0)  # type: ignore[arg-type]


def test_a_well_formed_frame_set_passes() -> None:
    check_frame_set(_frame_set(np.zeros((48, 64, 3), np.uint8)), (CAMERA,))


@pytest.mark.parametrize("image", [
    np.zeros((48, 64), np.uint8),
    np.zeros((48, 64, 4), np.uint8),
    np.zeros((48, 64, 3), np.float32),
    "frame.png",
])
def test_a_frame_that_is_not_an_rgb_uint8_image_is_named_with_what_it_is(image: object) -> None:
    with pytest.raises(CaptureError, match=r"frame 0 of camera 'cam0' is .*\(H, W, 3\) uint8"):
        check_frame_set(_frame_set(image), (CAMERA,))


@pytest.mark.parametrize("t", [float("nan"), float("inf")])
def test_a_frame_set_without_a_finite_time_is_rejected(t: float) -> None:
    with pytest.raises(TimestampError, match="capture time in seconds"):
        check_frame_set(_frame_set(np.zeros((48, 64, 3), np.uint8), t), (CAMERA,))

