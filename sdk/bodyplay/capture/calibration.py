"""Camera calibration from checkerboard photos, and reading Qualisys calibrations.

Intrinsics: Zhang's method (``cv2.findChessboardCorners`` + ``cornerSubPix``, falling
back to ``findChessboardCornersSB``, then ``cv2.calibrateCamera``), dropping views
whose reprojection error is far above the others (a mis-detected board) and fixing
k3 = 0 by default, which the few views of a quick calibration cannot pin down.

Extrinsics: one board seen by every camera (a *reference* image per camera, taken
with the board unmoved) defines the world (metres, Y up, floor at Y = 0):

* ``floor``: the board lies flat on the floor. Y is the board normal pointing
  towards the cameras, X the board edge direction closest to the first camera's
  image right, Z = X x Y (towards the first camera); origin at the board centre.
* ``wall``: the board hangs vertically facing the cameras. Z is the board normal
  towards the cameras, Y the board edge closest to the first camera's image up,
  X = Y x Z; origin on the floor below the board centre, given its height.
* ``none``: intrinsics only; every camera keeps R = I, t = 0.

Corner order is made the same in every camera: the board's axes are chosen
right-handed with the normal pointing away from the camera and the black outer
square at the origin, which needs a board whose inner-corner counts have
different parity (e.g. 9x6 or 7x4); a symmetric board warns.
"""

from __future__ import annotations

import math
import warnings
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.capture.camera import Camera
from bodyplay.errors import CalibrationError, ConfigError, reading

__all__ = [
    "Board",
    "BoardPose",
    "IntrinsicsResult",
    "RigCalibration",
    "find_board_corners",
    "calibrate_intrinsics",
    "board_pose_in_camera",
    "calibrate_rig",
    "read_qualisys_calib",
    "rig_geometry",
]

BoardPose = Literal["floor", "wall", "none"]
ImageInput = str | Path | NDArray[np.uint8]


@dataclass(frozen=True)
class Board:
    """A checkerboard: ``cols`` x ``rows`` *inner* corners, ``square`` edge in metres."""

    cols: int
    rows: int
    square: float

    def __post_init__(self) -> None:
        if self.cols < 2 or self.rows < 2:
            raise ConfigError(
                f"board needs at least 2x2 inner corners, got {self.cols}x{self.rows}"
            )
        if self.cols == self.rows:
            raise ConfigError("board must have different inner-corner counts per side (e.g. 9x6)")
        if not (self.square > 0 and math.isfinite(self.square)):
            raise ConfigError(f"board square size must be positive metres, got {self.square}")
        if self.square > 1.0:
            raise ConfigError(
                f"board square of {self.square} m is implausible; --square is in metres "
                "(e.g. 0.025 for 25 mm)"
            )

    @classmethod
    def parse(cls, spec: str, square: float) -> Board:
        """Parse ``"COLSxROWS"`` (inner corners), e.g. ``"9x6"``."""
        try:
            cols, rows = (int(v) for v in spec.lower().split("x"))
        except ValueError:
            raise ConfigError(
                f"board {spec!r}: expected COLSxROWS inner corners, e.g. 9x6"
            ) from None
        return cls(cols, rows, float(square))

    @property
    def size(self) -> tuple[int, int]:
        """OpenCV's pattern size ``(cols, rows)``."""
        return (self.cols, self.rows)

    @property
    def symmetric(self) -> bool:
        """True when a 180-degree turn of the board looks the same (ambiguous origin)."""
        return (self.cols + self.rows) % 2 == 0

    def object_points(self) -> NDArray[np.float32]:
        """(rows*cols, 3) corner positions in board coordinates (z = 0), row-major."""
        grid = np.mgrid[0 : self.cols, 0 : self.rows].T.reshape(-1, 2)
        pts = np.zeros((self.cols * self.rows, 3), np.float32)
        pts[:, :2] = grid * self.square
        return pts

    @property
    def center(self) -> NDArray[np.float64]:
        """The board centre in board coordinates."""
        return np.array([(self.cols - 1) * self.square / 2, (self.rows - 1) * self.square / 2, 0])


