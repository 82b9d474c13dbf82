"""The typed events bodyplay emits: ``pose``, ``gesture``, ``contact``, ``tracking``.

Every event is a frozen dataclass with a class-level ``name`` (the name games
subscribe to) and explicit timestamps: ``t`` is the capture time of the frame it
derives from (seconds since the session's first frame), ``emitted_t`` the session
clock's time when it was emitted. Games may define their own event classes the same
way and register them on the bus.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX, JOINT_NAMES

__all__ = [
    "Event",
    "PoseEvent",
    "GestureEvent",
    "ContactEvent",
    "TrackingEvent",
    "GesturePhase",
    "ContactPhase",
    "BUILTIN_EVENTS",
]

GesturePhase = Literal["started", "performed", "canceled"]
ContactPhase = Literal["begin", "end"]


@dataclass(frozen=True, eq=False)
class Event:
    """Base of all events: a registered ``name`` and capture/emit timestamps."""

    name: ClassVar[str] = "event"
    t: float
    emitted_t: float

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict: ``type``, timestamps and every field (arrays as lists)."""
        out: dict[str, Any] = {"type": self.name}
        for f in fields(self):
            out[f.name] = _jsonable(getattr(self, f.name))
        return out


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return [_jsonable(v) for v in value.tolist()]
    if isinstance(value, float):
        return None if not np.isfinite(value) else round(value, 6)
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, np.generic):
        return _jsonable(value.item())
    return value


@dataclass(frozen=True, eq=False)
class PoseEvent(Event):
    """A body pose for one frame.

    ``joints`` is (17, 3) world metres in JOINT_NAMES order (NaN where ``state`` is
    ``lost``); ``confidence`` 0..1 per joint; ``capabilities`` names what the source
    can see (e.g. ``("upper_body_only",)``).
    """

    name: ClassVar[str] = "pose"
    frame: int
    joints: NDArray[np.float64]
    state: tuple[str, ...]
    confidence: NDArray[np.float64]
    capabilities: tuple[str, ...] = ()
    player: int = 0

    def joint(self, name: str) -> NDArray[np.float64]:
        """Position of one joint by name, e.g. ``event.joint("r_wrist")``."""
        return self.joints[JOINT_INDEX[name]]

    def is_tracked(self, name: str) -> bool:
        """Whether a joint was seen in this frame (not inferred or lost)."""
        return self.state[JOINT_INDEX[name]] == "tracked"

    def as_dict(self) -> dict[str, NDArray[np.float64]]:
        """Joint name to position."""
        return {n: self.joints[i] for i, n in enumerate(JOINT_NAMES)}


@dataclass(frozen=True, eq=False)
class GestureEvent(Event):
    """A gesture's phase change: ``started``, ``performed`` or ``canceled``.

    ``progress`` runs 0..1 through the gesture; ``started_t`` is when it began.
    """

    name: ClassVar[str] = "gesture"
    gesture: str
    phase: GesturePhase
    progress: float
    started_t: float
    player: int = 0


@dataclass(frozen=True, eq=False)
class ContactEvent(Event):
    """A body part touching a physics object; ``begin`` and ``end`` always come in pairs.

    ``point`` is the contact point in world metres, ``impulse`` the magnitude of the
    collision impulse (N s) at begin, 0 at end.
    """

    name: ClassVar[str] = "contact"
    part: str
    obj: str
    phase: ContactPhase
    point: tuple[float, ...] = field(default=(0.0, 0.0, 0.0))
    impulse: float = 0.0
    player: int = 0


@dataclass(frozen=True, eq=False)
class TrackingEvent(Event):
    """The person was found or lost by the tracker."""

    name: ClassVar[str] = "tracking"
    status: Literal["found", "lost"]
    frame: int = 0
    player: int = 0


BUILTIN_EVENTS: tuple[type[Event], ...] = (PoseEvent, GestureEvent, ContactEvent, TrackingEvent)
"""Event classes every bus registers at creation."""
