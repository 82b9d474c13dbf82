"""Replaying a recording as a pose source, so a game sees the same events every time.

Feed a :class:`ReplaySource` to a session together with :meth:`ReplaySource.clock`
(a :class:`~bodyplay.runtime.clock.FixedClock` stepping at the recording's frame
rate): capture times come from the file and emit times from the frame count, so two
replays produce byte-identical event logs whatever the machine.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from bodyplay.errors import CaptureError, reading
from bodyplay.events.types import Event
from bodyplay.record.format import Recording, read_recording
from bodyplay.runtime.clock import FixedClock
from bodyplay.runtime.sources import PoseSample

__all__ = ["ReplaySource"]


class ReplaySource:
    """Recorded poses as :class:`PoseSample` objects, in order.

    ``replay_events`` names recorded events to re-emit after the pose they followed
    (e.g. ``("contact",)`` when replaying without the physics world, or
    ``("gesture",)`` without a recognizer); ``pose`` and ``tracking`` events are always
    recomputed by the session. ``player`` keeps only that player's poses.
    """

    def __init__(
        self,
        recording: Recording | str | Path,
        *,
        replay_events: Sequence[str] = (),
        player: int | None = None,
    ) -> None:
        self.recording = (
            recording if isinstance(recording, Recording) else read_recording(recording)
        )
        self.replay_events = tuple(replay_events)
        self.player = player
        with reading(self.recording.path, CaptureError, "recording header"):
            caps = self.recording.header.get("capabilities", ())
            if not isinstance(caps, list | tuple) or not all(isinstance(c, str) for c in caps):
                raise CaptureError(f"{self.recording.path}: header capabilities must be a "
                                   "list of names")
            self.capabilities: tuple[str, ...] = tuple(caps)
            self.cameras = tuple(self.recording.cameras)

    def __len__(self) -> int:
        return len(self.recording.poses)

    def clock(self) -> FixedClock:
        """A FixedClock stepping at the recording's median frame interval."""
        return FixedClock(dt=1.0 / self.recording.fps)

    def __iter__(self) -> Iterator[PoseSample]:
        pending: PoseSample | None = None
        extra: list[Event] = []
        for ev in self.recording.events:
            if ev.name == "pose":
                if self.player is not None and getattr(ev, "player", 0) != self.player:
                    continue
                if pending is not None:
                    yield _with_events(pending, extra)
                    extra = []
                pending = PoseSample(
                    t=ev.t,
                    frame=int(getattr(ev, "frame", 0)),
                    joints=np.asarray(getattr(ev, "joints"), dtype=np.float64),  # noqa: B009
                    state=tuple(getattr(ev, "state")),  # noqa: B009
                    confidence=np.asarray(getattr(ev, "confidence"), dtype=np.float64),  # noqa: B009
                    capabilities=tuple(getattr(ev, "capabilities", ())),
                )
            elif pending is not None and ev.name in self.replay_events:
                extra.append(ev)
        if pending is not None:
            yield _with_events(pending, extra)


def _with_events(sample: PoseSample, events: list[Event]) -> PoseSample:
    if not events:
        return sample
    return PoseSample(
        sample.t, sample.frame, sample.joints, sample.state, sample.confidence,
        sample.capabilities, sample.pose, tuple(events),
    )
