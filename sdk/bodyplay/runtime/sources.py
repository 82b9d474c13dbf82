"""What a session reads from: pose-level sources (no tracker) and frame sources (+ tracker).

A :class:`PoseSource` iterates :class:`PoseSample` objects: a pose that is already
known (a mocap clip, a recording, a scripted player), fed to the session without any
image processing, which makes gameplay tests fast. A :class:`FrameSource` iterates
:class:`~bodyplay.capture.frames.FrameSet` objects that the session hands to a
:class:`~bodyplay.trackers.base.Tracker`. Any object with the right ``__iter__``
qualifies; the classes here are the built-in pose sources.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.joints import JOINT_INDEX, NUM_JOINTS, UPPER_BODY
from bodyplay.capture.frames import FrameSet
from bodyplay.errors import ConfigError
from bodyplay.events.types import Event

__all__ = [
    "PoseSample",
    "PoseSource",
    "FrameSource",
    "ArrayPoseSource",
    "ClipPoseSource",
    "UPPER_BODY_ONLY",
    "state_from_joints",
]

UPPER_BODY_ONLY = "upper_body_only"
"""Capability name of sources that report no leg joints."""


@dataclass(frozen=True, eq=False)
class PoseSample:
    """One pose from a pose-level source.

    ``t`` capture time (s, strictly increasing), ``frame`` 0-based index, ``joints``
    (17, 3) world metres (NaN where lost), ``state`` per joint, ``confidence`` (17,)
    0..1. ``pose`` is the skeleton pose vector when the source has one (scripted
    players do; it lets them drive a synthetic camera). ``events`` are extra events a
    replay re-emits after the pose (e.g. recorded contacts).
    """

    t: float
    frame: int
    joints: NDArray[np.float64]
    state: tuple[str, ...]
    confidence: NDArray[np.float64]
    capabilities: tuple[str, ...] = ()
    pose: NDArray[np.float64] | None = None
    events: tuple[Event, ...] = ()


@runtime_checkable
class PoseSource(Protocol):
    """Iterates :class:`PoseSample` in order of strictly increasing ``t``."""

    def __iter__(self) -> Iterator[PoseSample]:
        """The samples, oldest first."""
        ...


@runtime_checkable
class FrameSource(Protocol):
    """Iterates synchronized :class:`FrameSet` objects for a tracker."""

    def __iter__(self) -> Iterator[FrameSet]:
        """The frame sets, oldest first."""
        ...


def state_from_joints(joints: NDArray[np.float64]) -> tuple[str, ...]:
    """``tracked`` for each finite joint, ``lost`` for each joint with a NaN."""
    ok = np.all(np.isfinite(joints), axis=-1)
    return tuple("tracked" if v else "lost" for v in ok.tolist())


def _mask_legs(joints: NDArray[np.float64]) -> NDArray[np.float64]:
    out = joints.copy()
    legs = [i for n, i in JOINT_INDEX.items() if n not in UPPER_BODY]
    out[..., legs, :] = np.nan
    return out


class ArrayPoseSource:
    """Poses from a (T, 17, 3) array with times (or a frame rate), e.g. from numpy code.

    ``upper_body_only`` reports the legs as lost, like the color-shirt tracker.
    Iterating again restarts from the first pose.
    """

    def __init__(
        self,
        joints: ArrayLike,
        times: ArrayLike | None = None,
        *,
        fps: float = 30.0,
        poses: ArrayLike | None = None,
        confidence: float = 1.0,
        upper_body_only: bool = False,
        capabilities: Sequence[str] = (),
    ) -> None:
        arr = np.asarray(joints, dtype=np.float64)
        if arr.ndim != 3 or arr.shape[1:] != (NUM_JOINTS, 3):
            raise ConfigError(f"joints must have shape (T, {NUM_JOINTS}, 3), got {arr.shape}")
        if times is None:
            if not fps > 0:
                raise ConfigError(f"fps must be positive, got {fps}")
            ts = np.arange(arr.shape[0], dtype=np.float64) / float(fps)
        else:
            ts = np.asarray(times, dtype=np.float64).reshape(-1)
            if ts.shape[0] != arr.shape[0]:
                raise ConfigError(f"{ts.shape[0]} times for {arr.shape[0]} poses")
        self.upper_body_only = bool(upper_body_only)
        self.joints = _mask_legs(arr) if upper_body_only else arr
        self.times = ts
        self.poses = None if poses is None else np.asarray(poses, dtype=np.float64)
        if self.poses is not None and self.poses.shape[0] != arr.shape[0]:
            raise ConfigError(f"{self.poses.shape[0]} pose vectors for {arr.shape[0]} poses")
        if not 0.0 <= confidence <= 1.0:
            raise ConfigError(f"confidence must be in 0..1, got {confidence}")
        self.confidence = float(confidence)
        caps = list(capabilities)
        if upper_body_only and UPPER_BODY_ONLY not in caps:
            caps.append(UPPER_BODY_ONLY)
        self.capabilities = tuple(caps)

    def __len__(self) -> int:
        return int(self.joints.shape[0])

    def __iter__(self) -> Iterator[PoseSample]:
        for i in range(self.joints.shape[0]):
            j = self.joints[i]
            state = state_from_joints(j)
            conf = np.where(np.all(np.isfinite(j), axis=1), self.confidence, 0.0)
            yield PoseSample(
                t=float(self.times[i]),
                frame=i,
                joints=j,
                state=state,
                confidence=conf,
                capabilities=self.capabilities,
                pose=None if self.poses is None else self.poses[i],
            )


class ClipPoseSource(ArrayPoseSource):
    """A mocap clip (``bodyplay.motion.MotionClip``, or a path / built-in clip name)
    fed to the session as poses, with no tracker: the fast path for gameplay tests.

    ``start`` shifts the clip's times (the first pose is at ``start`` seconds).
    """

    def __init__(
        self,
        clip: Any,
        *,
        start: float = 0.0,
        fps: float | None = None,
        upper_body_only: bool = False,
        capabilities: Sequence[str] = (),
    ) -> None:
        if isinstance(clip, str) or hasattr(clip, "__fspath__"):
            from bodyplay.motion import load_clip

            clip = load_clip(clip, fps=fps)
        self.clip = clip
        joints = np.asarray(clip.joints(), dtype=np.float64)
        times = np.asarray(clip.times, dtype=np.float64) + float(start)
        poses = getattr(clip, "poses", None)
        super().__init__(
            joints,
            times,
            poses=poses,
            upper_body_only=upper_body_only,
            capabilities=capabilities,
        )
