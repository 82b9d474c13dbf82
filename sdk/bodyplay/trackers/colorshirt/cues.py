"""Cues beyond the shirt, from the background plate: the feet and the head.

:func:`floor_reading`: one camera's root depth from the feet (:mod:`.floor`);
:func:`head_anchors`: the heads found above the collar (:mod:`.head`) as IK
anchors; :func:`head_from_cue`: the reported head joint on the rays through them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.shirt import NUM_PATCHES
from bodyplay.body.skeleton import NODE_NAMES, Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.floor import floor_depth
from bodyplay.trackers.colorshirt.head import HEAD_RADIUS, HeadPoint, find_head
from bodyplay.trackers.colorshirt.ik import PatchAnchors
from bodyplay.trackers.colorshirt.options import ColorShirtOptions
from bodyplay.trackers.colorshirt.views import CameraState, CameraView

__all__ = ["HEAD_PATCH", "FloorReading", "floor_reading", "head_anchors",
           "head_from_cue", "join_anchors"]

HEAD_PATCH = NUM_PATCHES + 1
"""The ``patch`` id of a head anchor (the shirt's patches are 1..20)."""

_HEAD_NODE = NODE_NAMES.index("head")
_HEAD_FIT_STD = 0.06
"""Metres: the std pulling the reported head towards the fitted pose's."""
_NO_ANCHORS = PatchAnchors(np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros(0, np.int64),
                           np.zeros((0, 2)), np.zeros(0), np.zeros(0, np.int64))
_HEAD_TOP = NODE_NAMES.index("head_top")
_IN_VIEW_REACH = 1.0
"""Head radii around the pose's head searched in the room plate's foreground (the
empty-room plate's: 2): with the player in view the room beside the head is often
unknown, foreground, so a wider search drifts to the arms and shoulders."""


@dataclass(frozen=True)
class FloorReading:
    """What the feet told in one frame: the root's ``depth`` along the lone camera's
    axis (m; None: no reading) and the ``stagger``, how far apart in depth the two
    feet stand (m; None unless both were found: then one image cannot say which
    foot bears the weight)."""

    stagger: float | None = None
    depth: float | None = None


def floor_reading(cameras: Sequence[Camera], states: Sequence[CameraState],
                  views: Sequence[CameraView], options: ColorShirtOptions,
                  root_height: float) -> FloorReading:
    """The root's depth that a lone camera reads from the feet: their floor points'
    mean raised by ``root_height`` (m), its depth plus ``options.floor_offset``."""
    if len(views) != 1 or not options.floor_cue:
        return FloorReading()
    cam = cameras[views[0].index]
    points, depths = [], []
    for f in states[views[0].index].floor.feet():
        z = floor_depth(cam, f)
        if z is not None:
            depths.append(z)
            ray = np.linalg.solve(cam.K, np.array([f.u, f.v, 1.0]))
            points.append(cam.R.T @ (ray * z) + cam.center)
    if not depths:
        return FloorReading()
    root = np.mean(points, axis=0) + np.array([0.0, root_height, 0.0])
    depth = float(cam.world_to_camera(root)[2]) + options.floor_offset
    return FloorReading(max(depths) - min(depths) if len(depths) > 1 else None, depth)


def head_anchors(skeleton: Skeleton, q: NDArray[np.float64], cameras: Sequence[Camera],
                 states: Sequence[CameraState], views: Sequence[CameraView],
                 options: ColorShirtOptions) -> tuple[PatchAnchors, list[tuple[int, HeadPoint]]]:
    """One anchor on the head per camera whose empty-room plate shows the head near
    pose ``q`` (``head_offset`` above the joint, std ``head_std`` m), and the heads
    found, also those of the room plate with the player in view (report only)."""
    if not options.head_cue:
        return _NO_ANCHORS, []
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


def join_anchors(a: PatchAnchors, b: PatchAnchors) -> PatchAnchors:
    """The anchors of ``a`` followed by those of ``b``."""
    if len(b) == 0:
        return a
    return PatchAnchors(*(np.concatenate([getattr(a, f), getattr(b, f)]) for f in
                          ("node", "local", "camera", "target", "sigma", "patch")))
