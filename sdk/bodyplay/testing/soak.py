"""Soak runs: a long session with everything attached, measured minute by minute.

:func:`run_soak` plays a mocap clip in a loop at a fixed frame rate through a
session with smoothing (``one_euro``), the built-in gestures, a physics world that
throws a ball at the player every two seconds (and removes it four seconds later, as
a game would) and a recorder writing every event to disk. The clock is a
``FixedClock``: simulated time, so 30 minutes run much faster than real time. A game
loop drains the pull queue once a second of simulated time. Each minute records the
resident memory, the median and 95th-percentile wall time of a frame and the events
so far; the result checks that nothing was lost: every emitted event reached the
subscriber that counts them, and the pull queue accounts for every one (drained,
dropped when full, or still queued).

``benchmarks/soak_bench.py`` runs 30 minutes; ``tests/integration/test_soak.py`` runs 2.
"""

from __future__ import annotations

import os
import resource
import tempfile
import time
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from bodyplay.errors import ConfigError
from bodyplay.runtime.clock import FixedClock
from bodyplay.runtime.sources import PoseSample

__all__ = ["LoopedClipSource", "SoakMinute", "SoakResult", "resident_mb", "run_soak"]


def resident_mb() -> float:
    """This process's resident memory now, in MB (Linux ``/proc``; else the peak)."""
    try:
        pages = int(Path("/proc/self/statm").read_text().split()[1])
        return pages * os.sysconf("SC_PAGE_SIZE") / 2**20
    except (OSError, ValueError, IndexError):
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


class LoopedClipSource:
    """A clip's poses played in a loop for ``seconds`` at ``fps`` (t = frame / fps)."""

    def __init__(self, clip: str, seconds: float, fps: float = 30.0) -> None:
        from bodyplay.motion import load_clip

        self.clip = load_clip(clip, fps=fps)
        self.joints: NDArray[np.float64] = np.asarray(self.clip.joints(), np.float64)
        self.fps = float(fps)
        self.frames = int(round(seconds * fps))
        self._state = ("tracked",) * self.joints.shape[1]
        self._conf = np.ones(self.joints.shape[1])

    def __iter__(self) -> Iterator[PoseSample]:
        n = len(self.joints)
        for i in range(self.frames):
            yield PoseSample(i / self.fps, i, self.joints[i % n], self._state, self._conf)


@dataclass(frozen=True)
class SoakMinute:
    """One minute of simulated time: memory at its end, wall time of its frames."""

    minute: int
    rss_mb: float
    ms_median: float
    ms_p95: float
    events: int


@dataclass(frozen=True)
class SoakResult:
    """What a soak run measured (see the module docstring)."""

    seconds: float
    fps: float
    frames: int
    wall_s: float
    minutes: tuple[SoakMinute, ...]
    emitted: int
    by_name: dict[str, int]
    delivered: int
    drained: int
    dropped: int
    queued: int
    recorded_lines: int
    recording_events: int
    balls_thrown: int
    frame_errors: int
    subscriber_errors: int
    ms: NDArray[np.float64] = field(repr=False)

    @property
    def rss_growth(self) -> float:
        """Resident memory at the end over that after the first minute, minus one."""
        return self.minutes[-1].rss_mb / self.minutes[0].rss_mb - 1.0

    @property
    def ms_drift(self) -> float:
        """Median frame time of the last minute over that of the second, minus one
        (the first minute warms caches and compiles)."""
        ref = self.minutes[1] if len(self.minutes) > 2 else self.minutes[0]
        return self.minutes[-1].ms_median / ref.ms_median - 1.0

    def lines(self) -> list[str]:
        """Human-readable report."""
        out = [f"{self.seconds / 60:.0f} simulated minutes at {self.fps:g} fps: "
               f"{self.frames} frames in {self.wall_s:.0f} s of wall time "
               f"({self.frames / self.wall_s:.0f} frames/s)"]
        out.append("minute  RSS MB  ms/frame median  p95  events so far")
        for m in self.minutes:
            out.append(f"{m.minute:6d}  {m.rss_mb:6.1f}  {m.ms_median:15.3f}  "
                       f"{m.ms_p95:5.3f}  {m.events}")
        out.append(f"RSS growth after the first minute: {100 * self.rss_growth:+.1f}%; "
                   f"median frame time, last minute vs second: {100 * self.ms_drift:+.1f}%")
        out.append(f"events: {self.emitted} emitted "
                   f"({', '.join(f'{k} {v}' for k, v in sorted(self.by_name.items()))}); "
                   f"{self.delivered} delivered to the counting subscriber; pull queue: "
                   f"{self.drained} drained, {self.dropped} dropped, {self.queued} queued")
        out.append(f"recording: {self.recorded_lines} lines, read back {self.recording_events} "
                   f"events; balls thrown {self.balls_thrown}; frame errors "
                   f"{self.frame_errors}, subscriber errors {self.subscriber_errors}")
        return out


