"""A watchdog for live sources: a camera that stalls becomes an error, not a hang.

:class:`WatchedSource` reads another source in a daemon reader thread and hands its
items over a small queue. If no item arrives within ``timeout`` seconds,
``next()`` raises :class:`~bodyplay.errors.CaptureError` ("no frame for ... s") and
the session reports it as a ``frame_error`` (and ``tracking: lost``); reading goes
on, so frames that come back are delivered again. :func:`create_session` wraps
sources that declare ``live = True`` (webcams) when ``SessionOptions.frame_timeout``
is set. Recorded, scripted and synthetic sources are read in the session's thread as
before (a synthetic camera's GL context belongs to the thread that made it).
"""

from __future__ import annotations

import queue
import threading
from collections.abc import Iterator
from typing import Any

from bodyplay.errors import CaptureError, ConfigError

__all__ = ["WatchedSource"]

_END = object()


class WatchedSource:
    """``source`` read in a reader thread; a silence of ``timeout`` seconds raises
    CaptureError from ``next()`` (and reading continues). Other attributes
    (``cameras``, ``fps``, ...) are the wrapped source's."""

    def __init__(self, source: Any, timeout: float, queue_size: int = 2) -> None:
        if not timeout > 0:
            raise ConfigError(f"frame timeout must be positive, got {timeout}")
        self.source = source
        self.timeout = float(timeout)
        self._queue: queue.Queue[Any] = queue.Queue(maxsize=queue_size)
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()
        self._ended = False
        self.stalls = 0

    def __getattr__(self, name: str) -> Any:
        return getattr(self.source, name)

    def _read(self) -> None:
        it = iter(self.source)
        while not self._stop.is_set():
            try:
                item: Any = next(it)
            except StopIteration:
                item = _END
            except Exception as exc:  # handed over: the session reports it
                item = exc
            while not self._stop.is_set():
                try:
                    self._queue.put(item, timeout=0.1)
                    break
                except queue.Full:
                    continue
            if item is _END:
                return

    def __iter__(self) -> Iterator[Any]:
        return self

    def __next__(self) -> Any:
        if self._ended:
            raise StopIteration
        if self._thread is None:
            self._thread = threading.Thread(target=self._read, name="bodyplay-source",
                                            daemon=True)
            self._thread.start()
        try:
            item = self._queue.get(timeout=self.timeout)
        except queue.Empty:
            self.stalls += 1
            name = getattr(self.source, "camera_name", type(self.source).__name__)
            raise CaptureError(
                f"{name}: no frame for {self.timeout:.1f} s (the camera stalled or was "
                "unplugged); waiting for frames to come back"
            ) from None
        if item is _END:
            self._ended = True
            raise StopIteration
        if isinstance(item, BaseException):
            raise item
        return item

    def close(self) -> None:
        """Stop the reader thread (after its current read) and close the source."""
        self._stop.set()
        close = getattr(self.source, "close", None)
        if callable(close):
            close()
