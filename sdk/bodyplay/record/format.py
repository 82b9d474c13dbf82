"""The recording file format: JSON lines, a header first, then events and frame records.

Line 1: ``{"type": "header", "format": "bodyplay-recording", "version": 1,
"options": {...}, "cameras": [calib.json camera entries], "capabilities": [...],
"meta": {...}}``. Every other line is either an event in :meth:`Event.to_json` form
(``{"type": "pose", "t": ..., "emitted_t": ..., ...}``) or a frame record
``{"type": "frame", "frame": 12, "t": 0.4, "files": {"cam0": "rec.frames/cam0/000012.png"}}``
(paths relative to the recording's folder). Lines are appended one ``write`` at a
time, so a file cut short by a crash loses at most its last, partial line, which
:func:`read_recording` ignores.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping
from dataclasses import MISSING, dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from bodyplay.capture.camera import Camera
from bodyplay.errors import CaptureError, reading
from bodyplay.events.bus import FrameErrorEvent, SubscriberErrorEvent
from bodyplay.events.types import BUILTIN_EVENTS, Event, PoseEvent

__all__ = [
    "FORMAT",
    "VERSION",
    "FrameRecord",
    "Recording",
    "event_from_json",
    "event_line",
    "read_recording",
]

FORMAT = "bodyplay-recording"
VERSION = 1

_DEFAULT_CLASSES: tuple[type[Event], ...] = (
    *BUILTIN_EVENTS,
    SubscriberErrorEvent,
    FrameErrorEvent,
)


def event_line(event: Event) -> bytes:
    """One event as a compact JSON line (UTF-8, ending in a newline)."""
    return (json.dumps(event.to_json(), separators=(",", ":")) + "\n").encode()


def _to_array(value: Any) -> NDArray[np.float64]:
    arr = np.array(value, dtype=object)
    arr[arr == None] = np.nan  # noqa: E711 - elementwise comparison with JSON nulls
    return arr.astype(np.float64)


def _check_pose(ev: PoseEvent) -> None:
    """ValueError unless the pose has (17, 3) finite-or-NaN joints and 17 known states."""
    joints = np.asarray(ev.joints)
    if joints.shape != (17, 3) or np.isinf(joints).any():
        raise ValueError(f"joints must be 17 [x, y, z] triples, got shape {joints.shape}")
    if len(ev.state) != 17 or not set(ev.state) <= {"tracked", "inferred", "lost"}:
        raise ValueError("state must list 17 of tracked / inferred / lost")
    if not isinstance(ev.t, int | float) or not math.isfinite(ev.t):
        raise ValueError(f"t must be a number, got {ev.t!r}")
    if np.asarray(ev.confidence).shape not in ((17,), (0,)):
        raise ValueError("confidence must hold 17 numbers")


def event_from_json(data: Mapping[str, Any], classes: Mapping[str, type[Event]]) -> Event:
    """Rebuild an event from its ``to_json`` dict: arrays for ``NDArray`` fields (nulls
    become NaN), tuples for ``tuple`` fields, missing timestamps as NaN."""
    name = data.get("type")
    cls = classes.get(str(name))
    if cls is None:
        raise KeyError(name)
    kwargs: dict[str, Any] = {}
    for f in fields(cls):
        if f.name not in data:
            if f.default is MISSING and f.default_factory is MISSING:
                raise ValueError(f"{name} event lacks field {f.name!r}")
            continue
        v = data[f.name]
        ann = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", "")
        if ann.startswith("NDArray"):
            v = _to_array(v)
        elif ann.startswith("tuple"):
            v = tuple(v) if v is not None else ()
        elif ann == "float" and v is None:
            v = float("nan")
        kwargs[f.name] = v
    return cls(**kwargs)


@dataclass(frozen=True)
class FrameRecord:
    """Where the images of one recorded frame set are: camera name to file path."""

    frame: int
    t: float
    files: dict[str, Path]


@dataclass(frozen=True, eq=False)
class Recording:
    """A recording read back: header, events in order, frame records.

    ``truncated`` says the last line was cut short (the process was killed while
    writing it) and was ignored; ``unknown`` keeps lines of event types this reader
    has no class for, as dicts.
    """

    path: Path
    header: dict[str, Any]
    events: tuple[Event, ...]
    frames: tuple[FrameRecord, ...]
    unknown: tuple[dict[str, Any], ...]
    truncated: bool

    @property
    def poses(self) -> tuple[PoseEvent, ...]:
        """The ``pose`` events, in order."""
        return tuple(e for e in self.events if isinstance(e, PoseEvent))

    def of(self, name: str) -> list[Event]:
        """The events named ``name``, in order."""
        return [e for e in self.events if e.name == name]

    @property
    def times(self) -> NDArray[np.float64]:
        """(T,) capture times of the poses."""
        return np.array([p.t for p in self.poses], dtype=np.float64)

    def joints(self) -> NDArray[np.float64]:
        """(T, 17, 3) joints of the poses (NaN where lost)."""
        poses = self.poses
        if not poses:
            return np.zeros((0, 17, 3))
        return np.stack([p.joints for p in poses])

    @property
    def cameras(self) -> list[Camera]:
        """The cameras from the header (empty for pose-level recordings)."""
        where = f"{self.path} header"
        return [Camera.from_dict(c, where=where) for c in self.header.get("cameras", [])]

    @property
    def fps(self) -> float:
        """Median frame rate of the poses (30 when there are fewer than two)."""
        t = self.times
        if t.size < 2:
            return 30.0
        return round(float(1.0 / np.median(np.diff(t))), 3)


def read_recording(
    path: str | Path, extra_events: Iterable[type[Event]] = ()
) -> Recording:
    """Read a recording; a partial last line is ignored (``truncated``).

    ``extra_events`` are a game's own event classes to rebuild as objects. Raises
    CaptureError naming the line if the file is not a recording or a complete line
    in the middle is corrupt.
    """
    with reading(path, CaptureError, "recording"):
        return _read_recording_unchecked(path, extra_events)


def _read_recording_unchecked(
    path: str | Path, extra_events: Iterable[type[Event]] = ()
) -> Recording:
    """The unchecked reader behind :func:`read_recording`."""
    p = Path(path)
    if p.is_dir():
        p = p / "recording.jsonl"
    if not p.exists():
        raise CaptureError(f"{p}: no such recording; record one with `bodyplay record`")
    classes = {c.name: c for c in (*_DEFAULT_CLASSES, *extra_events)}
    raw = p.read_bytes()
    lines = raw.split(b"\n")
    # Only the last piece can lack its newline; a complete file ends with b"".
    tail = lines.pop()
    truncated = bool(tail.strip())
    header: dict[str, Any] | None = None
    events: list[Event] = []
    frames: list[FrameRecord] = []
    unknown: list[dict[str, Any]] = []
    for n, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            d = json.loads(line)
        except json.JSONDecodeError as exc:
            raise CaptureError(
                f"{p}:{n}: corrupt line ({exc.msg}); the recording is damaged"
            ) from None
        except UnicodeDecodeError:
            raise CaptureError(f"{p}:{n}: corrupt line (not UTF-8); the recording is damaged"
                               ) from None
        if not isinstance(d, dict) or "type" not in d:
            raise CaptureError(f"{p}:{n}: expected a JSON object with a 'type'")
        if header is None:
            if d.get("type") != "header" or d.get("format") != FORMAT:
                raise CaptureError(f"{p}: not a bodyplay recording (no header line)")
            if int(d.get("version", 0)) > VERSION:
                raise CaptureError(
                    f"{p}: recording version {d.get('version')} is newer than this "
                    f"bodyplay reads ({VERSION}); upgrade bodyplay"
                )
            header = d
            continue
        if d["type"] == "frame":
            base = p.parent
            files = {str(k): base / str(v) for k, v in dict(d.get("files", {})).items()}
            frames.append(FrameRecord(int(d["frame"]), float(d["t"]), files))
            continue
        try:
            ev = event_from_json(d, classes)
            if isinstance(ev, PoseEvent):
                _check_pose(ev)
            events.append(ev)
        except KeyError:
            unknown.append(d)
        except (TypeError, ValueError) as exc:
            raise CaptureError(f"{p}:{n}: bad {d['type']} event: {exc}") from None
    if header is None:
        raise CaptureError(f"{p}: empty or not a bodyplay recording (no header line)")
    return Recording(p, header, tuple(events), tuple(frames), tuple(unknown), truncated)
