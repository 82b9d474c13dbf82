"""Scripted players and helpers for headless gameplay tests (see docs/concepts.md)."""

from bodyplay.testing.player import ScriptedPlayer, scripted_session
from bodyplay.testing.poses import GESTURE_MOTIONS, KEY_POSES, key_pose, resolve_pose
from bodyplay.testing.timeline import Segment, Timeline, slerp_poses

__all__ = [
    "GESTURE_MOTIONS",
    "KEY_POSES",
    "ScriptedPlayer",
    "Segment",
    "Timeline",
    "key_pose",
    "resolve_pose",
    "scripted_session",
    "slerp_poses",
]
