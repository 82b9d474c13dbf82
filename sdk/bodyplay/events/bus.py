"""The event bus a session owns: typed events delivered synchronously, or pulled in batches.

Games subscribe callbacks to event *names* (``"pose"``, ``"gesture"``, ...); every
name must be registered first (the built-in events are registered at creation), so a
typo fails at once with the list of known names instead of silently never firing,
as pyglet's ``EventDispatcher`` does. Delivery is synchronous, in subscription order,
on the thread that calls :meth:`EventBus.emit`.

A subscriber that raises is logged and reported as a :class:`SubscriberErrorEvent`;
the other subscribers still get the event, and after ``max_failures`` consecutive
failures the faulty subscriber is removed, so a broken callback cannot spam the log
forever or take the game down.

Pull mode: every emitted event is also appended to a bounded queue that
:meth:`EventBus.drain` empties, for game loops that prefer polling (and for a
session running in a worker thread). The queue drops the oldest events when full.

The emit path is kept lean (copy-on-write subscriber tuples, no locks, failure
bookkeeping only once something failed): ``benchmarks/bus_bench.py`` measures it.
"""

from __future__ import annotations

import logging
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any, ClassVar, TypeVar

from bodyplay.errors import ConfigError, UnknownEventError
from bodyplay.events.types import BUILTIN_EVENTS, Event

__all__ = ["EventBus", "Subscriber", "SubscriberErrorEvent", "FrameErrorEvent"]

_log = logging.getLogger("bodyplay.events")

Subscriber = Callable[[Any], object]
"""A callback taking one event; its return value is ignored."""

E = TypeVar("E", bound=type[Event])
F = TypeVar("F", bound=Callable[[Any], object])


@dataclass(frozen=True, eq=False)
class SubscriberErrorEvent(Event):
    """A subscriber raised while handling an event (``subscriber_error``).

    ``subscriber`` is the callback's qualified name, ``error`` the exception as text,
    ``failures`` how many times in a row it failed, ``unsubscribed`` whether the bus
    removed it because of this failure.
    """

    name: ClassVar[str] = "subscriber_error"
    event_name: str
    subscriber: str
    error: str
    failures: int
    unsubscribed: bool


@dataclass(frozen=True, eq=False)
class FrameErrorEvent(Event):
    """One frame could not be processed and was skipped (``frame_error``).

    ``stage`` says where it failed (``source``, ``tracker``, ``filter``, ``gesture``);
    the session carries on with the next frame.
    """

    name: ClassVar[str] = "frame_error"
    frame: int
    stage: str
    error: str


def _callback_name(cb: object) -> str:
    return str(getattr(cb, "__qualname__", None) or getattr(cb, "__name__", None) or repr(cb))


