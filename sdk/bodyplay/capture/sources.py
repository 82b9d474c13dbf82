"""Frame sources: video files, image folders, capture folders and webcams.

Every source is an iterable of :class:`~bodyplay.capture.frames.FrameSet` (a single
camera yields frame sets of one frame), with explicit timestamps in seconds since the
first frame, images in RGB order, and the calibrated cameras when it knows them.
Sources are context managers; :func:`open_source` picks the right one for a path, a
capture folder or a webcam index, so trackers and apps accept all of them alike.
"""

from __future__ import annotations

import json
import math
import re
import time
import warnings
from collections.abc import Callable, Generator, Iterator
from pathlib import Path
from types import TracebackType
from typing import Any, Protocol, Self, runtime_checkable

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.capture.camera import Camera, read_calib
from bodyplay.capture.frames import Frame, FrameSet
from bodyplay.errors import CaptureError

__all__ = [
    "FrameSource",
    "VideoFileSource",
    "ImageFolderSource",
    "CaptureFolderSource",
    "WebcamSource",
    "open_source",
    "VIDEO_EXTENSIONS",
    "IMAGE_EXTENSIONS",
]

VIDEO_EXTENSIONS: tuple[str, ...] = (".mp4", ".avi", ".mkv", ".mov", ".webm", ".m4v")
"""File name endings treated as videos by :func:`open_source` and capture folders."""

IMAGE_EXTENSIONS: tuple[str, ...] = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")
"""File name endings treated as frames of an image folder."""


@runtime_checkable
class FrameSource(Protocol):
    """What every frame source offers: cameras, frame rate, frame sets, closing."""

    cameras: tuple[Camera, ...] | None
    fps: float

    def __iter__(self) -> Iterator[FrameSet]:
        """Yield synchronized frame sets in time order."""
        ...

    def close(self) -> None:
        """Release files and devices; iterating afterwards raises CaptureError."""
        ...

    def __enter__(self) -> FrameSource: ...

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None: ...


def _to_rgb(image: Any) -> NDArray[np.uint8]:
    """OpenCV BGR (or gray) to contiguous RGB uint8."""
    if image.ndim == 2:
        return np.ascontiguousarray(cv2.cvtColor(image, cv2.COLOR_GRAY2RGB))
    return np.ascontiguousarray(cv2.cvtColor(image, cv2.COLOR_BGR2RGB))


def _natural_key(path: Path) -> tuple[Any, ...]:
    """Sort key that orders ``2.png`` before ``10.png`` (and ``000002`` before ``000010``)."""
    parts = re.split(r"(\d+)", path.name)
    return tuple(int(p) if p.isdigit() else p for p in parts)


def _list_images(folder: Path) -> list[Path]:
    return sorted(
        (p for p in folder.iterdir() if p.is_file() and p.suffix.lower() in IMAGE_EXTENSIONS),
        key=_natural_key,
    )


def _check_camera_size(camera: Camera, width: int, height: int, where: str) -> None:
    if (camera.width, camera.height) != (width, height):
        raise CaptureError(
            f"{where}: frames are {width}x{height} but camera {camera.name!r} is calibrated "
            f"for {camera.width}x{camera.height}; recalibrate at this size or pass "
            f"camera.with_size({width}, {height})"
        )


class _SourceBase:
    """Context-manager plumbing shared by the sources."""

    cameras: tuple[Camera, ...] | None
    fps: float
    _closed: bool = False

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def close(self) -> None:
        """Release the source; further iteration raises CaptureError."""
        self._closed = True

    def _check_open(self) -> None:
        if self._closed:
            raise CaptureError(f"{type(self).__name__} is closed; open a new source to read again")


