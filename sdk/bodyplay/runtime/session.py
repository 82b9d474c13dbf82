"""The session: what a game creates to turn a source of frames or poses into events.

A :class:`Session` owns a source, an optional tracker, a chain of joint filters,
gesture recognizers, a clock and an :class:`~bodyplay.events.bus.EventBus`. Each
:meth:`Session.step` consumes one frame and emits, in this order: ``tracking``
(``found`` / ``lost``, on transitions only), ``pose`` (every frame, NaN joints when
nobody is seen), then ``gesture`` events from the recognizers. A frame that fails in
the source, the tracker, a filter or a recognizer is reported as a ``frame_error``
event plus a log line and skipped: one bad frame never ends a session.

Games either call :meth:`Session.run` / :meth:`Session.step` from their own loop,
or :meth:`Session.start` a worker thread and pull with :meth:`Session.latest_pose`
and :meth:`Session.drain`. Other systems (the physics bridge) subscribe to ``pose``
on ``session.bus`` and emit their own events (``contact``) on the same bus.
"""

from __future__ import annotations

import dataclasses
import logging
import sys
import threading
import time
import traceback
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import NUM_JOINTS
from bodyplay.capture.frames import FrameSet
from bodyplay.errors import CaptureError, ConfigError, SessionError
from bodyplay.events.bus import EventBus, FrameErrorEvent
from bodyplay.events.types import Event, PoseEvent, TrackingEvent
from bodyplay.filters.base import JointFilter
from bodyplay.optiontypes import check_option_types
from bodyplay.runtime.clock import Clock, SystemClock, TimestampGuard
from bodyplay.runtime.sources import UPPER_BODY_ONLY, PoseSample

__all__ = ["GestureRecognizer", "SessionOptions", "Session", "create_session"]

_log = logging.getLogger("bodyplay.session")


@runtime_checkable
class GestureRecognizer(Protocol):
    """Turns the filtered joints of each frame into gesture phase events.

    ``update(t, joints (17, 3), state)`` returns the :class:`GestureEvent` objects
    this frame produced (often none). A ``reset()`` method, if present, is called
    when the person is lost.
    """

    def update(self, t: float, joints: NDArray[np.float64], state: Sequence[str]) -> list[Any]:
        """Process one frame; return the gesture events it completes or changes."""
        ...


@dataclass(frozen=True)
class SessionOptions:
    """How a session behaves; validated by :func:`create_session`.

    ``player`` tags every event; ``lost_after`` is how many consecutive frames
    without any joint make a ``tracking: lost`` event; ``max_subscriber_failures``
    consecutive exceptions unsubscribe a callback; ``queue_size`` bounds the pull
    queue; ``max_source_errors`` consecutive source failures end the session with a
    CaptureError; ``realtime`` paces :meth:`Session.run` to the capture times (for
    recorded or scripted sources played to a live game); ``capabilities`` are added
    to every pose event. ``frame_timeout``: a live source (a webcam: ``live = True``)
    that delivers nothing for this many seconds is reported as a failed frame
    (``frame_error``, and ``tracking: lost``) instead of hanging the session (None: wait
    forever); ``source_timeout``: seconds of the session clock without a frame after
    which the session ends with a CaptureError (with ``max_source_errors``, whichever
    comes first).
    """

    player: int = 0
    lost_after: int = 3
    max_subscriber_failures: int = 3
    queue_size: int = 4096
    max_source_errors: int = 30
    realtime: bool = False
    reset_on_lost: bool = True
    capabilities: tuple[str, ...] = ()
    frame_timeout: float | None = 2.0
    source_timeout: float = 30.0

    def validate(self) -> SessionOptions:
        """Return self, or raise ConfigError naming the bad option."""
        for name, lo in (
            ("player", 0),
            ("lost_after", 1),
            ("max_subscriber_failures", 1),
            ("queue_size", 0),
            ("max_source_errors", 1),
        ):
            v = getattr(self, name)
            if not isinstance(v, int) or isinstance(v, bool) or v < lo:
                raise ConfigError(f"SessionOptions.{name} must be an integer >= {lo}, got {v!r}")
        ft = self.frame_timeout
        if ft is not None and not (isinstance(ft, int | float) and ft > 0):
            raise ConfigError(f"SessionOptions.frame_timeout must be positive or None, got {ft!r}")
        if not (isinstance(self.source_timeout, int | float) and self.source_timeout > 0):
            raise ConfigError("SessionOptions.source_timeout must be positive seconds, got "
                              f"{self.source_timeout!r}")
        if not all(isinstance(c, str) for c in self.capabilities):
            raise ConfigError("SessionOptions.capabilities must be a tuple of strings")
        return self

    def to_json(self) -> dict[str, Any]:
        """The options as a JSON-ready dict (recorded in recording headers)."""
        d = dataclasses.asdict(self)
        d["capabilities"] = list(self.capabilities)
        return d

    def __post_init__(self) -> None:
        check_option_types(self)


