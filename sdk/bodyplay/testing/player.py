"""Scripted players: a timeline played as a pose source, for headless gameplay tests.

:class:`ScriptedPlayer` samples a :class:`~bodyplay.testing.timeline.Timeline` at a
fixed frame rate and yields :class:`~bodyplay.runtime.sources.PoseSample` objects
(with the pose vector, so the same player can later pose a synthetic actor for a
camera + tracker run). :func:`scripted_session` wires it into a session with a
:class:`~bodyplay.runtime.clock.FixedClock`, so a test sees the same events on every
machine.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from bodyplay.errors import ConfigError
from bodyplay.runtime.clock import FixedClock
from bodyplay.runtime.session import Session, SessionOptions, create_session
from bodyplay.runtime.sources import UPPER_BODY_ONLY, PoseSample, state_from_joints
from bodyplay.testing.timeline import Timeline

__all__ = ["ScriptedPlayer", "scripted_session"]

_LEGS = np.arange(11, 17)


class ScriptedPlayer:
    """A :class:`PoseSource` playing ``timeline`` at ``fps`` from ``start`` for
    ``duration`` seconds (default: to the timeline's end).

    ``noise`` adds Gaussian jitter (metres, seeded by ``seed``) to the joints, like
    a tracker's; ``upper_body_only`` reports the legs as lost (the color shirt).
    """

    def __init__(
        self,
        timeline: Timeline,
        fps: float = 30.0,
        *,
        start: float = 0.0,
        duration: float | None = None,
        noise: float = 0.0,
        seed: int = 0,
        upper_body_only: bool = False,
        confidence: float = 1.0,
    ) -> None:
        if not (np.isfinite(fps) and fps > 0):
            raise ConfigError(f"fps must be positive, got {fps}")
        if noise < 0:
            raise ConfigError(f"noise must be >= 0 metres, got {noise}")
        self.timeline = timeline
        self.fps = float(fps)
        self.start = float(start)
        self.duration = timeline.duration - start if duration is None else float(duration)
        if self.duration < 0:
            raise ConfigError(f"start {start} s is after the timeline's end")
        self.noise = float(noise)
        self.seed = int(seed)
        self.upper_body_only = bool(upper_body_only)
        self.confidence = float(confidence)
        self.capabilities: tuple[str, ...] = (UPPER_BODY_ONLY,) if upper_body_only else ()

    @property
    def times(self) -> NDArray[np.float64]:
        """Capture times of every sample: ``start + i / fps`` up to ``start + duration``."""
        n = int(np.floor(self.duration * self.fps + 1e-9)) + 1
        return self.start + np.arange(n) / self.fps

    def __len__(self) -> int:
        return int(self.times.shape[0])

    def poses(self) -> Iterator[tuple[float, NDArray[np.float64]]]:
        """``(t, pose vector)`` per frame: what a synthetic camera renders."""
        for t in self.times:
            yield float(t), self.timeline.pose_at(float(t))

    def __iter__(self) -> Iterator[PoseSample]:
        rng = np.random.default_rng(self.seed)
        sk = self.timeline.skeleton
        for i, (t, q) in enumerate(self.poses()):
            j = sk.joint_positions(q)
            if self.noise > 0:
                j = j + rng.normal(0.0, self.noise, size=j.shape)
            if self.upper_body_only:
                j = j.copy()
                j[_LEGS] = np.nan
            state = state_from_joints(j)
            conf = np.where(np.all(np.isfinite(j), axis=1), self.confidence, 0.0)
            yield PoseSample(t=t, frame=i, joints=j, state=state, confidence=conf,
                             capabilities=self.capabilities, pose=q)


def scripted_session(
    timeline: Timeline,
    fps: float = 30.0,
    *,
    options: SessionOptions | None = None,
    player: dict[str, Any] | None = None,
    **session_kwargs: Any,
) -> Session:
    """A headless session driven by ``timeline`` with a FixedClock at ``fps``.

    ``player`` passes options to :class:`ScriptedPlayer` (noise, seed, ...); the other
    keyword arguments go to :func:`~bodyplay.runtime.session.create_session`
    (filters, gestures, plugins).
    """
    source = ScriptedPlayer(timeline, fps, **(player or {}))
    session_kwargs.setdefault("clock", FixedClock(1.0 / fps))
    return create_session(options, source=source, **session_kwargs)