class _VideoReader:
    """One camera's frames from a video file (re-openable, BGR->RGB)."""

    def __init__(self, path: Path) -> None:
        if not path.exists():
            raise CaptureError(f"{path}: no such video file; check the path")
        if not path.is_file():
            raise CaptureError(f"{path}: expected a video file, found a folder")
        cap = cv2.VideoCapture(str(path))
        try:
            if not cap.isOpened():
                raise CaptureError(
                    f"{path}: OpenCV cannot open this video; convert it to H.264 .mp4 "
                    "(e.g. ffmpeg -i in.ext -c:v libx264 out.mp4)"
                )
            ok, first = cap.read()
            if not ok or first is None:
                raise CaptureError(f"{path}: the video has no readable frame; re-encode it")
            self.width = int(first.shape[1])
            self.height = int(first.shape[0])
            self.fps = float(cap.get(cv2.CAP_PROP_FPS) or 0.0)
            self.count = int(cap.get(cv2.CAP_PROP_FRAME_COUNT) or 0)
        finally:
            cap.release()
        self.path = path

    def frames(self, opened: list[Any]) -> Generator[NDArray[np.uint8], None, None]:
        """RGB images in order; the capture is registered in ``opened`` while in use."""
        cap = cv2.VideoCapture(str(self.path))
        opened.append(cap)
        try:
            while True:
                ok, image = cap.read()
                if not ok or image is None:
                    return
                yield _to_rgb(image)
        finally:
            cap.release()
            if cap in opened:
                opened.remove(cap)


class _FolderReader:
    """One camera's frames from a folder of numbered images."""

    def __init__(self, folder: Path) -> None:
        if not folder.exists():
            raise CaptureError(f"{folder}: no such image folder; check the path")
        if not folder.is_dir():
            raise CaptureError(f"{folder}: expected a folder of images (000000.png, ...)")
        self.files = _list_images(folder)
        if not self.files:
            raise CaptureError(
                f"{folder}: no images ({', '.join(IMAGE_EXTENSIONS)}); expected 000000.png, "
                "000001.png, ..."
            )
        first = self._read(self.files[0])
        self.width = int(first.shape[1])
        self.height = int(first.shape[0])
        self.count = len(self.files)
        self.folder = folder

    @staticmethod
    def _read(path: Path) -> NDArray[np.uint8]:
        image = cv2.imread(str(path), cv2.IMREAD_COLOR)
        if image is None:
            raise CaptureError(f"{path}: unreadable image; replace or delete it")
        return np.asarray(image, dtype=np.uint8)

    def frames(self, opened: list[Any]) -> Generator[NDArray[np.uint8], None, None]:
        """RGB images in name order; a frame of another size raises CaptureError."""
        for path in self.files:
            image = self._read(path)
            if (image.shape[1], image.shape[0]) != (self.width, self.height):
                raise CaptureError(
                    f"{path}: image is {image.shape[1]}x{image.shape[0]} but the folder's first "
                    f"frame is {self.width}x{self.height}; every frame must have one size"
                )
            yield _to_rgb(image)


class VideoFileSource(_SourceBase):
    """Frames of one video file, ``t = index / fps``.

    ``camera`` (optional) is the calibrated camera of the video; its size must match.
    ``fps`` overrides the frame rate stored in the file (needed when it stores none).
    Iterating again starts over from the first frame.
    """

    def __init__(
        self, path: str | Path, camera: Camera | None = None, fps: float | None = None
    ) -> None:
        self.path = Path(path)
        self._reader = _VideoReader(self.path)
        rate = float(fps) if fps is not None else self._reader.fps
        if not (rate > 0 and math.isfinite(rate)):
            raise CaptureError(f"{self.path}: the video stores no frame rate; pass fps=...")
        self.fps = rate
        if camera is not None:
            _check_camera_size(camera, self._reader.width, self._reader.height, str(self.path))
        self.camera_name = camera.name if camera is not None else "cam0"
        self.cameras = (camera,) if camera is not None else None
        self.size = (self._reader.width, self._reader.height)
        self.frame_count = self._reader.count
        self._opened: list[Any] = []

    def __iter__(self) -> Iterator[FrameSet]:
        self._check_open()
        for i, image in enumerate(self._reader.frames(self._opened)):
            t = i / self.fps
            yield FrameSet((Frame(image, t, i, self.camera_name),), t, i)

    def close(self) -> None:
        """Release the video file."""
        for cap in list(self._opened):
            cap.release()
        self._opened.clear()
        super().close()