def _blocked_in(thread: threading.Thread) -> str:
    """Where ``thread`` is now: its innermost frame outside bodyplay's loop and threading."""
    frame = sys._current_frames().get(thread.ident or -1)
    if frame is None:
        return "an unknown place"
    skip = ("threading.py", "runtime/session.py", "events/bus.py", "runtime/watchdog.py")
    stack = [f for f in traceback.extract_stack(frame) if not f.filename.endswith(skip)]
    if not stack:
        return "bodyplay's own loop"
    f = stack[-1]  # the innermost
    return f"{f.name} ({f.filename}:{f.lineno})"


def _check_kind(obj: object, methods: Sequence[str], what: str) -> None:
    missing = [m for m in methods if not callable(getattr(obj, m, None))]
    if missing:
        raise ConfigError(f"{what} {obj!r} lacks method(s) {', '.join(missing)}")


class Session:
    """A running pipeline from a source to typed events; build it with :func:`create_session`.

    Attributes: ``bus`` (subscribe here), ``clock``, ``options``, ``source``,
    ``tracker`` (None for pose-level sources), ``filters``, ``gestures``,
    ``frames`` (frames consumed), ``errors`` (frames skipped), ``done``.
    """

    def __init__(
        self,
        options: SessionOptions,
        source: Any,
        tracker: Any = None,
        filters: Sequence[JointFilter] = (),
        gestures: Sequence[GestureRecognizer] = (),
        clock: Clock | None = None,
        bus: EventBus | None = None,
    ) -> None:
        self.options = options
        self.source = source
        self.tracker = tracker
        self.filters = tuple(filters)
        self.gestures = tuple(gestures)
        self.clock: Clock = clock if clock is not None else SystemClock()
        self._tick: Callable[[], float] | None = getattr(self.clock, "tick", None)
        self.bus = bus if bus is not None else EventBus(
            max_failures=options.max_subscriber_failures, queue_size=options.queue_size
        )
        caps = list(options.capabilities)
        tcaps = getattr(tracker, "capabilities", None)
        if tcaps is not None and getattr(tcaps, "upper_body_only", False):
            caps.append(UPPER_BODY_ONLY)
        caps.extend(getattr(source, "capabilities", ()) or ())
        self.capabilities: tuple[str, ...] = tuple(dict.fromkeys(caps))
        self.cameras: tuple[Any, ...] = tuple(
            getattr(source, "cameras", None) or getattr(tracker, "cameras", None) or ()
        )
        self.frames = 0
        self.errors = 0
        self.done = False
        self._iter: Iterator[Any] | None = None
        self._guard = TimestampGuard("frame")
        self._found = False
        self._lost_run = 0
        self._source_errors = 0
        self._failing_since: float | None = None
        self._last_t = float("nan")
        self._latest: PoseEvent | None = None
        self._frame_listeners: list[Callable[[Any], object]] = []
        self._lock = threading.RLock()
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()
        self._thread_error: BaseException | None = None
        self._pace_origin: tuple[float, float] | None = None

    @classmethod
    def from_options(cls, options: SessionOptions | None = None, **kwargs: Any) -> Session:
        """Same as :func:`create_session` (``source=`` is required)."""
        return create_session(options, **kwargs)

    # ---- conveniences for games ------------------------------------------------------
    def on(self, name: str) -> Callable[[Any], Any]:
        """Decorator subscribing to ``name`` on this session's bus."""
        return self.bus.on(name)

    def subscribe(self, name: str, callback: Callable[[Any], object]) -> Callable[[Any], object]:
        """Subscribe ``callback`` to ``name`` on this session's bus."""
        return self.bus.subscribe(name, callback)

    def emit(self, event: Event) -> None:
        """Emit an event on the session's bus (e.g. ``contact`` from a physics world)."""
        self.bus.emit(event)

    def now(self) -> float:
        """The session clock's time: what to put in ``emitted_t`` of events you emit."""
        return self.clock.now()

    def add_frame_listener(self, callback: Callable[[Any], object]) -> None:
        """Call ``callback(item)`` with each raw FrameSet / PoseSample read (recorders)."""
        self._frame_listeners.append(callback)

    def latest_pose(self) -> PoseEvent | None:
        """The most recent pose event (thread-safe; None before the first frame)."""
        return self._latest

    def drain(self, names: Sequence[str] | None = None) -> list[Event]:
        """Events emitted since the last drain (thread-safe pull mode)."""
        return self.bus.drain(names)

    # ---- processing ------------------------------------------------------------------
    def _report(self, frame: int, t: float, stage: str, exc: BaseException) -> None:
        self.errors += 1
        _log.warning("frame %d skipped: %s failed: %r", frame, stage, exc)
        self.bus.emit(
            FrameErrorEvent(
                t=t, emitted_t=self.clock.now(), frame=frame, stage=stage, error=repr(exc)
            )
        )

    def _next_item(self) -> Any:
        if self._iter is None:
            self._iter = iter(self.source)
        while True:
            try:
                item = next(self._iter)
            except StopIteration:
                return None
            except Exception as exc:
                self._source_failed(exc)
                continue
            self._source_errors = 0
            self._failing_since = None
            return item

    def _source_failed(self, exc: Exception) -> None:
        """Report a failed read (``frame_error``, ``tracking: lost``); end the session
        with a CaptureError once the failures last too long."""
        self._source_errors += 1
        now = self.clock.now()
        if self._failing_since is None:
            self._failing_since = now
        self._report(self.frames, self._last_t, "source", exc)
        if self._found:
            self._found = False
            self.bus.emit(TrackingEvent(t=self._last_t, emitted_t=now, status="lost",
                                        frame=self.frames, player=self.options.player))
            if self.options.reset_on_lost:
                self._reset_stages()
        silent = now - self._failing_since
        if (self._source_errors >= self.options.max_source_errors
                or silent >= self.options.source_timeout):
            raise CaptureError(
                f"the source failed {self._source_errors} times in a row, no frame for "
                f"{silent:.1f} s (limits: source_timeout={self.options.source_timeout} s, "
                f"max_source_errors={self.options.max_source_errors}; last: {exc}); "
                "check the camera or file it reads"
            ) from exc

    def step(self) -> PoseEvent | None:
        """Consume one frame and emit its events.

        Returns the pose event, or None when the frame was skipped or the source is
        exhausted (then ``done`` is True). Raises TimestampError if the source goes
        back in time.
        """
        with self._lock:
            if self.done:
                return None
            item = self._next_item()
            if item is None:
                self.done = True
                return None
            self.frames += 1
            try:
                for cb in self._frame_listeners:
                    cb(item)
                return self._process(item)
            finally:
                if self._tick is not None:  # a stepping clock reads t0 for the first frame
                    self._tick()

    def _process(self, item: Any) -> PoseEvent | None:
        extra: tuple[Event, ...] = ()
        if isinstance(item, PoseSample):
            self._guard.check(item.t, item.frame)
            t, frame = float(item.t), int(item.frame)
            joints = np.asarray(item.joints, dtype=np.float64)
            state = tuple(item.state)
            conf = np.asarray(item.confidence, dtype=np.float64)
            caps = self.capabilities if not item.capabilities else tuple(
                dict.fromkeys((*self.capabilities, *item.capabilities))
            )
            extra = item.events
        elif isinstance(item, FrameSet):
            self._guard.check(item.t, item.index)
            t, frame = float(item.t), int(item.index)
            if self.tracker is None:
                raise ConfigError(
                    "the source yields FrameSets but the session has no tracker; "
                    "pass tracker=... to create_session"
                )
            try:
                res = self.tracker.process(item)
            except Exception as exc:
                self._report(frame, t, "tracker", exc)
                return None
            joints = np.asarray(res.joints, dtype=np.float64)
            state = tuple(res.state)
            conf = np.asarray(res.confidence, dtype=np.float64)
            caps = self.capabilities
        else:
            raise ConfigError(
                f"source yielded {type(item).__name__}; expected PoseSample or FrameSet"
            )
        self._last_t = t
        if joints.shape != (NUM_JOINTS, 3) or len(state) != NUM_JOINTS:
            self._report(frame, t, "source", ValueError(f"joints of shape {joints.shape}"))
            return None
        for f in self.filters:
            try:
                joints = np.asarray(f.filter(t, joints, state), dtype=np.float64)
            except Exception as exc:
                self._report(frame, t, "filter", exc)
                return None
        now = self.clock.now()
        player = self.options.player
        found = any(s != "lost" for s in state)
        if found:
            self._lost_run = 0
            if not self._found:
                self._found = True
                self.bus.emit(TrackingEvent(t=t, emitted_t=now, status="found", frame=frame,
                                            player=player))
        pose = PoseEvent(
            t=t, emitted_t=now, frame=frame, joints=joints, state=state, confidence=conf,
            capabilities=caps, player=player,
        )
        self._latest = pose
        self.bus.emit(pose)
        for rec in self.gestures:
            try:
                events = rec.update(t, joints, state)
            except Exception as exc:
                self._report(frame, t, "gesture", exc)
                continue
            for ev in events or ():
                if ev.emitted_t != now or getattr(ev, "player", player) != player:
                    ev = dataclasses.replace(ev, emitted_t=now, player=player)
                self.bus.emit(ev)
        for ev in extra:
            self.bus.emit(dataclasses.replace(ev, emitted_t=now))
        if not found:
            self._lost_run += 1
            if self._found and self._lost_run >= self.options.lost_after:
                self._found = False
                self.bus.emit(TrackingEvent(t=t, emitted_t=now, status="lost", frame=frame,
                                            player=player))
                if self.options.reset_on_lost:
                    self._reset_stages()
        return pose

    def _reset_stages(self) -> None:
        for stage in (*self.filters, *self.gestures):
            reset = getattr(stage, "reset", None)
            if callable(reset):
                reset()

    def run(self, max_frames: int | None = None) -> int:
        """Process frames in the calling thread until the source ends, ``max_frames``
        have been consumed or :meth:`stop` is called; return the frames consumed."""
        if max_frames is not None and (not isinstance(max_frames, int | np.integer)
                                       or isinstance(max_frames, bool) or max_frames < 0):
            raise ConfigError(f"max_frames must be a whole number >= 0 (or None: until the "
                              f"source ends), got {max_frames!r}")
        start = self.frames
        while not self.done and not self._stop.is_set():
            if max_frames is not None and self.frames - start >= max_frames:
                break
            pose = self.step()
            if self.options.realtime and pose is not None:
                self._pace(pose.t)
        return self.frames - start

    def _pace(self, t: float) -> None:
        wall = time.perf_counter()
        if self._pace_origin is None:
            self._pace_origin = (wall, t)
            return
        delay = (t - self._pace_origin[1]) - (wall - self._pace_origin[0])
        if delay > 0:
            self._stop.wait(delay)

    # ---- worker thread ---------------------------------------------------------------
    def start(self, max_frames: int | None = None) -> None:
        """Run in a daemon worker thread; pull with :meth:`latest_pose` / :meth:`drain`."""
        if self._thread is not None and self._thread.is_alive():
            raise ConfigError("the session is already running; call stop() first")
        self._stop.clear()
        self._thread_error = None

        def work() -> None:
            try:
                self.run(max_frames)
            except BaseException as exc:  # surfaced by stop()/join()
                _log.error("session worker stopped: %r", exc)
                self._thread_error = exc

        self._thread = threading.Thread(target=work, name="bodyplay-session", daemon=True)
        self._thread.start()

    @property
    def running(self) -> bool:
        """Whether the worker thread is alive."""
        return self._thread is not None and self._thread.is_alive()

    def join(self, timeout: float | None = None) -> None:
        """Wait for the worker to finish on its own; re-raise the error that ended it."""
        if self._thread is not None:
            self._thread.join(timeout)
        self._raise_thread_error()

    def stop(self, timeout: float | None = 5.0) -> None:
        """Ask the worker to stop after its current frame, wait for it, and re-raise the
        error that ended it, if any."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout)
            if self._thread.is_alive():
                raise SessionError(
                    f"the session's worker did not stop within {timeout} s: it is blocked in "
                    f"{_blocked_in(self._thread)}; a subscriber or the source must return"
                )
        self._raise_thread_error()

    def _raise_thread_error(self) -> None:
        err, self._thread_error = self._thread_error, None
        if err is not None:
            raise err

    def close(self) -> None:
        """Stop the worker and close the source (if it has ``close``)."""
        try:
            self.stop()
        finally:
            close = getattr(self.source, "close", None)
            if callable(close):
                close()

    def __enter__(self) -> Session:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def create_session(
    options: SessionOptions | None = None,
    *,
    source: Any,
    tracker: Any = None,
    filters: Sequence[JointFilter | str] = (),
    gestures: GestureRecognizer | str | Sequence[GestureRecognizer | str] | None = "builtin",
    clock: Clock | None = None,
    bus: EventBus | None = None,
    plugins: Any = None,
) -> Session:
    """Validate ``options`` and build a :class:`Session`.

    ``source`` is a PoseSource (no tracker) or a FrameSource (with ``tracker``).
    Filters, recognizers and the tracker may be objects or plugin names, resolved
    through ``plugins`` (a :class:`~bodyplay.plugins.PluginRegistry`; one reading the
    installed entry points is made when needed). ``gestures`` defaults to the built-in
    gesture set (``"builtin"``, as ``bodyplay events`` does); pass ``None`` or ``()``
    for a session without gesture recognition. ``clock`` defaults to SystemClock.
    """
    opts = (options or SessionOptions()).validate()
    if not hasattr(source, "__iter__"):
        raise ConfigError(f"source {source!r} is not iterable (need a PoseSource or FrameSource)")

    def registry() -> Any:
        nonlocal plugins
        if plugins is None:
            from bodyplay.plugins import PluginRegistry

            plugins = PluginRegistry()
        return plugins

    if isinstance(tracker, str):
        tracker = registry().create(
            "trackers", tracker, cameras=tuple(getattr(source, "cameras", ()) or ())
        )
    if tracker is not None:
        _check_kind(tracker, ("process",), "tracker")
    flts: list[JointFilter] = []
    for f in filters:
        obj = registry().create("filters", f) if isinstance(f, str) else f
        _check_kind(obj, ("filter", "reset"), "filter")
        flts.append(obj)
    if gestures is None:
        gest_in: Sequence[Any] = ()
    elif isinstance(gestures, str) or not isinstance(gestures, Sequence):
        gest_in = (gestures,)
    else:
        gest_in = gestures
    recs: list[GestureRecognizer] = []
    for g in gest_in:
        obj = registry().create("gestures", g) if isinstance(g, str) else g
        _check_kind(obj, ("update",), "gesture recognizer")
        recs.append(obj)
    if clock is not None and not callable(getattr(clock, "now", None)):
        raise ConfigError(f"clock {clock!r} has no now() method")
    if getattr(source, "live", False) is True and opts.frame_timeout is not None:
        from bodyplay.runtime.watchdog import WatchedSource

        source = WatchedSource(source, opts.frame_timeout)
    return Session(opts, source, tracker, flts, recs, clock, bus)
