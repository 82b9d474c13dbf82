"""The SDK runtime games touch: sessions, sources, clocks (see docs/concepts.md)."""

from bodyplay.runtime.clock import (
    Clock,
    FixedClock,
    ManualClock,
    SteppingClock,
    SystemClock,
    TimestampGuard,
)
from bodyplay.runtime.session import GestureRecognizer, Session, SessionOptions, create_session
from bodyplay.runtime.sources import (
    UPPER_BODY_ONLY,
    ArrayPoseSource,
    ClipPoseSource,
    FrameSource,
    PoseSample,
    PoseSource,
    state_from_joints,
)

__all__ = [
    "UPPER_BODY_ONLY",
    "ArrayPoseSource",
    "ClipPoseSource",
    "Clock",
    "FixedClock",
    "FrameSource",
    "GestureRecognizer",
    "ManualClock",
    "PoseSample",
    "PoseSource",
    "Session",
    "SessionOptions",
    "SteppingClock",
    "SystemClock",
    "TimestampGuard",
    "create_session",
    "state_from_joints",
]