def run_soak(seconds: float = 120.0, fps: float = 30.0, clip: str = "13_29",
             folder: str | Path | None = None, queue_size: int = 4096,
             drain_every: float = 1.0) -> SoakResult:
    """Run the soak session for ``seconds`` of simulated time (see the module docstring).

    The recording goes to ``folder`` (default: a temporary folder, deleted after).
    """
    if not seconds >= 60.0:
        raise ConfigError("a soak run needs at least one minute of simulated time")
    from bodyplay.physics import PhysicsOptions, attach_physics
    from bodyplay.record import RecorderOptions, read_recording, record_session
    from bodyplay.runtime.session import SessionOptions, create_session

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(folder) if folder is not None else Path(tmp)
        out.mkdir(parents=True, exist_ok=True)
        rec_path = out / "soak.jsonl"
        rec_path.unlink(missing_ok=True)
        source = LoopedClipSource(clip, seconds, fps)
        session = create_session(SessionOptions(queue_size=queue_size), source=source,
                                 filters=["one_euro"], gestures="builtin",
                                 clock=FixedClock(1.0 / fps))
        world = attach_physics(session, PhysicsOptions())
        recorder = record_session(session, rec_path, RecorderOptions(fsync="interval"))
        delivered = Counter[str]()
        for name in session.bus.names:
            session.bus.subscribe(name, lambda e: delivered.update([e.name]))
        thrown: list[tuple[float, str]] = []
        balls = 0
        per_frame = int(round(fps))
        ms = np.zeros(source.frames)
        minutes: list[SoakMinute] = []
        drained = 0
        wall0 = time.perf_counter()
        for i in range(source.frames):
            t = i / fps
            if i % (2 * per_frame) == 0:  # the game: a ball every 2 s, gone after 4 s
                side = -1.0 if (i // (2 * per_frame)) % 2 else 1.0
                ball = world.add_ball((3.0 * side, 1.3), (-7.0 * side, 2.0))
                thrown.append((t, ball.name))
                balls += 1
            while thrown and t - thrown[0][0] >= 4.0 and thrown[0][1] in world.objects:
                world.remove(thrown.pop(0)[1])
            s0 = time.perf_counter()
            session.step()
            ms[i] = 1000.0 * (time.perf_counter() - s0)
            if i % max(1, int(round(drain_every * fps))) == 0:
                drained += len(session.drain())
            if (i + 1) % (60 * per_frame) == 0:
                chunk = ms[i + 1 - 60 * per_frame : i + 1]
                minutes.append(SoakMinute((i + 1) // (60 * per_frame), resident_mb(),
                                          float(np.median(chunk)),
                                          float(np.percentile(chunk, 95)),
                                          sum(delivered.values())))
        wall = time.perf_counter() - wall0
        bus = session.bus
        world.close()  # ends the open contacts: their events are recorded too
        recorder.close()
        session.close()
        queued = len(bus._queue) if bus._queue is not None else 0
        rec = read_recording(rec_path)
        return SoakResult(
            seconds=float(seconds), fps=float(fps), frames=session.frames, wall_s=wall,
            minutes=tuple(minutes), emitted=bus._emitted, by_name=dict(delivered),
            delivered=sum(delivered.values()), drained=drained, dropped=bus.dropped,
            queued=queued, recorded_lines=recorder.lines, recording_events=len(rec.events),
            balls_thrown=balls,
            frame_errors=delivered["frame_error"],
            subscriber_errors=delivered["subscriber_error"], ms=ms,
        )