class ImageFolderSource(_SourceBase):
    """Frames from a folder of numbered images (``000000.png`` ...) at a given rate.

    Files are taken in natural name order; ``t = index / fps``.
    """

    def __init__(self, folder: str | Path, fps: float, camera: Camera | None = None) -> None:
        if not (fps > 0 and math.isfinite(fps)):
            raise CaptureError(f"ImageFolderSource: fps must be positive, got {fps}")
        self.folder = Path(folder)
        self._reader = _FolderReader(self.folder)
        self.fps = float(fps)
        if camera is not None:
            _check_camera_size(camera, self._reader.width, self._reader.height, str(self.folder))
        self.camera_name = camera.name if camera is not None else "cam0"
        self.cameras = (camera,) if camera is not None else None
        self.size = (self._reader.width, self._reader.height)
        self.frame_count = self._reader.count

    def __iter__(self) -> Iterator[FrameSet]:
        self._check_open()
        for i, image in enumerate(self._reader.frames([])):
            t = i / self.fps
            yield FrameSet((Frame(image, t, i, self.camera_name),), t, i)


def _fps_from_truth(folder: Path) -> float | None:
    """The frame rate implied by ``truth.jsonl`` timestamps, when the file is there."""
    path = folder / "truth.jsonl"
    if not path.exists():
        return None
    frames: list[int] = []
    times: list[float] = []
    with path.open() as fh:
        for line in fh:
            try:
                rec = json.loads(line)
                frames.append(int(rec["frame"]))
                times.append(float(rec["t"]))
            except (ValueError, KeyError, TypeError):
                break
            if len(frames) >= 200:
                break
    if len(frames) < 2:
        return None
    df = np.diff(np.asarray(frames, float))
    dt = np.diff(np.asarray(times, float))
    ok = (df > 0) & (dt > 0)
    if not np.any(ok):
        return None
    return float(1.0 / np.median(dt[ok] / df[ok]))


class CaptureFolderSource(_SourceBase):
    """Synchronized frame sets from a capture folder (DESIGN.md).

    The folder holds ``calib.json`` and, per camera named there, ``<name>.mp4`` (or
    another video type) or a ``<name>/`` folder of numbered images. Every camera must
    have its frames and a calibration of the same size. If the cameras hold different
    numbers of frames, a warning is issued and iteration stops at the shortest.
    Frame sets list the frames in calib.json order. ``fps``: videos give their own;
    image folders take ``fps``, else the rate of ``truth.jsonl``, else 30.
    """

    def __init__(self, folder: str | Path, fps: float | None = None) -> None:
        self.folder = Path(folder)
        if not self.folder.is_dir():
            raise CaptureError(
                f"{self.folder}: no such capture folder (expected calib.json and cam0.mp4 or "
                "cam0/000000.png ...)"
            )
        if not (self.folder / "calib.json").exists():
            raise CaptureError(
                f"{self.folder}: capture folder lacks calib.json; run `bodyplay calibrate ... "
                f"--out {self.folder / 'calib.json'}`"
            )
        cameras = read_calib(self.folder / "calib.json")
        self._readers: list[_VideoReader | _FolderReader] = []
        rates: list[float] = []
        for cam in cameras:
            reader = self._reader_for(cam.name)
            _check_camera_size(cam, reader.width, reader.height, f"{self.folder}: {cam.name}")
            if isinstance(reader, _VideoReader) and reader.fps > 0:
                rates.append(reader.fps)
            self._readers.append(reader)
        self.cameras = tuple(cameras)
        self.fps = self._pick_fps(rates, fps)
        counts = [r.count for r in self._readers]
        self.frame_count = min(counts)
        if len(set(counts)) > 1:
            listed = ", ".join(f"{c.name}={n}" for c, n in zip(cameras, counts, strict=True))
            warnings.warn(
                f"{self.folder}: cameras hold different numbers of frames ({listed}); "
                f"reading the first {self.frame_count} of each",
                stacklevel=2,
            )
        self._opened: list[Any] = []

    def _reader_for(self, name: str) -> _VideoReader | _FolderReader:
        for ext in VIDEO_EXTENSIONS:
            path = self.folder / f"{name}{ext}"
            if path.is_file():
                return _VideoReader(path)
        sub = self.folder / name
        if sub.is_dir():
            return _FolderReader(sub)
        raise CaptureError(
            f"{self.folder}: calib.json names camera {name!r} but there is no {name}.mp4 nor "
            f"{name}/000000.png; add its frames or remove it from calib.json"
        )

    def _pick_fps(self, rates: list[float], fps: float | None) -> float:
        if fps is not None:
            if not (fps > 0 and math.isfinite(fps)):
                raise CaptureError(f"{self.folder}: fps must be positive, got {fps}")
            return float(fps)
        if rates:
            if max(rates) - min(rates) > 1e-3 * max(rates):
                raise CaptureError(
                    f"{self.folder}: videos have different frame rates {sorted(set(rates))}; "
                    "resample them to one rate"
                )
            return rates[0]
        return _fps_from_truth(self.folder) or 30.0

    def __iter__(self) -> Iterator[FrameSet]:
        self._check_open()
        assert self.cameras is not None
        streams = [r.frames(self._opened) for r in self._readers]
        names = [c.name for c in self.cameras]
        try:
            for i in range(self.frame_count):
                got = [next(s, None) for s in streams]
                images = [im for im in got if im is not None]
                if len(images) < len(got):
                    short = [n for n, im in zip(names, got, strict=True) if im is None]
                    warnings.warn(
                        f"{self.folder}: {', '.join(short)} ended at frame {i}, before the "
                        f"{self.frame_count} frames its header declares; stopping there",
                        stacklevel=2,
                    )
                    return
                t = i / self.fps
                yield FrameSet(
                    tuple(
                        Frame(im, t, i, n)
                        for im, n in zip(images, names, strict=True)
                    ),
                    t,
                    i,
                )
        finally:
            for s in streams:
                s.close()

    def close(self) -> None:
        """Release every video file."""
        for cap in list(self._opened):
            cap.release()
        self._opened.clear()
        super().close()