class EventBus:
    """Registry of event classes, their subscribers, and a bounded pull queue.

    ``events`` are registered at creation (default: the built-in events plus
    ``subscriber_error`` and ``frame_error``); ``max_failures`` consecutive exceptions
    unsubscribe a callback; ``queue_size`` bounds the pull queue (0 disables it).
    """

    def __init__(
        self,
        events: Iterable[type[Event]] = (*BUILTIN_EVENTS, SubscriberErrorEvent, FrameErrorEvent),
        *,
        max_failures: int = 3,
        queue_size: int = 4096,
    ) -> None:
        if max_failures < 1:
            raise ConfigError(f"max_failures must be at least 1, got {max_failures}")
        if queue_size < 0:
            raise ConfigError(f"queue_size must be 0 (no pull queue) or more, got {queue_size}")
        self.max_failures = int(max_failures)
        self._classes: dict[str, type[Event]] = {}
        self._subs: dict[str, tuple[Subscriber, ...]] = {}
        self._failures: dict[tuple[str, int], int] = {}
        self._queue: deque[Event] | None = deque(maxlen=queue_size) if queue_size else None
        self._emitted = 0
        self._drained = 0
        for cls in events:
            self.register(cls)

    # ---- registration ----------------------------------------------------------------
    def register(self, event_class: E) -> E:
        """Register an event class under its ``name`` (usable as a class decorator).

        Registering the same class twice is harmless; another class under a taken
        name is a :class:`ConfigError`.
        """
        name = getattr(event_class, "name", None)
        if not isinstance(name, str) or not name:
            raise ConfigError(f"{event_class!r} has no class-level string `name` to register")
        known = self._classes.get(name)
        if known is not None and known is not event_class:
            raise ConfigError(
                f"event name {name!r} is already registered to {known.__qualname__}; "
                "give the new event class another name"
            )
        self._classes[name] = event_class
        self._subs.setdefault(name, ())
        return event_class

    @property
    def names(self) -> tuple[str, ...]:
        """Registered event names, sorted."""
        return tuple(sorted(self._classes))

    def event_class(self, name: str) -> type[Event]:
        """The class registered under ``name``."""
        self._check(name)
        return self._classes[name]

    def _check(self, name: str) -> None:
        if name not in self._classes:
            raise UnknownEventError(
                f"unknown event {name!r}; registered events are {', '.join(self.names)} "
                "(register your own event class with bus.register)"
            )

    # ---- subscription ----------------------------------------------------------------
    def subscribe(self, name: str, callback: F) -> F:
        """Call ``callback(event)`` for every ``name`` event, after earlier subscribers."""
        self._check(name)
        if not callable(callback):
            raise ConfigError(f"subscriber for {name!r} must be callable, got {callback!r}")
        self._subs[name] = (*self._subs[name], callback)
        return callback

    def on(self, name: str) -> Callable[[F], F]:
        """Decorator form of :meth:`subscribe`: ``@bus.on("pose")``."""
        self._check(name)

        def decorator(callback: F) -> F:
            return self.subscribe(name, callback)

        return decorator

    def unsubscribe(self, name: str, callback: Subscriber) -> bool:
        """Remove one subscription of ``callback``; return whether it was subscribed."""
        self._check(name)
        subs = list(self._subs[name])
        for i, cb in enumerate(subs):
            if cb is callback or cb == callback:
                del subs[i]
                self._subs[name] = tuple(subs)
                self._failures.pop((name, id(callback)), None)
                return True
        return False

    def subscribers(self, name: str) -> tuple[Subscriber, ...]:
        """The callbacks subscribed to ``name``, in delivery order."""
        self._check(name)
        return self._subs[name]

    # ---- delivery --------------------------------------------------------------------
    def emit(self, event: Event) -> None:
        """Deliver ``event`` to its subscribers now, then queue it for :meth:`drain`."""
        name = event.name
        try:
            subs = self._subs[name]
        except KeyError:
            self._check(name)
            raise
        failed: list[tuple[Subscriber, BaseException]] | None = None
        for cb in subs:
            try:
                cb(event)
            except Exception as exc:
                if failed is None:
                    failed = []
                failed.append((cb, exc))
        if failed is not None or self._failures:
            self._account(name, subs, failed or [], event)
        if self._queue is not None:
            self._queue.append(event)
            self._emitted += 1

    def _account(
        self,
        name: str,
        subs: tuple[Subscriber, ...],
        failed: list[tuple[Subscriber, BaseException]],
        event: Event,
    ) -> None:
        failed_ids = {id(cb) for cb, _ in failed}
        for cb in subs:  # a success breaks the run of consecutive failures
            if id(cb) not in failed_ids:
                self._failures.pop((name, id(cb)), None)
        for cb, exc in failed:
            key = (name, id(cb))
            count = self._failures.get(key, 0) + 1
            self._failures[key] = count
            drop = count >= self.max_failures
            _log.error(
                "subscriber %s raised on %r event (%d in a row)%s: %r",
                _callback_name(cb),
                name,
                count,
                "; unsubscribed" if drop else "",
                exc,
                exc_info=exc,
            )
            if drop:
                self.unsubscribe(name, cb)
            if name != SubscriberErrorEvent.name:  # never report failures of the reporters
                self.emit(
                    SubscriberErrorEvent(
                        t=event.t,
                        emitted_t=event.emitted_t,
                        event_name=name,
                        subscriber=_callback_name(cb),
                        error=repr(exc),
                        failures=count,
                        unsubscribed=drop,
                    )
                )

    # ---- pull mode -------------------------------------------------------------------
    def drain(self, names: Iterable[str] | None = None) -> list[Event]:
        """Events emitted since the last drain, oldest first (all, or only ``names``).

        Safe to call from another thread than the one emitting. Events of other
        names are discarded when ``names`` is given.
        """
        if self._queue is None:
            return []
        wanted: set[str] | None = None
        if names is not None:
            wanted = set(names)
            for n in wanted:
                self._check(n)
        out: list[Event] = []
        pop = self._queue.popleft
        while True:
            try:
                ev = pop()
            except IndexError:
                break
            self._drained += 1
            if wanted is None or ev.name in wanted:
                out.append(ev)
        return out

    @property
    def dropped(self) -> int:
        """Events the full pull queue discarded since the bus was created."""
        if self._queue is None:
            return 0
        return max(0, self._emitted - self._drained - len(self._queue))
