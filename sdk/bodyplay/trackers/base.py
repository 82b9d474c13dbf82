"""What every tracker is: the Tracker protocol, its capabilities and its result type.

Trackers follow the Options / Thing / Result shape: a frozen options dataclass, a
factory that validates it (``create_tracker`` in :mod:`bodyplay.trackers`), and a
:class:`TrackResult` per frame set.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_NAMES, NUM_JOINTS
from bodyplay.capture.camera import Camera
from bodyplay.capture.frames import FrameSet
from bodyplay.errors import CaptureError, TimestampError

__all__ = ["JointState", "TrackerCapabilities", "TrackResult", "Tracker", "check_frame_set",
           "lost_result"]

JointState = Literal["tracked", "inferred", "lost"]


@dataclass(frozen=True)
class TrackerCapabilities:
    """What a tracker can see, so games can adapt (e.g. no legs from the color shirt)."""

    joints: tuple[str, ...] = JOINT_NAMES
    min_cameras: int = 1
    max_cameras: int = 1
    needs_calibration: bool = True

    @property
    def upper_body_only(self) -> bool:
        """True when the tracker reports no leg joints."""
        return "l_knee" not in self.joints


@dataclass(frozen=True, eq=False)
class TrackResult:
    """The pose a tracker estimated for one frame set.

    ``joints`` is (17, 3) world metres in JOINT_NAMES order, NaN where the joint is
    not reported; ``state`` gives each joint's state; ``confidence`` is 0..1 per joint;
    ``ms`` is the processing time; ``pose`` the tracker's pose vector when it has one.
    """

    frame: int
    t: float
    joints: NDArray[np.float64]
    state: tuple[JointState, ...]
    confidence: NDArray[np.float64]
    ms: float
    pose: NDArray[np.float64] | None = None
    extras: dict[str, object] = field(default_factory=dict)

    @property
    def found(self) -> bool:
        """Whether any joint is tracked or inferred."""
        return any(s != "lost" for s in self.state)

    def to_json(self) -> dict[str, object]:
        """The poses.jsonl record of this result (DESIGN.md), nulls for unreported joints."""
        joints: dict[str, list[float] | None] = {}
        for name, p, s in zip(JOINT_NAMES, self.joints, self.state, strict=True):
            joints[name] = None if s == "lost" or not np.all(np.isfinite(p)) else [
                round(float(v), 5) for v in p
            ]
        return {
            "frame": int(self.frame),
            "t": round(float(self.t), 6),
            "joints": joints,
            "state": dict(zip(JOINT_NAMES, self.state, strict=True)),
            "ms": round(float(self.ms), 3),
        }


def check_frame_set(frames: FrameSet, cameras: tuple[Camera, ...]) -> None:
    """Raise :class:`CaptureError` unless ``frames`` holds one (H, W, 3) uint8 RGB
    frame per calibrated camera, each of the size its calibration was made for, and
    :class:`TimestampError` unless its time is a finite number of seconds.

    A frame of another size would be read with the wrong intrinsics: the poses come
    out wrong (or the shirt is never found) with no other sign of why; a NaN time
    compares as neither before nor after any other, so the trackers' order checks
    could not see it.
    """
    if not math.isfinite(frames.t):
        raise TimestampError(
            f"frame set {frames.index} has the time {frames.t}; give every frame set its "
            "capture time in seconds (a finite number)"
        )
    if len(frames) != len(cameras):
        raise CaptureError(
            f"got {len(frames)} frames for {len(cameras)} cameras; the frame set "
            "must hold one frame per calibrated camera"
        )
    for frame, cam in zip(frames, cameras, strict=True):
        image = frame.image
        if (not isinstance(image, np.ndarray) or image.ndim != 3 or image.shape[2] != 3
                or image.dtype != np.uint8):
            what = (f"{image.shape} {image.dtype}" if isinstance(image, np.ndarray)
                    else type(image).__name__)
            raise CaptureError(
                f"frame {frames.index} of camera {cam.name!r} is {what}; trackers need "
                "(H, W, 3) uint8 RGB images (a gray one: cv2.cvtColor(image, "
                "cv2.COLOR_GRAY2RGB); floats in 0..1: (image * 255).astype(np.uint8))"
            )
        h, w = image.shape[:2]
        if (w, h) != (cam.width, cam.height):
            raise CaptureError(
                f"frame {frames.index} of camera {cam.name!r} is {w}x{h} but its "
                f"calibration is for {cam.width}x{cam.height}; capture at the calibrated "
                "size, or scale the calibration with Camera.with_size(width, height)"
            )


def lost_result(frame: int, t: float, ms: float = 0.0) -> TrackResult:
    """A result reporting every joint lost (no person in view)."""
    lost: JointState = "lost"
    return TrackResult(
        frame=frame,
        t=t,
        joints=np.full((NUM_JOINTS, 3), np.nan),
        state=(lost,) * NUM_JOINTS,
        confidence=np.zeros(NUM_JOINTS),
        ms=ms,
    )


@runtime_checkable
class Tracker(Protocol):
    """A pose tracker: turns synchronized frames from calibrated cameras into poses.

    Implementations are created by a factory from their options and cameras; they
    keep their temporal state between calls to :meth:`process` and must be fed frame
    sets with strictly increasing ``t``.
    """

    name: str
    capabilities: TrackerCapabilities
    cameras: tuple[Camera, ...]

    def process(self, frames: FrameSet) -> TrackResult:
        """Estimate the pose for one synchronized frame set."""
        ...

    def reset(self) -> None:
        """Forget temporal state (previous pose, learned illuminations, background)."""
        ...
