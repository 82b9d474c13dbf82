"""Specifications of the pygame bridge (headless, SDL dummy video driver)."""

from __future__ import annotations

import os

import numpy as np
import pytest

from bodyplay.errors import ConfigError, UnknownEventError
from bodyplay.events import EventBus, GestureEvent, PoseEvent

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
pygame = pytest.importorskip("pygame")


@pytest.fixture
def pg():  # type: ignore[no-untyped-def]
    pygame.display.init()
    pygame.event.clear()
    yield pygame
    pygame.display.quit()


def _gesture() -> GestureEvent:
    return GestureEvent(t=1.0, emitted_t=1.0, gesture="wave", phase="performed", progress=1.0,
                        started_t=0.5)


def test_bus_events_arrive_in_pygame_queue_as_custom_types_carrying_the_event(pg) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.events.pygame_bridge import PygameBridge

    bus = EventBus()
    bridge = PygameBridge(bus)
    g = _gesture()
    bus.emit(g)
    bus.emit(PoseEvent(t=1.0, emitted_t=1.0, frame=3, joints=np.zeros((17, 3)),
                       state=("tracked",) * 17, confidence=np.ones(17)))
    got = [e for e in pg.event.get() if bridge.name_of(e.type) is not None]
    assert [bridge.name_of(e.type) for e in got] == ["gesture", "pose"]
    assert got[0].event is g and got[0].name == "gesture"
    assert got[0].type == bridge.types["gesture"] != bridge.types["pose"]
    assert pg.USEREVENT <= got[0].type < pg.NUMEVENTS and bridge.posted == 2


def test_detached_bridge_posts_nothing(pg) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.events.pygame_bridge import PygameBridge

    bus = EventBus()
    with PygameBridge(bus, ["gesture"]) as bridge:
        pass
    bus.emit(_gesture())
    assert not [e for e in pg.event.get() if e.type == bridge.types["gesture"]]


def test_bridge_needs_pygame_initialised_and_known_names() -> None:
    from bodyplay.events.pygame_bridge import PygameBridge

    pygame.display.quit()
    with pytest.raises(ConfigError, match="pygame.init"):
        PygameBridge(EventBus())
    pygame.display.init()
    try:
        with pytest.raises(UnknownEventError):
            PygameBridge(EventBus(), ["jump"])
    finally:
        pygame.display.quit()
