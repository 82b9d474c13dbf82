"""Where the synthetic webcams stand: intrinsics, placement in front of the actor, framing.

A webcam for body games sits at about chest height, 2.5 to 4 m in front of the
player, with a horizontal field of view near 60 degrees. :func:`frame_rig` places
one camera (or a converging pair 1 to 2 m apart) so that every joint of a clip,
padded for the body's flesh, stays inside the picture: it estimates which way the
actor faces from the hips and shoulders, finds the smallest distance that frames
the whole clip, then adds seeded jitter (distance, height, yaw) so different seeds
give different but plausible set-ups. :func:`out_of_view_frames` reports frames
in which the actor leaves the picture anyway.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.joints import JOINT_INDEX, NUM_JOINTS
from bodyplay.capture.camera import Camera, look_at
from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types

__all__ = [
    "RigOptions",
    "make_rig_options",
    "Rig",
    "frame_rig",
    "out_of_view_frames",
    "distortion_maps",
]

# Padding around joints for flesh: head top above the head centre, hands past the
# wrists, feet below the ankles, and the limbs' radius.
_PAD_UP = 0.16
_PAD = 0.12
_PAD_DOWN = 0.10


@dataclass(frozen=True)
class RigOptions:
    """How to build the rig; make one with :func:`make_rig_options` (it validates).

    ``distance`` None lets :func:`frame_rig` choose (2.5..4 m, farther only if the
    clip needs it); ``baseline`` None picks 1..2 m for two cameras; ``k1`` is the
    radial distortion coefficient (0: an ideal pinhole, -0.05: a typical webcam).
    """

    cameras: int = 1
    width: int = 640
    height: int = 480
    hfov_deg: float = 60.0
    distance: float | None = None
    baseline: float | None = None
    k1: float = 0.0
    seed: int = 0

    def __post_init__(self) -> None:
        check_option_types(self)


def make_rig_options(
    cameras: int = 1,
    width: int = 640,
    height: int = 480,
    hfov_deg: float = 60.0,
    distance: float | None = None,
    baseline: float | None = None,
    k1: float = 0.0,
    seed: int = 0,
) -> RigOptions:
    """Validated :class:`RigOptions`; errors say which value is wrong and the valid range."""
    if cameras not in (1, 2):
        raise ConfigError(f"cameras must be 1 or 2, got {cameras}")
    if not (16 <= width <= 4096 and 16 <= height <= 4096):
        raise ConfigError(f"image size {width}x{height} must be within 16..4096 pixels a side")
    if not 20.0 <= hfov_deg <= 120.0:
        raise ConfigError(f"horizontal field of view {hfov_deg} deg must be within 20..120")
    if distance is not None and not 1.0 <= distance <= 10.0:
        raise ConfigError(f"camera distance {distance} m must be within 1..10 m")
    if baseline is not None and not 0.2 <= baseline <= 4.0:
        raise ConfigError(f"camera baseline {baseline} m must be within 0.2..4 m")
    if not -0.5 <= k1 <= 0.5:
        raise ConfigError(f"radial distortion k1 {k1} must be within -0.5..0.5")
    return RigOptions(cameras, width, height, hfov_deg, distance, baseline, k1, int(seed))


@dataclass(frozen=True, eq=False)
class Rig:
    """The placed cameras and the frame they were placed in.

    ``forward`` is the unit horizontal direction from the actor towards the camera
    rig, ``right`` the camera's right, ``target`` the point the cameras look at.
    """

    cameras: tuple[Camera, ...]
    target: NDArray[np.float64]
    forward: NDArray[np.float64]
    right: NDArray[np.float64]
    distance: float
    baseline: float


def _padded_points(joints: NDArray[np.float64]) -> NDArray[np.float64]:
    """(T, 17, 3) joints -> (T*17*7, 3) points: each joint and six padded neighbours."""
    j = joints.reshape(-1, NUM_JOINTS, 3)
    offsets = np.array(
        [[0, 0, 0], [_PAD, 0, 0], [-_PAD, 0, 0], [0, _PAD, 0], [0, -_PAD, 0], [0, 0, _PAD],
         [0, 0, -_PAD]],
        dtype=np.float64,
    )
    pts = j[:, :, None, :] + offsets[None, None]
    head = j[:, JOINT_INDEX["head"]] + np.array([0.0, _PAD_UP, 0.0])
    feet = np.concatenate(
        [j[:, JOINT_INDEX["l_ankle"]], j[:, JOINT_INDEX["r_ankle"]]]
    ) - np.array([0.0, _PAD_DOWN, 0.0])
    return np.concatenate([pts.reshape(-1, 3), head, feet])


def _facing(joints: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit horizontal direction the actor faces on average (left x up)."""
    j = joints.reshape(-1, NUM_JOINTS, 3)
    left = (j[:, JOINT_INDEX["l_hip"]] - j[:, JOINT_INDEX["r_hip"]]) + (
        j[:, JOINT_INDEX["l_shoulder"]] - j[:, JOINT_INDEX["r_shoulder"]]
    )
    fwd = np.cross(left, np.array([0.0, 1.0, 0.0])).sum(axis=0)
    fwd[1] = 0.0
    n = np.linalg.norm(fwd)
    return np.array([0.0, 0.0, 1.0]) if n < 1e-9 else fwd / n