def _load_gray(image: ImageInput) -> tuple[NDArray[np.uint8], str]:
    if isinstance(image, str | Path):
        gray = cv2.imread(str(image), cv2.IMREAD_GRAYSCALE)
        if gray is None:
            raise CalibrationError(f"{image}: cannot read this image; check the path and format")
        return np.asarray(gray, dtype=np.uint8), str(image)
    arr = np.asarray(image)
    if arr.ndim == 3:
        arr = np.asarray(cv2.cvtColor(arr, cv2.COLOR_BGR2GRAY))
    return arr.astype(np.uint8), "<array>"


def _sample(gray: NDArray[np.uint8], p: NDArray[np.float64], r: int) -> float:
    x, y = int(round(p[0])), int(round(p[1]))
    h, w = gray.shape
    x0, x1, y0, y1 = max(x - r, 0), min(x + r + 1, w), max(y - r, 0), min(y + r + 1, h)
    if x0 >= x1 or y0 >= y1:
        return math.nan
    return float(gray[y0:y1, x0:x1].mean())


def _normalize_order(
    corners: NDArray[np.float32], gray: NDArray[np.uint8], board: Board
) -> NDArray[np.float32]:
    """Reorder corners: right-handed with normal away from the camera, black square first."""
    c = corners.reshape(board.rows, board.cols, 2).astype(np.float64)
    dx = c[0, 1] - c[0, 0]
    dy = c[1, 0] - c[0, 0]
    if dx[0] * dy[1] - dx[1] * dy[0] < 0:
        c = c[::-1]
        dx = c[0, 1] - c[0, 0]
        dy = c[1, 0] - c[0, 0]
    if not board.symmetric:
        r = max(1, int(0.15 * min(np.linalg.norm(dx), np.linalg.norm(dy))))
        outer = _sample(gray, c[0, 0] - 0.5 * dx - 0.5 * dy, r)
        beside = _sample(gray, c[0, 0] + 0.5 * dx - 0.5 * dy, r)
        if math.isfinite(outer) and math.isfinite(beside) and outer > beside:
            c = c[::-1, ::-1]
    return np.ascontiguousarray(c.reshape(-1, 1, 2), dtype=np.float32)


def find_board_corners(
    image: ImageInput,
    board: Board,
    max_side: int = 1280,
    method: Literal["auto", "classic", "sb"] = "auto",
) -> NDArray[np.float32] | None:
    """Sub-pixel inner corners ``(rows*cols, 1, 2)`` of ``board`` in an image, or None.

    ``classic``: ``findChessboardCorners`` on a copy scaled to ``max_side`` pixels
    (fast), ``cornerSubPix`` at full resolution; ``sb``: ``findChessboardCornersSB``
    (slower, more robust); ``auto`` tries classic, then sb. Either way the corners come
    in the one order described in the module docs.
    """
    if method not in ("auto", "classic", "sb"):
        raise ConfigError(f"corner detection method must be auto, classic or sb, got {method!r}")
    gray, _ = _load_gray(image)
    scale = min(1.0, max_side / max(gray.shape))
    small = (
        cv2.resize(gray, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
        if scale < 1.0
        else gray
    )
    flags = cv2.CALIB_CB_ADAPTIVE_THRESH | cv2.CALIB_CB_NORMALIZE_IMAGE
    ok, corners = False, None
    if method != "sb":
        ok, corners = cv2.findChessboardCorners(small, board.size, flags=flags)
    if ok:
        corners = (corners / scale).astype(np.float32)
        step = np.min(np.linalg.norm(np.diff(corners.reshape(board.rows, board.cols, 2), axis=1),
                                     axis=-1))
        win = int(np.clip(step * 0.3, 3, 15))
        criteria = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 40, 1e-3)
        corners = cv2.cornerSubPix(gray, corners, (win, win), (-1, -1), criteria)
    elif method == "classic":
        return None
    else:
        sb_flags = cv2.CALIB_CB_NORMALIZE_IMAGE | cv2.CALIB_CB_EXHAUSTIVE | cv2.CALIB_CB_ACCURACY
        ok, corners = cv2.findChessboardCornersSB(gray, board.size, flags=sb_flags)
        if not ok:
            return None
    return _normalize_order(np.asarray(corners, dtype=np.float32), gray, board)


