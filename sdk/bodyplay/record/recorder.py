"""Writing recordings and event logs that survive the process being killed at any moment.

Each line is handed to the kernel with a single ``os.write`` on a file opened with
``O_APPEND``, so whatever was written before a crash (even SIGKILL) is in the file;
``fsync`` decides whether it also survives a power cut: ``"line"`` (every line,
slow), ``"interval"`` (at most every ``fsync_interval`` seconds, the default) or
``"never"``. Frames are written as image files (PNG or JPEG) *before* their record
line, so a line never names a missing image.
"""

from __future__ import annotations

import contextlib
import json
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import cv2

from bodyplay.capture.frames import FrameSet
from bodyplay.errors import CaptureError, ConfigError
from bodyplay.events.types import Event
from bodyplay.optiontypes import check_option_types
from bodyplay.record.format import FORMAT, VERSION, event_line

__all__ = ["RecorderOptions", "Recorder", "EventLogWriter", "record_session"]


@dataclass(frozen=True)
class RecorderOptions:
    """How a recorder writes: durability, which events, whether and how frames are kept.

    ``frames`` is ``"none"``, ``"png"`` or ``"jpeg"`` (files under ``<name>.frames/``);
    ``events`` limits the event names written (None: every registered event).
    """

    fsync: Literal["never", "line", "interval"] = "interval"
    fsync_interval: float = 1.0
    frames: Literal["none", "png", "jpeg"] = "none"
    jpeg_quality: int = 90
    events: tuple[str, ...] | None = None
    overwrite: bool = False

    def validate(self) -> RecorderOptions:
        """Return self or raise ConfigError naming the bad option."""
        if self.fsync not in ("never", "line", "interval"):
            raise ConfigError(f"fsync must be never, line or interval, got {self.fsync!r}")
        if not self.fsync_interval > 0:
            raise ConfigError(f"fsync_interval must be positive, got {self.fsync_interval}")
        if self.frames not in ("none", "png", "jpeg"):
            raise ConfigError(f"frames must be none, png or jpeg, got {self.frames!r}")
        if not 1 <= self.jpeg_quality <= 100:
            raise ConfigError(f"jpeg_quality must be 1..100, got {self.jpeg_quality}")
        return self

    def __post_init__(self) -> None:
        check_option_types(self)


class _LineFile:
    """An append-only file written one whole line per ``os.write``."""

    def __init__(self, path: Path, options: RecorderOptions) -> None:
        self.path = path
        self.options = options
        flags = os.O_WRONLY | os.O_CREAT | os.O_APPEND
        if not options.overwrite:
            flags |= os.O_EXCL
        else:
            flags |= os.O_TRUNC
        path.parent.mkdir(parents=True, exist_ok=True)
        try:
            self.fd: int | None = os.open(path, flags, 0o644)
        except FileExistsError:
            raise ConfigError(
                f"{path} exists; choose another name or pass overwrite=True (--force)"
            ) from None
        self._last_sync = time.monotonic()
        self.lines = 0
        self._bytes = os.fstat(self.fd).st_size
        self.failed: str | None = None

    def write(self, data: bytes) -> None:
        """Append one whole line; on a failed write (disk full) cut the file back to its
        last whole line and refuse every later write, so the file stays readable."""
        if self.fd is None:
            raise ConfigError(f"{self.path}: the recorder is closed")
        if self.failed is not None:
            raise CaptureError(f"{self.path}: recording stopped after a failed write "
                               f"({self.failed}); {self.lines} lines kept")
        view = memoryview(data)
        try:
            while view:
                n = os.write(self.fd, view)
                view = view[n:]
        except OSError as exc:
            self.failed = exc.strerror or repr(exc)
            with contextlib.suppress(OSError):
                os.ftruncate(self.fd, self._bytes)  # no half line at the end
            raise CaptureError(f"{self.path}: cannot write ({self.failed}); recording "
                               f"stopped, the {self.lines} lines so far are kept") from exc
        self._bytes += len(data)
        self.lines += 1
        pol = self.options.fsync
        if pol == "line":
            os.fsync(self.fd)
        elif pol == "interval":
            now = time.monotonic()
            if now - self._last_sync >= self.options.fsync_interval:
                os.fsync(self.fd)
                self._last_sync = now

    def close(self) -> None:
        if self.fd is not None:
            if self.options.fsync != "never":
                os.fsync(self.fd)
            os.close(self.fd)
            self.fd = None