class WebcamSource(_SourceBase):
    """Live frames from a webcam, timestamped by a clock.

    ``t`` is ``clock() - clock()`` at the first frame (seconds; the default clock is
    :func:`time.monotonic`; tests inject their own). ``width``/``height``/``fps`` are
    requests to the driver; the size actually delivered is in :attr:`size` and must
    match ``camera`` when one is given. ``opener`` builds the capture object (default
    ``cv2.VideoCapture``), so a recorded or fake device can stand in for hardware.
    Iteration runs until the source is closed: a read that fails (the camera was
    unplugged) raises CaptureError from ``next()`` after trying to reopen the device,
    and the next ``next()`` reads again, so a session reports the gap and goes on when
    frames come back. The source is ``live``: a session watches it for stalls
    (``SessionOptions.frame_timeout``).
    """

    live = True

    def __init__(
        self,
        index: int = 0,
        width: int = 640,
        height: int = 480,
        fps: float = 30.0,
        *,
        camera: Camera | None = None,
        clock: Callable[[], float] = time.monotonic,
        opener: Callable[[int], Any] | None = None,
    ) -> None:
        self.index = int(index)
        self._clock = clock
        self._opener = opener or cv2.VideoCapture
        self._request = (float(width), float(height), float(fps))
        cap = self._opener(self.index)
        if cap is None or not cap.isOpened():
            if cap is not None:
                cap.release()
            raise CaptureError(
                f"cannot open webcam {self.index}: check that it is plugged in, not used by "
                "another program and that you may read it (Linux: /dev/video"
                f"{self.index}, group 'video'); or pass a video file instead"
            )
        cap.set(cv2.CAP_PROP_FRAME_WIDTH, float(width))
        cap.set(cv2.CAP_PROP_FRAME_HEIGHT, float(height))
        cap.set(cv2.CAP_PROP_FPS, float(fps))
        self._cap = cap
        got_w = int(cap.get(cv2.CAP_PROP_FRAME_WIDTH) or width)
        got_h = int(cap.get(cv2.CAP_PROP_FRAME_HEIGHT) or height)
        got_fps = float(cap.get(cv2.CAP_PROP_FPS) or 0.0)
        self.size = (got_w, got_h)
        self.fps = got_fps if got_fps > 0 else float(fps)
        if camera is not None:
            _check_camera_size(camera, got_w, got_h, f"webcam {self.index}")
        self.camera_name = camera.name if camera is not None else f"cam{self.index}"
        self.cameras = (camera,) if camera is not None else None

    def __iter__(self) -> Iterator[FrameSet]:
        self._check_open()
        return _WebcamFrames(self)

    def _reopen(self) -> None:
        """Release the device and open it again (after a failed read)."""
        self._cap.release()
        cap = self._opener(self.index)
        if cap is not None and cap.isOpened():
            w, h, fps = self._request
            cap.set(cv2.CAP_PROP_FRAME_WIDTH, w)
            cap.set(cv2.CAP_PROP_FRAME_HEIGHT, h)
            cap.set(cv2.CAP_PROP_FPS, fps)
            self._cap = cap

    def close(self) -> None:
        """Release the device."""
        self._cap.release()
        super().close()