@dataclass(frozen=True, eq=False)
class IntrinsicsResult:
    """One camera's intrinsic calibration.

    ``rms_px`` is OpenCV's reprojection RMS over the views kept; ``used`` lists those
    views with their RMS in ``view_rms_px``; ``rejected`` the views left out and why.
    """

    camera: Camera
    rms_px: float
    used: tuple[str, ...]
    view_rms_px: tuple[float, ...]
    rejected: tuple[tuple[str, str], ...]


def calibrate_intrinsics(
    images: Sequence[ImageInput],
    board: Board,
    name: str = "cam0",
    *,
    fix_k3: bool = True,
    outlier_px: float = 1.0,
    min_views: int = 3,
) -> IntrinsicsResult:
    """Calibrate one camera (K, distortion) from photos of ``board`` in varied poses.

    Views whose RMS exceeds ``max(outlier_px, 3 x median)`` are dropped one at a time
    (worst first) while at least ``min_views`` remain.
    """
    if min_views < 1:
        raise ConfigError("min_views must be at least 1")
    labels: list[str] = []
    views: list[NDArray[np.float32]] = []
    rejected: list[tuple[str, str]] = []
    size: tuple[int, int] | None = None
    for k, image in enumerate(images):
        gray, label = _load_gray(image)
        label = label if label != "<array>" else f"image {k}"
        wh = (int(gray.shape[1]), int(gray.shape[0]))
        if size is None:
            size = wh
        elif wh != size:
            raise CalibrationError(
                f"{label}: image is {wh[0]}x{wh[1]} but camera {name!r}'s first image is "
                f"{size[0]}x{size[1]}; give each camera its own --images"
            )
        corners = find_board_corners(gray, board)
        if corners is None:
            rejected.append((label, "board not found"))
            continue
        labels.append(label)
        views.append(corners)
    if size is None:
        raise CalibrationError(f"camera {name!r}: no images given; check the --images glob")
    if len(views) < min_views:
        raise CalibrationError(
            f"camera {name!r}: the {board.cols}x{board.rows} board was found in {len(views)} of "
            f"{len(views) + len(rejected)} images, need {min_views}; check --board (inner "
            "corners) and take more photos with the whole board visible"
        )
    obj = board.object_points()
    flags = cv2.CALIB_FIX_K3 if fix_k3 else 0
    while True:
        rms, K, dist, _, _, _, _, per_view = cv2.calibrateCameraExtended(  # type: ignore[call-overload]
            [obj] * len(views), views, size, None, None, flags=flags
        )
        per_view = per_view.ravel()
        worst = int(np.argmax(per_view))
        limit = max(outlier_px, 3.0 * float(np.median(per_view)))
        if per_view[worst] <= limit or len(views) <= min_views:
            break
        rejected.append((labels[worst], f"reprojection {per_view[worst]:.2f} px (outlier)"))
        del labels[worst], views[worst]
    camera = Camera(name, size[0], size[1], K, dist=np.ravel(dist)[:5])
    return IntrinsicsResult(
        camera, float(rms), tuple(labels), tuple(float(v) for v in per_view), tuple(rejected)
    )


def board_pose_in_camera(
    camera: Camera, image: ImageInput, board: Board
) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    """Board-to-camera ``(R, t, rms_px)`` from one image (IPPE, then LM refinement)."""
    gray, label = _load_gray(image)
    if (gray.shape[1], gray.shape[0]) != (camera.width, camera.height):
        raise CalibrationError(
            f"{label}: reference image is {gray.shape[1]}x{gray.shape[0]}, camera "
            f"{camera.name!r} is {camera.width}x{camera.height}"
        )
    corners = find_board_corners(gray, board)
    if corners is None:
        raise CalibrationError(
            f"{label}: board not found in camera {camera.name!r}'s reference image; every "
            "camera must see the whole board in its reference image"
        )
    obj = board.object_points()
    ok, rvec, tvec = cv2.solvePnP(obj, corners, camera.K, camera.dist, flags=cv2.SOLVEPNP_IPPE)
    if not ok:
        raise CalibrationError(f"{label}: solvePnP failed for camera {camera.name!r}")
    rvec, tvec = cv2.solvePnPRefineLM(obj, corners, camera.K, camera.dist, rvec, tvec)
    proj, _ = cv2.projectPoints(obj, rvec, tvec, camera.K, camera.dist)
    rms = float(np.sqrt(np.mean(np.sum((proj - corners) ** 2, axis=-1))))
    R, _ = cv2.Rodrigues(rvec)
    return np.asarray(R, dtype=np.float64), np.asarray(tvec, dtype=np.float64).ravel(), rms


