"""What poses a virtual player: the :class:`PoseController` protocol and the scripted one.

A pose controller answers ``pose_at(t)``: the pose vector of its ``skeleton`` at
time ``t`` seconds, the vectors :meth:`bodyplay.testing.ScriptedPlayer.poses` yields
and :meth:`bodyplay.synth.SyntheticCamera.capture` renders. A game may steer a
controller between frames (closed loop), so sources ask it one frame at a time.
"""

from __future__ import annotations

import math
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.testing.timeline import Timeline

__all__ = ["PoseController", "TimelineController"]


@runtime_checkable
class PoseController(Protocol):
    """Anything that poses the actor skeleton over time.

    ``skeleton``: the skeleton the pose vectors are for (a virtual player source
    renders them on the actor, so use the actor's: ``load_actor(body).skeleton``).
    ``pose_at(t)``: the (pose_dim,) vector at ``t`` seconds; called with
    non-decreasing times by the sources.
    """

    skeleton: Skeleton

    def pose_at(self, t: float) -> NDArray[np.float64]:
        """The pose vector at time ``t`` seconds."""
        ...


class TimelineController:
    """A :class:`~bodyplay.testing.Timeline` as a pose controller (scripted gestures, clips).

    ``duration`` (default: the timeline's) is how long a source plays it; after it the
    timeline's last pose is held. ``frame_joints`` are joints sampled over the
    timeline at 10 Hz: what a camera frames.
    """

    def __init__(self, timeline: Timeline, *, duration: float | None = None) -> None:
        if not isinstance(timeline, Timeline):
            raise ConfigError(
                f"TimelineController wraps a bodyplay.testing.Timeline, got "
                f"{type(timeline).__name__}"
            )
        self.timeline = timeline
        self.skeleton = timeline.skeleton
        d = timeline.duration if duration is None else float(duration)
        if not (math.isfinite(d) and d >= 0):
            raise ConfigError(f"duration must be >= 0 seconds, got {duration}")
        self.duration = d

    def pose_at(self, t: float) -> NDArray[np.float64]:
        """The timeline's pose at ``t`` seconds."""
        return self.timeline.pose_at(t)

    def frame_joints(self) -> NDArray[np.float64]:
        """(T, 17, 3) joints over the timeline (10 Hz): the motion a camera must frame."""
        times = np.arange(0.0, max(self.duration, 0.0) + 1e-9, 0.1)
        return self.skeleton.joint_positions(self.timeline.poses(times))
