"""Where the head is: a cue from the background plate for the joint the shirt misses.

The head has no patch, but above the collar it is the only foreground:
:func:`find_head` looks in the plate's foreground near where the fit predicts the
head for a disk of the head's projected size; :func:`head_anchors` makes the heads
found IK anchors, :func:`head_from_cue` puts the reported head joint on the rays
through them. Beyond the paper; the foreground is the empty-room plate's, else the
room plate's where another camera's view tells the room; without either the head
follows the blend.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.shirt import NUM_PATCHES
from bodyplay.body.skeleton import NODE_NAMES, Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.ik import PatchAnchors

if TYPE_CHECKING:
    from bodyplay.trackers.colorshirt.options import ColorShirtOptions
    from bodyplay.trackers.colorshirt.views import CameraState, CameraView

__all__ = ["HEAD_PATCH", "HEAD_RADIUS", "HeadPoint", "find_head", "head_anchors",
           "head_from_cue"]

HEAD_RADIUS = 0.095
"""Radius (m) of the disk a head projects to, for a body of 1.75 m (scaled by height)."""

HEAD_PATCH = NUM_PATCHES + 1
"""The ``patch`` id of a head anchor (the shirt's patches are 1..20)."""

_HEAD_NODE = NODE_NAMES.index("head")
_HEAD_FIT_STD = 0.06
"""Metres: the std pulling the reported head towards the fitted pose's."""
_HEAD_TOP = NODE_NAMES.index("head_top")
_IN_VIEW_REACH = 1.0
"""Head radii around the pose's head searched in the room plate's foreground (the
empty-room plate's: 2): with the player in view the room beside the head is often
unknown, foreground, so a wider search drifts to the arms and shoulders."""


@dataclass(frozen=True)
class HeadPoint:
    """The head's centre found in one image (full-resolution pixels) and its radius."""

    u: float
    v: float
    radius: float
    fill: float
    """Share of the disk that is foreground (1: a whole head)."""


def find_head(
    fg: NDArray[np.bool_],
    downscale: int,
    head: NDArray[np.float64],
    neck: NDArray[np.float64],
    radius: float,
    reach: float = 2.0,
    cut: float = 0.45,
    min_fill: float = 0.5,
) -> HeadPoint | None:
    """The centre of the head-sized disk of foreground nearest the predicted head.

    ``fg`` is the plate-resolution foreground mask, ``head`` and ``neck`` the
    predicted head and neck joints in full-resolution pixels, ``radius`` the head's
    projected radius there (pixels). Only pixels beyond ``cut`` of the way from the
    neck to the head count (the shirt's collar and the throat are excluded); the
    disk's centre is searched within ``reach`` radii of the prediction, then set to
    the centroid of the foreground inside it (two mean-shift steps). None when the
    best disk is less than ``min_fill`` foreground.
    """
    s = float(downscale)
    h, w = fg.shape
    r = radius / s
    if not (np.all(np.isfinite(head)) and np.all(np.isfinite(neck))) or r < 2.0:
        return None
    hx, hy = head / s
    nx, ny = neck / s
    axis = np.array([hx - nx, hy - ny])
    length = float(np.hypot(*axis))
    if length < 1.0:
        return None
    axis /= length
    pad = reach * r + r + 1
    x0, x1 = max(0, int(hx - pad)), min(w, int(np.ceil(hx + pad)))
    y0, y1 = max(0, int(hy - pad)), min(h, int(np.ceil(hy + pad)))
    if x1 - x0 < 2 * r or y1 - y0 < 2 * r:
        return None
    roi = fg[y0:y1, x0:x1]
    yy, xx = np.mgrid[y0:y1, x0:x1]
    along = (xx - nx) * axis[0] + (yy - ny) * axis[1]
    cand = roi & (along > cut * length)
    k = int(np.ceil(r))
    ky, kx = np.mgrid[-k: k + 1, -k: k + 1]
    disk = ((kx * kx + ky * ky) <= r * r).astype(np.float32)
    area = float(disk.sum())
    score = cv2.filter2D(cand.astype(np.float32), -1, disk, borderType=cv2.BORDER_CONSTANT) / area
    near = (xx - hx) ** 2 + (yy - hy) ** 2 <= (reach * r) ** 2
    score = np.where(near, score, -1.0)
    iy, ix = np.unravel_index(int(np.argmax(score)), score.shape)
    fill = float(score[iy, ix])
    if fill < min_fill:
        return None
    cx, cy = float(ix + x0), float(iy + y0)
    for _ in range(2):
        inside = cand & ((xx - cx) ** 2 + (yy - cy) ** 2 <= r * r)
        if not inside.any():
            return None
        cx, cy = float(xx[inside].mean()), float(yy[inside].mean())
    return HeadPoint((cx + 0.5) * s, (cy + 0.5) * s, radius, fill)


def head_anchors(skeleton: Skeleton, q: NDArray[np.float64], cameras: Sequence[Camera],
                 states: Sequence[CameraState], views: Sequence[CameraView],
                 options: ColorShirtOptions) -> tuple[PatchAnchors, list[tuple[int, HeadPoint]]]:
    """One anchor on the head per camera whose empty-room plate shows the head near
    pose ``q`` (``head_offset`` above the joint, std ``head_std`` m), and the heads
    found, also those of the room plate with the player in view (report only)."""
    if not options.head_cue:
        return PatchAnchors.empty(), []
    J = skeleton.joint_positions(q)
    head_w, neck_w = J[JOINT_INDEX["head"]], J[JOINT_INDEX["neck"]]
    radius_m = HEAD_RADIUS * float(np.linalg.norm(skeleton.offsets[_HEAD_TOP])) / 0.13
    found: list[tuple[int, HeadPoint]] = []
    anchored: list[tuple[int, HeadPoint, float]] = []
    for v in views:
        st = states[v.index]
        fg, reach = st.floor.foreground(), 2.0
        in_view = fg is None and st.room.seen_alike is not None
        if in_view:
            # no empty room: the room plate, where another camera's view tells the
            # room the plate has not uncovered; no outline there, so near the pose
            fg, reach = st.room.foreground(), _IN_VIEW_REACH
        if fg is None:
            continue
        cam = cameras[v.index]
        z = float(cam.world_to_camera(head_w)[2])
        if z <= 0.3:
            continue
        f = float(cam.K[0, 0])
        hp = find_head(fg, st.floor.plate.downscale,
                       cam.project(head_w, distort=False), cam.project(neck_w, distort=False),
                       radius_m * f / z, reach=reach)
        if hp is None:
            continue
        found.append((v.index, hp))
        if not in_view:  # as an anchor it moved the trunk's fit and the body chosen
            anchored.append((v.index, hp, options.head_std * f / z))
    n = len(anchored)
    anchors = PatchAnchors(
        np.full(n, _HEAD_NODE, np.int64),
        np.tile([0.0, options.head_offset, 0.0], (n, 1)),
        np.array([a[0] for a in anchored], np.int64),
        np.array([[a[1].u, a[1].v] for a in anchored], np.float64).reshape(n, 2),
        np.array([a[2] for a in anchored], np.float64),
        np.full(n, HEAD_PATCH, np.int64),
    )
    return anchors, found


def head_from_cue(skeleton: Skeleton, q: NDArray[np.float64], cameras: Sequence[Camera],
                  found: Sequence[tuple[int, HeadPoint]], options: ColorShirtOptions,
                  max_shift: float = 0.12) -> NDArray[np.float64] | None:
    """The head joint placed on the rays through the heads found, or None.

    The fitted pose's head anchor moves to the point nearest to every ray (std
    ``head_std``) and to where the pose put it (:data:`_HEAD_FIT_STD`): the skeleton's
    neck length is generic. A move over ``max_shift`` metres is not trusted (None).
    """
    if not found:
        return None
    G = skeleton.forward(q)
    R_head, p_head = G[_HEAD_NODE, :3, :3], G[_HEAD_NODE, :3, 3]
    up = R_head @ np.array([0.0, options.head_offset, 0.0])
    anchor = p_head + up
    A = np.eye(3) / _HEAD_FIT_STD**2
    b = A @ anchor
    for index, hp in found:
        cam = cameras[index]
        d = cam.R.T @ np.linalg.solve(cam.K, np.array([hp.u, hp.v, 1.0]))
        d /= np.linalg.norm(d)
        P = (np.eye(3) - np.outer(d, d)) / options.head_std**2
        A += P
        b += P @ cam.center
    point = np.linalg.solve(A, b)
    if not np.all(np.isfinite(point)) or np.linalg.norm(point - anchor) > max_shift:
        return None
    return np.asarray(point - up, np.float64)