class _WebcamFrames:
    """Iterator over a webcam's frames that survives failed reads (see WebcamSource)."""

    def __init__(self, cam: WebcamSource) -> None:
        self.cam = cam
        self.t0: float | None = None
        self.index = 0

    def __iter__(self) -> _WebcamFrames:
        return self

    def __next__(self) -> FrameSet:
        cam = self.cam
        if cam._closed:
            raise StopIteration
        ok, image = cam._cap.read()
        if not ok or image is None:
            if cam._closed:
                raise StopIteration
            cam._reopen()
            raise CaptureError(
                f"webcam {cam.index}: no frame (unplugged or in use?); trying again"
            )
        now = cam._clock()
        if self.t0 is None:
            self.t0 = now
        t = float(now - self.t0)
        i = self.index
        self.index += 1
        return FrameSet((Frame(_to_rgb(image), t, i, cam.camera_name),), t, i)


def open_source(
    spec: str | int | Path,
    *,
    fps: float | None = None,
    camera: Camera | None = None,
) -> FrameSource:
    """Open the source ``spec`` names: a capture folder, video, image folder or webcam.

    * an ``int`` (or a string of digits): the webcam with that index; ``"webcam"``
      is webcam 0 and ``"webcam:N"`` webcam N (a path of that name, if it exists,
      wins);
    * a folder with ``calib.json``: :class:`CaptureFolderSource`;
    * a folder of images: :class:`ImageFolderSource` at ``fps`` (default 30);
    * a video file: :class:`VideoFileSource`.
    """
    if isinstance(spec, int) or (isinstance(spec, str) and spec.strip().isdigit()):
        return WebcamSource(int(spec), fps=fps or 30.0, camera=camera)
    if isinstance(spec, str) and not Path(spec).exists():
        name, _, index = spec.strip().lower().partition(":")
        if name == "webcam":
            if index and not index.strip().isdigit():
                raise CaptureError(f"{spec!r}: the webcam's index must be a number, as in "
                                   "webcam:1")
            return WebcamSource(int(index or 0), fps=fps or 30.0, camera=camera)
    if not isinstance(spec, str | Path):
        raise CaptureError(f"cannot open a source from {spec!r}; pass a path or a webcam index")
    path = Path(spec)
    if not path.exists():
        raise CaptureError(
            f"{path}: no such file or folder; pass a capture folder, a video, an image folder "
            "or a webcam (its index, or webcam / webcam:N)"
        )
    if path.is_dir():
        if (path / "calib.json").exists():
            return CaptureFolderSource(path, fps=fps)
        if _list_images(path):
            return ImageFolderSource(path, fps or 30.0, camera=camera)
        if any((path / f"cam0{ext}").exists() for ext in VIDEO_EXTENSIONS) or (
            path / "cam0"
        ).is_dir():
            raise CaptureError(
                f"{path}: looks like a capture folder but has no calib.json; run "
                "`bodyplay calibrate` and write it there"
            )
        raise CaptureError(
            f"{path}: folder holds neither calib.json nor images; expected a capture folder "
            "(calib.json + cam0.mp4) or numbered images"
        )
    return VideoFileSource(path, camera=camera, fps=fps)