def _snap(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """The board edge direction (+-x or +-y) closest to ``v`` (board coordinates)."""
    axes = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]])
    return axes[int(np.argmax(axes @ v))]


def _world_from_board(
    R0: NDArray[np.float64], board: Board, pose: BoardPose, height: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(M, o): p_world = M (p_board - centre) + o, from the first camera's board pose."""
    normal_to_cam = np.array([0.0, 0.0, -1.0])  # board z points away from the cameras
    if pose == "floor":
        Y = normal_to_cam
        X = _snap(R0[0])  # camera right in board coordinates
        Z = np.cross(X, Y)
        origin = np.zeros(3)
    else:
        Z = normal_to_cam
        Y = _snap(-R0[1])  # camera up in board coordinates
        X = np.cross(Y, Z)
        origin = np.array([0.0, height, 0.0])
    return np.stack([X, Y, Z]), origin


@dataclass(frozen=True, eq=False)
class RigCalibration:
    """Calibrated cameras of a rig with the figures that say how good they are.

    ``extrinsic_rms_px`` is the reprojection RMS of the reference board per camera
    (NaN with ``board_pose="none"``).
    """

    cameras: tuple[Camera, ...]
    intrinsics: tuple[IntrinsicsResult, ...]
    extrinsic_rms_px: tuple[float, ...]
    board_pose: BoardPose


def calibrate_rig(
    image_sets: Sequence[Sequence[ImageInput]],
    board: Board,
    names: Sequence[str] | None = None,
    *,
    reference: Sequence[ImageInput] | None = None,
    board_pose: BoardPose = "floor",
    board_height: float | None = None,
    fix_k3: bool = True,
) -> RigCalibration:
    """Calibrate every camera's intrinsics, then place them all in one world.

    ``image_sets[i]`` are camera i's checkerboard photos; ``reference[i]`` its view of
    the board that defines the world (default: its first photo), see module docs.
    """
    n = len(image_sets)
    if n == 0:
        raise ConfigError("no cameras: give one image set (--images GLOB) per camera")
    names = list(names) if names else [f"cam{i}" for i in range(n)]
    if len(names) != n or len(set(names)) != n:
        raise ConfigError(f"need {n} distinct camera names, got {names}")
    if board_pose not in ("floor", "wall", "none"):
        raise ConfigError(f"board pose must be floor, wall or none, got {board_pose!r}")
    if board_pose == "wall" and board_height is None:
        raise ConfigError(
            "a wall board needs its centre's height above the floor (--board-height METRES) "
            "so that the floor is at Y = 0"
        )
    refs = list(reference) if reference is not None else [s[0] for s in image_sets if len(s)]
    if board_pose != "none" and len(refs) != n:
        raise ConfigError(f"need one reference image per camera ({n}), got {len(refs)}")
    intr = tuple(
        calibrate_intrinsics(imgs, board, name, fix_k3=fix_k3)
        for imgs, name in zip(image_sets, names, strict=True)
    )
    if board_pose == "none":
        cams = tuple(r.camera for r in intr)
        return RigCalibration(cams, intr, tuple(math.nan for _ in cams), board_pose)
    if board.symmetric and n > 1:
        warnings.warn(
            f"a {board.cols}x{board.rows} board looks the same turned by 180 degrees; cameras "
            "facing it from opposite sides may disagree. Use e.g. 9x6 inner corners",
            stacklevel=2,
        )
    poses = [board_pose_in_camera(r.camera, ref, board) for r, ref in zip(intr, refs, strict=True)]
    M, origin = _world_from_board(poses[0][0], board, board_pose, board_height or 0.0)
    c = board.center
    placed: list[Camera] = []
    for r, (Rb, tb, _) in zip(intr, poses, strict=True):
        R = Rb @ M.T
        t = Rb @ (c - M.T @ origin) + tb
        k = r.camera
        placed.append(Camera(k.name, k.width, k.height, k.K, R, t, k.dist))
    return RigCalibration(tuple(placed), intr, tuple(p[2] for p in poses), board_pose)


def read_qualisys_calib(path: str | Path, y_up: bool = True) -> list[Camera]:
    """Read a Qualisys ``.qca.txt`` calibration (as shipped with Pose2Sim) as cameras.

    Focal lengths and principal points are stored x64 (principal points relative to
    the sensor, so the ``fov_video`` offset is subtracted); the transform gives the
    camera centre in millimetres and M (r11..r33 row by row) with world-to-camera
    ``R = diag(1, -1, -1) M``. The Qualisys world is Z up; with ``y_up`` it is turned
    into bodyplay's Y-up world by (X, Y, Z) = (old y, old z, old x).
    """
    with reading(path, CalibrationError, "Qualisys calibration"):
        return _read_qualisys_calib_unchecked(path, y_up)


def _read_qualisys_calib_unchecked(path: str | Path, y_up: bool = True) -> list[Camera]:
    """The unchecked reader behind :func:`read_qualisys_calib`."""
    p = Path(path)
    if not p.is_file():
        raise CalibrationError(f"{p}: no such Qualisys calibration file")
    try:
        root = ET.parse(p).getroot()
    except ET.ParseError as exc:
        raise CalibrationError(f"{p}: not a Qualisys XML calibration ({exc})") from None
    P = np.array([[0.0, 1, 0], [0, 0, 1], [1, 0, 0]]) if y_up else np.eye(3)
    cams: list[Camera] = []
    for k, node in enumerate(root.iter("camera")):
        tr, it, fov = node.find("transform"), node.find("intrinsic"), node.find("fov_video")
        if tr is None or it is None or fov is None:
            raise CalibrationError(f"{p}: camera {k} lacks transform, intrinsic or fov_video")
        try:
            M = np.array([[float(tr.attrib[f"r{i}{j}"]) for j in "123"] for i in "123"])
            C = np.array([float(tr.attrib[a]) for a in "xyz"]) / 1000.0
            left, top = float(fov.attrib["left"]), float(fov.attrib["top"])
            width = int(round(float(fov.attrib["right"]) - left + 1))
            height = int(round(float(fov.attrib["bottom"]) - top + 1))
            fx = float(it.attrib["focalLengthU"]) / 64.0
            fy = float(it.attrib["focalLengthV"]) / 64.0
            cx = float(it.attrib["centerPointU"]) / 64.0 - left
            cy = float(it.attrib["centerPointV"]) / 64.0 - top
            dist = [
                float(it.attrib["radialDistortion1"]),
                float(it.attrib["radialDistortion2"]),
                float(it.attrib["tangentalDistortion1"]),
                float(it.attrib["tangentalDistortion2"]),
                float(it.attrib.get("radialDistortion3", 0.0)),
            ]
        except (KeyError, ValueError) as exc:
            raise CalibrationError(f"{p}: camera {k}: missing or bad value {exc}") from None
        R = np.diag([1.0, -1.0, -1.0]) @ M
        Rw = R @ P.T
        t = -R @ C
        K = np.array([[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]])
        name = node.attrib.get("serial") or f"cam{k}"
        cams.append(Camera(name, width, height, K, Rw, t, np.array(dist)))
    if not cams:
        raise CalibrationError(f"{p}: no <camera> entries")
    return cams


def rig_geometry(cameras: Sequence[Camera]) -> list[tuple[str, str, float, float]]:
    """For each camera pair: (name a, name b, angle between optical axes in degrees,
    baseline in metres) -- figures that do not depend on the world frame."""
    out = []
    for i, a in enumerate(cameras):
        for b in cameras[i + 1 :]:
            cos = float(np.clip(a.R[2] @ b.R[2], -1.0, 1.0))
            out.append(
                (a.name, b.name, math.degrees(math.acos(cos)),
                 float(np.linalg.norm(a.center - b.center)))
            )
    return out