class EventLogWriter:
    """Writes events as JSON lines (no header): what ``bodyplay events`` outputs.

    Subscribe it to a bus (``writer.attach(bus)``) or call it with events directly.
    """

    def __init__(
        self, path: str | Path, options: RecorderOptions | None = None
    ) -> None:
        self.options = (options or RecorderOptions(fsync="never")).validate()
        self._file = _LineFile(Path(path), self.options)

    @property
    def path(self) -> Path:
        """The file written."""
        return self._file.path

    @property
    def lines(self) -> int:
        """Lines written so far (header included)."""
        return self._file.lines

    def __call__(self, event: Event) -> None:
        """Append one event."""
        self._file.write(event_line(event))

    def attach(self, bus: Any, names: tuple[str, ...] | None = None) -> EventLogWriter:
        """Subscribe to ``names`` (default: ``options.events`` or every registered name)."""
        for n in names or self.options.events or bus.names:
            bus.subscribe(n, self)
        return self

    def close(self) -> None:
        """Flush and close the file."""
        self._file.close()

    def __enter__(self) -> EventLogWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class Recorder(EventLogWriter):
    """Writes a recording: a header line, then events and frame records as they come.

    ``header`` adds to the header line (``options``, ``cameras``, ``capabilities``,
    ``meta``). Use :func:`record_session` to record a session.
    """

    def __init__(
        self,
        path: str | Path,
        options: RecorderOptions | None = None,
        header: dict[str, Any] | None = None,
    ) -> None:
        super().__init__(path, options or RecorderOptions())
        head: dict[str, Any] = {
            "type": "header",
            "format": FORMAT,
            "version": VERSION,
            "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
            "options": {},
            "cameras": [],
            "capabilities": [],
            "meta": {},
        }
        head.update(header or {})
        self._file.write((json.dumps(head, separators=(",", ":")) + "\n").encode())
        self.frames_dir = self.path.with_name(self.path.stem + ".frames")

    def write_frames(self, frames: FrameSet) -> None:
        """Save each camera's image of a frame set, then append its frame record."""
        if self.options.frames == "none":
            return
        ext = ".png" if self.options.frames == "png" else ".jpg"
        params = [] if ext == ".png" else [cv2.IMWRITE_JPEG_QUALITY, self.options.jpeg_quality]
        files: dict[str, str] = {}
        for fr in frames:
            d = self.frames_dir / fr.camera
            d.mkdir(parents=True, exist_ok=True)
            f = d / f"{frames.index:06d}{ext}"
            if not cv2.imwrite(str(f), cv2.cvtColor(fr.image, cv2.COLOR_RGB2BGR), params):
                raise ConfigError(f"could not write frame image {f}")
            files[fr.camera] = str(f.relative_to(self.path.parent))
        rec = {"type": "frame", "frame": int(frames.index), "t": round(float(frames.t), 6),
               "files": files}
        self._file.write((json.dumps(rec, separators=(",", ":")) + "\n").encode())


def record_session(
    session: Any,
    path: str | Path,
    options: RecorderOptions | None = None,
    meta: dict[str, Any] | None = None,
) -> Recorder:
    """Start recording ``session`` to ``path``: its options, cameras and capabilities go
    in the header; its events (and frames, if asked) are appended as they happen."""
    rec = Recorder(
        path,
        options,
        header={
            "options": session.options.to_json(),
            "cameras": [c.to_dict() for c in session.cameras],
            "capabilities": list(session.capabilities),
            "meta": dict(meta or {}),
        },
    )
    rec.attach(session.bus)
    if rec.options.frames != "none":

        def on_item(item: object) -> None:
            if isinstance(item, FrameSet):
                rec.write_frames(item)

        session.add_frame_listener(on_item)
    return rec
