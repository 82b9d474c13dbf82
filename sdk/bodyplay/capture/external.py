"""Turn third-party recordings into bodyplay capture folders.

Pose2Sim (Qualisys ``Calib.qca.txt``, several synchronized videos) and Sports2D
(``Calib_*.toml``, one video) ship real footage with their own calibration formats.
:func:`import_capture` writes a standard capture folder (``cam0.mp4`` ... as
symbolic links or copies, plus ``calib.json``) so every tracker and ``bodyplay
track`` can read them like any other capture.
"""

from __future__ import annotations

import math
import os
import shutil
import tomllib
from collections.abc import Sequence
from pathlib import Path

import cv2
import numpy as np

from bodyplay.capture.calibration import read_qualisys_calib
from bodyplay.capture.camera import Camera, write_calib
from bodyplay.errors import CalibrationError, CaptureError, reading

__all__ = ["read_toml_calib", "scale_about_center", "import_capture"]


def read_toml_calib(path: str | Path, y_up: bool = True) -> list[Camera]:
    """Read a Pose2Sim / Sports2D TOML calibration (one table per camera).

    Each table holds ``size`` [w, h], ``matrix`` (K), ``distortions`` [k1, k2, p1,
    p2], ``rotation`` (a Rodrigues vector) and ``translation`` (metres), world to
    camera, OpenCV convention; the ``metadata`` table is skipped. Their world is Z
    up with the floor at Z = 0 (Sports2D puts its camera ``perspective_value`` metres
    from the origin at about eye height, looking level along -X); with ``y_up`` it
    is turned into bodyplay's Y-up world by (X, Y, Z) = (old y, old z, old x), the
    same axis swap as :func:`~bodyplay.capture.calibration.read_qualisys_calib`, so
    the floor is Y = 0.
    """
    with reading(path, CalibrationError, "TOML calibration"):
        return _read_toml_calib_unchecked(path, y_up)


def _read_toml_calib_unchecked(path: str | Path, y_up: bool = True) -> list[Camera]:
    """The unchecked reader behind :func:`read_toml_calib`."""
    # X_cam = R X_old + t and X_old = P^T X_new, so the camera's rotation becomes R P^T
    P = np.array([[0.0, 1, 0], [0, 0, 1], [1, 0, 0]]) if y_up else np.eye(3)
    p = Path(path)
    try:
        data = tomllib.loads(p.read_text())
    except FileNotFoundError:
        raise CalibrationError(f"{p}: no such calibration file") from None
    except tomllib.TOMLDecodeError as exc:
        raise CalibrationError(f"{p}: not valid TOML ({exc})") from None
    cams = []
    for key, table in data.items():
        if key == "metadata" or not isinstance(table, dict):
            continue
        try:
            w, h = (int(round(v)) for v in table["size"])
            R, _ = cv2.Rodrigues(np.asarray(table["rotation"], dtype=np.float64))
            cams.append(
                Camera(
                    str(table.get("name", key)),
                    w,
                    h,
                    np.asarray(table["matrix"], dtype=np.float64),
                    np.asarray(R, dtype=np.float64) @ P.T,
                    np.asarray(table["translation"], dtype=np.float64),
                    np.asarray(table.get("distortions", [0, 0, 0, 0]), dtype=np.float64),
                )
            )
        except (KeyError, TypeError, ValueError) as exc:
            raise CalibrationError(f"{p}: camera table [{key}] is incomplete ({exc})") from None
    if not cams:
        raise CalibrationError(f"{p}: no camera tables found")
    return cams


def scale_about_center(camera: Camera, width: int, height: int, scale: float) -> Camera:
    """The camera seen through a frame scaled by ``scale`` about the image centre and
    re-framed to ``width`` x ``height`` (how Pose2Sim's 1080-wide videos relate to their
    1088-wide calibration)."""
    K = camera.K.copy()
    K[0, 0] *= scale
    K[1, 1] *= scale
    K[0, 1] *= scale
    K[0, 2] = (K[0, 2] - camera.width / 2.0) * scale + width / 2.0
    K[1, 2] = (K[1, 2] - camera.height / 2.0) * scale + height / 2.0
    return Camera(camera.name, width, height, K, camera.R, camera.t, camera.dist)


