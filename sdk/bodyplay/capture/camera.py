"""Pinhole camera models with OpenCV distortion, and the ``calib.json`` file format.

A :class:`Camera` maps world points (metres, Y up) to pixels with OpenCV's
convention: ``x_cam = R @ X + t``, then ``K`` and the distortion ``[k1, k2, p1, p2,
k3]``. ``calib.json`` (DESIGN.md) holds a list of cameras in exactly this form.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.errors import CalibrationError, reading
from bodyplay.files import atomic_write

__all__ = ["Camera", "read_calib", "write_calib", "look_at"]


def _as_matrix(value: ArrayLike, shape: tuple[int, ...], what: str) -> NDArray[np.float64]:
    arr = np.asarray(value, dtype=np.float64)
    if arr.shape != shape:
        raise CalibrationError(f"{what} must have shape {shape}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise CalibrationError(f"{what} contains NaN or infinite values")
    return arr


@dataclass(frozen=True, eq=False)
class Camera:
    """One calibrated camera: intrinsics ``K``, distortion, extrinsics ``R``, ``t``."""

    name: str
    width: int
    height: int
    K: NDArray[np.float64]
    R: NDArray[np.float64] = field(default_factory=lambda: np.eye(3))
    t: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    dist: NDArray[np.float64] = field(default_factory=lambda: np.zeros(5))

    def __post_init__(self) -> None:
        if self.width <= 0 or self.height <= 0:
            raise CalibrationError(f"camera {self.name!r}: image size must be positive")
        object.__setattr__(self, "K", _as_matrix(self.K, (3, 3), f"camera {self.name!r} K"))
        object.__setattr__(self, "R", _as_matrix(self.R, (3, 3), f"camera {self.name!r} R"))
        object.__setattr__(self, "t", _as_matrix(np.ravel(self.t), (3,), f"camera {self.name!r} t"))
        d = np.zeros(5)
        given = np.ravel(np.asarray(self.dist, dtype=np.float64))
        if given.size > 5:
            raise CalibrationError(f"camera {self.name!r}: dist has more than 5 values")
        d[: given.size] = given
        object.__setattr__(self, "dist", d)
        if abs(np.linalg.det(self.R) - 1.0) > 1e-3:
            raise CalibrationError(f"camera {self.name!r}: R is not a rotation matrix")

    # ---- construction ---------------------------------------------------------------
    @classmethod
    def from_fov(
        cls,
        name: str,
        width: int,
        height: int,
        hfov_deg: float,
        R: ArrayLike | None = None,
        t: ArrayLike | None = None,
    ) -> Camera:
        """A distortion-free camera with square pixels and a horizontal field of view."""
        f = 0.5 * width / math.tan(math.radians(hfov_deg) / 2.0)
        K = np.array([[f, 0.0, (width - 1) / 2.0], [0.0, f, (height - 1) / 2.0], [0, 0, 1.0]])
        return cls(
            name,
            width,
            height,
            K,
            np.eye(3) if R is None else np.asarray(R, float),
            np.zeros(3) if t is None else np.asarray(t, float),
        )

    def to_dict(self) -> dict[str, object]:
        """The camera in calib.json form."""
        return {
            "name": self.name,
            "width": int(self.width),
            "height": int(self.height),
            "K": self.K.tolist(),
            "dist": self.dist.tolist(),
            "R": self.R.tolist(),
            "t": self.t.tolist(),
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], where: str = "calib.json") -> Camera:
        """Read one camera entry of calib.json, naming missing keys in errors."""
        missing = [k for k in ("name", "width", "height", "K", "R", "t") if k not in data]
        if missing:
            raise CalibrationError(f"{where}: camera entry lacks {', '.join(missing)}")
        return cls(
            str(data["name"]),
            int(data["width"]),
            int(data["height"]),
            np.asarray(data["K"], dtype=float),
            np.asarray(data["R"], dtype=float),
            np.asarray(data["t"], dtype=float),
            np.asarray(data.get("dist", [0, 0, 0, 0, 0]), dtype=float),
        )

    # ---- geometry -------------------------------------------------------------------
    @property
    def center(self) -> NDArray[np.float64]:
        """The camera centre in world coordinates, ``-R^T t``."""
        return -self.R.T @ self.t

    @property
    def hfov_deg(self) -> float:
        """Horizontal field of view in degrees."""
        return math.degrees(2.0 * math.atan(0.5 * self.width / self.K[0, 0]))

    def world_to_camera(self, points: ArrayLike) -> NDArray[np.float64]:
        """(..., 3) world points to camera coordinates (Z forward, Y down)."""
        p = np.asarray(points, dtype=np.float64)
        return p @ self.R.T + self.t

    def project(self, points: ArrayLike, distort: bool = True) -> NDArray[np.float64]:
        """(..., 3) world points to (..., 2) pixel coordinates (NaN behind the camera)."""
        pc = self.world_to_camera(points)
        z = pc[..., 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            x = pc[..., 0] / z
            y = pc[..., 1] / z
        if distort and np.any(self.dist):
            k1, k2, p1, p2, k3 = self.dist
            r2 = x * x + y * y
            radial = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2
            xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
            yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
            x, y = xd, yd
        u = self.K[0, 0] * x + self.K[0, 1] * y + self.K[0, 2]
        v = self.K[1, 1] * y + self.K[1, 2]
        out = np.stack([u, v], axis=-1)
        out[z <= 1e-9] = np.nan
        return out

    def in_view(self, points: ArrayLike, margin: float = 0.0) -> NDArray[np.bool_]:
        """Whether world points project inside the image (with a pixel margin)."""
        uv = self.project(points)
        u, v = uv[..., 0], uv[..., 1]
        with np.errstate(invalid="ignore"):
            return (
                (u >= margin)
                & (v >= margin)
                & (u <= self.width - 1 - margin)
                & (v <= self.height - 1 - margin)
            )

    def undistort_maps(self) -> tuple[NDArray[np.float32], NDArray[np.float32]] | None:
        """``cv2.remap`` maps that take this camera's images to the ideal pinhole ``K``
        (the one :meth:`project` with ``distort=False`` uses); None without distortion.

        Trackers undistort each frame once, so that their pinhole models hold.
        """
        if not np.any(self.dist):
            return None
        m1, m2 = cv2.initUndistortRectifyMap(self.K, self.dist, None, self.K,
                                             (self.width, self.height), cv2.CV_32FC1)
        return np.asarray(m1, np.float32), np.asarray(m2, np.float32)

    def with_size(self, width: int, height: int) -> Camera:
        """The same camera with its image resampled to another size."""
        sx, sy = width / self.width, height / self.height
        K = self.K.copy()
        K[0] *= sx
        K[1] *= sy
        return Camera(self.name, width, height, K, self.R, self.t, self.dist)


def look_at(eye: ArrayLike, target: ArrayLike, up: ArrayLike = (0.0, 1.0, 0.0)) -> tuple[
    NDArray[np.float64], NDArray[np.float64]
]:
    """World-to-camera ``(R, t)`` for a camera at ``eye`` looking at ``target`` (OpenCV axes)."""
    eye = np.asarray(eye, dtype=float)
    forward = np.asarray(target, dtype=float) - eye
    n = np.linalg.norm(forward)
    if n < 1e-9:
        raise CalibrationError("look_at: eye and target coincide")
    z = forward / n
    x = np.cross(z, np.asarray(up, dtype=float))
    if np.linalg.norm(x) < 1e-9:
        raise CalibrationError("look_at: viewing direction is parallel to up")
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    R = np.stack([x, y, z])
    return R, -R @ eye


def read_calib(path: str | Path) -> list[Camera]:
    """Read ``calib.json``; errors name the file and what is wrong with it."""
    p = Path(path)
    if p.is_dir():
        p = p / "calib.json"
    if not p.exists():
        raise CalibrationError(
            f"{p}: no calibration file; run `bodyplay calibrate` or pass the capture folder"
        )
    with reading(p, CalibrationError, "calibration (calib.json)"):
        try:
            data = json.loads(p.read_text())
        except json.JSONDecodeError as exc:
            raise CalibrationError(
                f"{p}: not valid JSON ({exc.msg} at line {exc.lineno})"
            ) from None
        cams = data.get("cameras") if isinstance(data, dict) else None
        if not isinstance(cams, list) or not cams:
            raise CalibrationError(f'{p}: expected {{"cameras": [...]}} with at least one camera')
        return [Camera.from_dict(c, where=str(p)) for c in cams]


def write_calib(path: str | Path, cameras: Sequence[Camera]) -> Path:
    """Write cameras as ``calib.json`` (a folder gets ``calib.json`` inside it)."""
    p = Path(path)
    if p.is_dir():
        p = p / "calib.json"
    with atomic_write(p, "w") as fh:  # whole or not at all
        fh.write(json.dumps({"cameras": [c.to_dict() for c in cameras]}, indent=2))
    return p