def _place(
    opts: RigOptions,
    target: NDArray[np.float64],
    forward: NDArray[np.float64],
    right: NDArray[np.float64],
    distance: float,
    baseline: float,
    height: float,
) -> tuple[Camera, ...]:
    cams = []
    for i in range(opts.cameras):
        side = 0.0 if opts.cameras == 1 else (i - 0.5) * baseline
        eye = target + forward * distance + right * side
        eye = np.array([eye[0], height, eye[2]])
        R, t = look_at(eye, target)
        base = Camera.from_fov(f"cam{i}", opts.width, opts.height, opts.hfov_deg, R, t)
        dist = np.array([opts.k1, 0.0, 0.0, 0.0, 0.0])
        cams.append(Camera(base.name, base.width, base.height, base.K, R, t, dist))
    return tuple(cams)


def _fits(cams: tuple[Camera, ...], pts: NDArray[np.float64], margin: float) -> bool:
    return all(bool(np.all(c.in_view(pts, margin))) for c in cams)


def frame_rig(joints: ArrayLike, options: RigOptions | None = None) -> Rig:
    """Place the cameras so that the clip's joints ``(T, 17, 3)`` stay in view.

    The cameras stand at chest height in front of the actor's average facing
    direction, look at the centre of the clip's extent, and are pulled back from
    2.5 m until the padded joints of every frame fit; a seeded jitter of distance
    (up to 4 m), height (+-5 cm) and yaw (+-6 degrees) follows. Warns when the clip
    needs more than 4 m, and when any frame still leaves the picture.
    """
    opts = options or make_rig_options()
    j = np.asarray(joints, dtype=np.float64).reshape(-1, NUM_JOINTS, 3)
    if j.shape[0] == 0 or not np.all(np.isfinite(j)):
        raise ConfigError("frame_rig needs at least one frame of finite joint positions")
    rng = np.random.default_rng(opts.seed)
    pts = _padded_points(j)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    target = 0.5 * (lo + hi)
    yaw = math.radians(rng.uniform(-6.0, 6.0))
    f0 = _facing(j)
    c, s = math.cos(yaw), math.sin(yaw)
    forward = np.array([c * f0[0] + s * f0[2], 0.0, -s * f0[0] + c * f0[2]])
    right = np.cross(np.array([0.0, 1.0, 0.0]), forward)  # camera's right = actor's left
    right /= np.linalg.norm(right)
    chest = float(np.median(j[:, JOINT_INDEX["chest"], 1]))
    height = chest + rng.uniform(-0.05, 0.05)
    baseline = opts.baseline if opts.baseline is not None else float(rng.uniform(1.0, 2.0))
    jitter = float(rng.uniform(0.0, 0.6))
    margin = 0.02 * min(opts.width, opts.height)
    if opts.distance is not None:
        distance = opts.distance
    else:
        near, far = 2.5, 2.5
        while not _fits(_place(opts, target, forward, right, far, baseline, height), pts, margin):
            near, far = far, far * 1.25
            if far > 12.0:
                break
        if far > 2.5:
            for _ in range(20):  # bisection on the fitting distance
                mid = 0.5 * (near + far)
                placed = _place(opts, target, forward, right, mid, baseline, height)
                fits = _fits(placed, pts, margin)
                near, far = (near, mid) if fits else (mid, far)
        distance = min(max(far, 2.5) + jitter, max(far, 4.0))
        if far > 4.0:
            warnings.warn(
                f"the clip spans {hi[0] - lo[0]:.1f} x {hi[1] - lo[1]:.1f} x "
                f"{hi[2] - lo[2]:.1f} m: the camera stands {far:.1f} m away (a webcam "
                "would be at most 4 m); shorten the clip with --start/--seconds",
                stacklevel=2,
            )
    cams = _place(opts, target, forward, right, distance, baseline, height)
    rig = Rig(cams, target, forward, right, float(distance), float(baseline))
    bad = out_of_view_frames(rig.cameras, j)
    if bad.size:
        warnings.warn(
            f"the actor leaves the picture in {bad.size} of {j.shape[0]} frames "
            f"(first: frame {int(bad[0])})",
            stacklevel=2,
        )
    return rig


def out_of_view_frames(
    cameras: tuple[Camera, ...] | list[Camera], joints: ArrayLike, margin: float = 0.0
) -> NDArray[np.int64]:
    """Indices of frames ``(T, 17, 3)`` in which some joint projects outside some camera."""
    j = np.asarray(joints, dtype=np.float64).reshape(-1, NUM_JOINTS, 3)
    bad = np.zeros(j.shape[0], dtype=bool)
    for cam in cameras:
        bad |= ~np.all(cam.in_view(j, margin), axis=1)
    return np.flatnonzero(bad)


def distortion_maps(camera: Camera) -> tuple[NDArray[np.float32], NDArray[np.float32]] | None:
    """cv2.remap maps that turn a pinhole render into the camera's distorted picture.

    For every output (distorted) pixel, the map gives where to sample the ideal
    render: undistort the pixel, then reproject with ``K``. None without distortion.
    """
    if not np.any(camera.dist):
        return None
    u, v = np.meshgrid(
        np.arange(camera.width, dtype=np.float64), np.arange(camera.height, dtype=np.float64)
    )
    pts = np.stack([u.ravel(), v.ravel()], axis=1).reshape(-1, 1, 2)
    und = cv2.undistortPoints(pts, camera.K, camera.dist, P=camera.K).reshape(
        camera.height, camera.width, 2
    )
    return und[..., 0].astype(np.float32), und[..., 1].astype(np.float32)