def _video_size(path: Path) -> tuple[int, int]:
    cap = cv2.VideoCapture(str(path))
    try:
        if not cap.isOpened():
            raise CaptureError(f"{path}: cannot open the video")
        return int(cap.get(cv2.CAP_PROP_FRAME_WIDTH)), int(cap.get(cv2.CAP_PROP_FRAME_HEIGHT))
    finally:
        cap.release()


def _fit_to_video(camera: Camera, video: Path) -> Camera:
    w, h = _video_size(video)
    if (w, h) == (camera.width, camera.height):
        return camera
    s = w / camera.width
    if abs(h - camera.height) <= 1 or not math.isclose(h, camera.height * s, rel_tol=0.01):
        return scale_about_center(camera, w, h, s)
    return camera.with_size(w, h)


def _link(src: Path, dst: Path, copy: bool) -> None:
    if dst.exists() or dst.is_symlink():
        dst.unlink()
    if copy:
        shutil.copyfile(src, dst)
    else:
        os.symlink(src.resolve(), dst)


def import_capture(
    source: str | Path, out: str | Path, cameras: Sequence[str] | None = None, copy: bool = False
) -> Path:
    """Write a capture folder for a Pose2Sim project or a Sports2D demo folder.

    ``source`` is a folder holding ``calibration/Calib.qca.txt`` and ``videos/*.mp4``
    (Pose2Sim) or a ``Calib*.toml`` beside ``*.mp4`` (Sports2D). ``cameras`` picks
    videos by stem (e.g. ``["cam01", "cam02"]``); they become cam0, cam1, ... in that
    order. Videos are symlinked unless ``copy``.
    """
    src = Path(source)
    dst = Path(out)
    if not src.is_dir():
        raise CaptureError(f"{src}: not a folder; pass a Pose2Sim project or a Sports2D folder")
    qca = src / "calibration" / "Calib.qca.txt"
    if qca.is_file():
        calib = read_qualisys_calib(qca)
        videos = sorted((src / "videos").glob("*.mp4"))
        if len(videos) != len(calib):
            raise CaptureError(
                f"{src}: {len(videos)} videos but {len(calib)} cameras in {qca.name}; "
                "expected one video per calibrated camera, in the same order"
            )
        pairs = list(zip(videos, calib, strict=True))
    else:
        tomls = sorted(src.glob("Calib*.toml"))
        videos = sorted(src.glob("*.mp4"))
        if not tomls or not videos:
            raise CaptureError(
                f"{src}: found neither calibration/Calib.qca.txt (Pose2Sim) "
                "nor Calib*.toml with *.mp4 (Sports2D)"
            )
        calib = read_toml_calib(tomls[0])
        if len(calib) != len(videos):
            raise CaptureError(f"{src}: {len(videos)} videos but {len(calib)} cameras")
        pairs = list(zip(videos, calib, strict=True))
    if cameras:
        by_stem = {v.stem: (v, c) for v, c in pairs}
        unknown = [c for c in cameras if c not in by_stem]
        if unknown:
            raise CaptureError(f"unknown camera(s) {unknown}; available: {sorted(by_stem)}")
        pairs = [by_stem[c] for c in cameras]
    dst.mkdir(parents=True, exist_ok=True)
    out_cams = []
    for i, (video, cam) in enumerate(pairs):
        fitted = _fit_to_video(cam, video)
        out_cams.append(
            Camera(f"cam{i}", fitted.width, fitted.height, fitted.K, fitted.R, fitted.t,
                   fitted.dist)
        )
        _link(video, dst / f"cam{i}.mp4", copy)
    write_calib(dst / "calib.json", out_cams)
    return dst
