"""Writing a synthetic capture folder: videos or PNG frames, calib.json, truth.jsonl, meta.json.

The folder follows DESIGN.md's capture-folder contract, so every tool that reads a
real capture (``CaptureFolderSource``, ``bodyplay track``, ``bodyplay eval``) reads
it too. ``meta.json`` records every option, the clip, the span rendered and the
rig actually placed, so ``bodyplay synth --repeat META.json`` can redo the run; with
``format="png"`` the same seed gives the same bytes.
"""

from __future__ import annotations

import json
import platform
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

import bodyplay
from bodyplay.capture.camera import write_calib
from bodyplay.capture.jsonl import PoseJsonlWriter
from bodyplay.capture.video import VideoWriter
from bodyplay.errors import CaptureError, ConfigError
from bodyplay.synth.camera import SyntheticCamera, SynthFrame

__all__ = ["CaptureSummary", "write_capture", "read_meta"]

META_VERSION = 1


@dataclass(frozen=True)
class CaptureSummary:
    """What :func:`write_capture` wrote: folder, frame count, seconds of rendering."""

    folder: Path
    frames: int
    files: tuple[str, ...]


class _VideoSink:
    """One camera's mp4 (the shared :class:`VideoWriter`) or folder of numbered PNGs."""

    def __init__(self, folder: Path, name: str, fmt: str, fps: float):
        self.video: VideoWriter | None = None
        if fmt == "mp4":
            self.path = folder / f"{name}.mp4"
            self.video = VideoWriter(self.path, fps)
        else:
            self.path = folder / name
            self.path.mkdir(parents=True, exist_ok=True)

    def write(self, index: int, rgb: NDArray[np.uint8]) -> None:
        if self.video is not None:
            opening = self.video.frames == 0  # the encoder is opened on the first frame
            try:
                self.video.write(rgb)
            except CaptureError as exc:
                if not opening:
                    raise
                raise CaptureError(f"{exc}; try --format png") from None
        elif not cv2.imwrite(str(self.path / f"{index:06d}.png"),
                             np.ascontiguousarray(rgb[:, :, ::-1])):
            raise CaptureError(f"{self.path}: could not write frame {index}")

    def close(self) -> None:
        if self.video is not None:
            self.video.close()
            self.video = None


def write_capture(
    out: str | Path,
    camera: SyntheticCamera,
    frames: Iterable[SynthFrame],
    run: dict[str, Any] | None = None,
) -> CaptureSummary:
    """Render ``frames`` of ``camera`` into the capture folder ``out`` (created if needed).

    ``run`` holds what produced the frames (clip, start, seconds/frames ...); it is
    stored in meta.json beside the options and the rig.
    """
    folder = Path(out)
    if folder.exists() and not folder.is_dir():
        raise ConfigError(f"{folder}: exists and is not a folder; choose another --out")
    folder.mkdir(parents=True, exist_ok=True)
    o = camera.options
    sinks = [_VideoSink(folder, c.name, o.format, o.fps) for c in camera.cameras]
    count = 0
    try:
        with PoseJsonlWriter(folder / "truth.jsonl") as truth:
            for sf in frames:
                for sink, fr in zip(sinks, sf.frames, strict=True):
                    sink.write(sf.index, fr.image)
                truth.write(sf.truth_record())
                count += 1
    finally:
        for sink in sinks:
            sink.close()
    write_calib(folder / "calib.json", camera.cameras)
    meta = {
        "meta_version": META_VERSION,
        "generator": f"bodyplay {bodyplay.__version__} synth",
        "options": o.to_dict(),
        "run": dict(run or {}),
        "frames": count,
        "rig": {
            "distance_m": camera.rig.distance,
            "baseline_m": camera.rig.baseline if len(camera.cameras) > 1 else None,
            "target": camera.rig.target.tolist(),
        },
        "machine": {"python": platform.python_version(), "opencv": cv2.__version__,
                    "numpy": np.__version__},
    }
    (folder / "meta.json").write_text(json.dumps(meta, indent=2))
    files = [s.path.name for s in sinks] + ["calib.json", "truth.jsonl", "meta.json"]
    return CaptureSummary(folder, count, tuple(files))


def read_meta(path: str | Path) -> dict[str, Any]:
    """Read a synthetic capture's meta.json (a folder gets its meta.json)."""
    p = Path(path)
    if p.is_dir():
        p = p / "meta.json"
    try:
        data = json.loads(p.read_text())
    except FileNotFoundError:
        raise ConfigError(f"{p}: no meta.json; pass a folder written by `bodyplay synth`") from None
    except json.JSONDecodeError as exc:
        raise ConfigError(f"{p}: not valid JSON ({exc.msg} at line {exc.lineno})") from None
    if not isinstance(data, dict) or "options" not in data or "run" not in data:
        raise ConfigError(f"{p}: not a bodyplay synth meta.json (no options/run)")
    return data
