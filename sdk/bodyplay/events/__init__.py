"""Typed events, the event bus that delivers them, and the pygame bridge.

``PygameBridge`` is imported from :mod:`bodyplay.events.pygame_bridge` on demand so
that importing the events never imports pygame.
"""

from bodyplay.events.bus import EventBus, FrameErrorEvent, Subscriber, SubscriberErrorEvent
from bodyplay.events.types import (
    BUILTIN_EVENTS,
    ContactEvent,
    ContactPhase,
    Event,
    GestureEvent,
    GesturePhase,
    PoseEvent,
    TrackingEvent,
)

__all__ = [
    "BUILTIN_EVENTS",
    "ContactEvent",
    "ContactPhase",
    "Event",
    "EventBus",
    "FrameErrorEvent",
    "GestureEvent",
    "GesturePhase",
    "PoseEvent",
    "Subscriber",
    "SubscriberErrorEvent",
    "TrackingEvent",
]
