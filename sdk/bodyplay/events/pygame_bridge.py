"""Posting bus events into pygame's event queue, for games written around pygame's loop.

Each bodyplay event name gets its own pygame event type from
``pygame.event.custom_type()``; the posted pygame event carries the bodyplay event
as its ``event`` attribute and the name as ``name``::

    bridge = PygameBridge(session.bus)
    for ev in pygame.event.get():
        if ev.type == bridge.types["gesture"]:
            print(ev.event.gesture, ev.event.phase)

``pygame.event.post`` is thread-safe, so a session running in a worker thread may
feed the game's main loop through the bridge.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from bodyplay.errors import ConfigError
from bodyplay.events.bus import EventBus
from bodyplay.events.types import Event

__all__ = ["PygameBridge"]


class PygameBridge:
    """Subscribes to ``names`` on ``bus`` and posts each event into pygame's queue.

    pygame must be initialized (``pygame.init()`` or at least the display module) so
    that it has an event queue. ``types`` maps each name to its pygame event type.
    Posting failures (a full queue) are counted in ``failed`` rather than raised.
    """

    def __init__(
        self,
        bus: EventBus,
        names: Iterable[str] = ("pose", "gesture", "contact", "tracking"),
        *,
        pygame_module: Any = None,
    ) -> None:
        if pygame_module is None:
            import pygame as pygame_module
        self._pg = pygame_module
        if not self._pg.display.get_init():
            raise ConfigError(
                "pygame has no event queue yet; call pygame.init() before creating the "
                "PygameBridge (set SDL_VIDEODRIVER=dummy when running headless)"
            )
        self.bus = bus
        self.names = tuple(names)
        for n in self.names:
            bus.event_class(n)  # unknown names fail before any custom type is taken
        self.types: dict[str, int] = {n: self._pg.event.custom_type() for n in self.names}
        self.posted = 0
        self.failed = 0
        self._callbacks: dict[str, Any] = {}
        self.attach()

    def _poster(self, name: str) -> Any:
        etype = self.types[name]
        make = self._pg.event.Event
        post = self._pg.event.post

        def post_event(event: Event) -> None:
            if post(make(etype, event=event, name=name)):
                self.posted += 1
            else:
                self.failed += 1

        return post_event

    def attach(self) -> None:
        """Start posting (done at creation; use after :meth:`detach`)."""
        for n in self.names:
            if n not in self._callbacks:
                cb = self._poster(n)
                self._callbacks[n] = cb
                self.bus.subscribe(n, cb)

    def detach(self) -> None:
        """Stop posting events."""
        for n, cb in self._callbacks.items():
            self.bus.unsubscribe(n, cb)
        self._callbacks.clear()

    def name_of(self, pygame_type: int) -> str | None:
        """The bodyplay event name of a pygame event type, or None for other types."""
        for n, t in self.types.items():
            if t == pygame_type:
                return n
        return None

    def __enter__(self) -> PygameBridge:
        return self

    def __exit__(self, *exc: object) -> None:
        self.detach()
