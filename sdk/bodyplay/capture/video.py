"""Writing RGB frames to a video file: the one place bodyplay creates video writers."""

from __future__ import annotations

from pathlib import Path
from types import TracebackType

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.errors import CaptureError

__all__ = ["VideoWriter"]

_FOURCC = {".mp4": "mp4v", ".avi": "MJPG", ".mkv": "mp4v"}


class VideoWriter:
    """Append RGB uint8 frames to an mp4 (or .avi/.mkv) file; use as a context manager.

    The size is taken from the first frame; later frames of another size are an error.
    The file is finalized on close, also when the ``with`` block raises, so that what
    was written is kept.
    """

    def __init__(self, path: str | Path, fps: float) -> None:
        self.path = Path(path)
        if self.path.suffix.lower() not in _FOURCC:
            raise CaptureError(
                f"{self.path}: unsupported video type; use one of {', '.join(_FOURCC)}"
            )
        if fps <= 0:
            raise CaptureError(f"video frame rate must be positive, got {fps}")
        if not self.path.parent.is_dir():
            raise CaptureError(f"{self.path.parent}: folder does not exist; create it first")
        self.fps = float(fps)
        self.frames = 0
        self._writer: cv2.VideoWriter | None = None
        self._size: tuple[int, int] | None = None

    def write(self, rgb: NDArray[np.uint8]) -> None:
        """Append one (H, W, 3) RGB frame."""
        if rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.dtype != np.uint8:
            raise CaptureError(f"frames must be (H, W, 3) uint8 RGB, got {rgb.shape} {rgb.dtype}")
        size = (int(rgb.shape[1]), int(rgb.shape[0]))
        if self._writer is None:
            fourcc = cv2.VideoWriter.fourcc(*_FOURCC[self.path.suffix.lower()])
            self._writer = cv2.VideoWriter(str(self.path), fourcc, self.fps, size)
            if not self._writer.isOpened():
                raise CaptureError(f"{self.path}: OpenCV cannot write this video file")
            self._size = size
        elif size != self._size:
            raise CaptureError(f"{self.path}: frame size {size} differs from {self._size}")
        self._writer.write(cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))  # faster than [..., ::-1]
        self.frames += 1

    def close(self) -> None:
        """Finalize the file (idempotent)."""
        if self._writer is not None:
            self._writer.release()
            self._writer = None

    def __enter__(self) -> VideoWriter:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()
