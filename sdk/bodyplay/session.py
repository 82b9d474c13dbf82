"""Shortcut module: ``from bodyplay.session import Session, create_session``.

The implementation lives in :mod:`bodyplay.runtime`.
"""

from bodyplay.runtime.clock import Clock, FixedClock, ManualClock, SystemClock
from bodyplay.runtime.session import GestureRecognizer, Session, SessionOptions, create_session
from bodyplay.runtime.sources import ArrayPoseSource, ClipPoseSource, PoseSample, PoseSource

__all__ = [
    "ArrayPoseSource",
    "ClipPoseSource",
    "Clock",
    "FixedClock",
    "GestureRecognizer",
    "ManualClock",
    "PoseSample",
    "PoseSource",
    "Session",
    "SessionOptions",
    "SystemClock",
    "create_session",
]
