"""Clocks that stamp events with their emit time, and the strictly-increasing-time guard.

A session reads its clock once per step for every event's ``emitted_t``. Live games
use :class:`SystemClock`; replays and scripted tests use :class:`FixedClock`, which
advances by a fixed ``dt`` per step, so two runs produce byte-identical event logs.
"""

from __future__ import annotations

import math
import time
from typing import Protocol, runtime_checkable

from bodyplay.errors import ConfigError, TimestampError

__all__ = ["Clock", "SteppingClock", "SystemClock", "FixedClock", "ManualClock", "TimestampGuard"]


@runtime_checkable
class Clock(Protocol):
    """Anything with ``now() -> float`` seconds; the session's source of ``emitted_t``."""

    def now(self) -> float:
        """The current time in seconds."""
        ...


@runtime_checkable
class SteppingClock(Clock, Protocol):
    """A clock the session advances once per processed frame by calling ``tick()``."""

    def tick(self) -> float:
        """Advance one step and return the new time."""
        ...


class SystemClock:
    """Wall-clock seconds since the clock was created (monotonic, ``time.perf_counter``)."""

    def __init__(self) -> None:
        self._t0 = time.perf_counter()

    def now(self) -> float:
        """Seconds since creation."""
        return time.perf_counter() - self._t0


class FixedClock:
    """A deterministic clock: ``t0`` at first, plus ``dt`` for every :meth:`tick`.

    The session ticks it once per frame, so event ``emitted_t`` values depend only on
    the frame count, never on how fast the machine is.
    """

    def __init__(self, dt: float = 1.0 / 30.0, t0: float = 0.0) -> None:
        if not (math.isfinite(dt) and dt > 0):
            raise ConfigError(f"FixedClock dt must be a positive number of seconds, got {dt}")
        if not math.isfinite(t0):
            raise ConfigError(f"FixedClock t0 must be finite, got {t0}")
        self.dt = float(dt)
        self.t0 = float(t0)
        self.steps = 0

    def now(self) -> float:
        """``t0 + steps * dt`` (computed, not accumulated, so no rounding drift)."""
        return self.t0 + self.steps * self.dt

    def tick(self) -> float:
        """Advance by ``dt``; return the new time."""
        self.steps += 1
        return self.now()


class ManualClock:
    """A clock that only moves when told to (``advance`` / ``set``): for unit tests."""

    def __init__(self, t: float = 0.0) -> None:
        self._t = float(t)

    def now(self) -> float:
        """The time last set."""
        return self._t

    def advance(self, dt: float) -> float:
        """Move forward by ``dt`` >= 0 seconds; return the new time."""
        if dt < 0:
            raise TimestampError(f"ManualClock cannot go backwards (advance by {dt})")
        self._t += float(dt)
        return self._t

    def set(self, t: float) -> None:
        """Jump to ``t`` (not earlier than now)."""
        if t < self._t:
            raise TimestampError(f"ManualClock cannot go back from {self._t} to {t}")
        self._t = float(t)


class TimestampGuard:
    """Checks that capture times strictly increase; ``what`` names them in errors."""

    def __init__(self, what: str = "frame") -> None:
        self.what = what
        self.last: float | None = None
        self.last_index: int | None = None

    def check(self, t: float, index: int | None = None) -> None:
        """Accept ``t`` or raise :class:`TimestampError` saying which item was out of order."""
        if not math.isfinite(t):
            raise TimestampError(f"{self.what} {index}: time must be finite seconds, got {t}")
        if self.last is not None and t <= self.last:
            raise TimestampError(
                f"{self.what} {index} has t = {t:.6f} s, not after the previous "
                f"{self.what} {self.last_index} at t = {self.last:.6f} s; sources must "
                "deliver strictly increasing capture times"
            )
        self.last = float(t)
        self.last_index = index

    def reset(self) -> None:
        """Forget the previous time (e.g. when a source restarts)."""
        self.last = None
        self.last_index = None
