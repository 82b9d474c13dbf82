"""From a frame's fitted pose to the typed result games read: joints, states, extras
(legs ``lost``; a joint ``tracked`` when a patch of its bones, or the head cue, was seen)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX, JOINT_NAMES, NUM_JOINTS, UPPER_BODY
from bodyplay.body.shirt import PATCHES
from bodyplay.body.skeleton import Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.capture.frames import FrameSet
from bodyplay.trackers.base import JointState, TrackResult
from bodyplay.trackers.colorshirt.head import HEAD_PATCH, HeadPoint, head_from_cue
from bodyplay.trackers.colorshirt.options import ColorShirtOptions
from bodyplay.trackers.colorshirt.views import CameraView

__all__ = ["pose_result"]

_TORSO = {p.id for p in PATCHES if p.bone in ("thorax", "lumbar")}
_JOINT_PATCHES: dict[str, set[int]] = {
    "l_shoulder": {p.id for p in PATCHES if p.bone in ("l_clavicle", "l_shoulder")},
    "r_shoulder": {p.id for p in PATCHES if p.bone in ("r_clavicle", "r_shoulder")},
    "l_elbow": {p.id for p in PATCHES if p.bone in ("l_shoulder", "l_elbow")},
    "r_elbow": {p.id for p in PATCHES if p.bone in ("r_shoulder", "r_elbow")},
    "l_wrist": {p.id for p in PATCHES if p.bone == "l_elbow"},
    "r_wrist": {p.id for p in PATCHES if p.bone == "r_elbow"},
}


def pose_result(frames: FrameSet, skeleton: Skeleton, q: NDArray[np.float64], seen: set[int],
                views: Sequence[CameraView], cameras: Sequence[Camera],
                heads: Sequence[tuple[int, HeadPoint]], options: ColorShirtOptions,
                ms: float, extras: dict[str, object]) -> TrackResult:
    """The :class:`TrackResult` of a frame fitted to pose ``q``; ``seen``: the patch
    ids anchored (``HEAD_PATCH`` for the head cue), ``heads``: the heads found;
    ``extras`` gains the cameras used, the mismatch, the classified crops and heads."""
    joints = np.full((NUM_JOINTS, 3), np.nan)
    n_up = len(UPPER_BODY)
    joints[:n_up] = skeleton.joint_positions(q)[:n_up]
    head = head_from_cue(skeleton, q, cameras, heads, options)
    if head is not None:
        joints[JOINT_INDEX["head"]] = head
    torso_seen = len(seen & _TORSO) >= 2
    match = 1.0 - min(v.distance for v in views)
    state: list[JointState] = []
    conf = np.zeros(NUM_JOINTS)
    for j, name in enumerate(JOINT_NAMES):
        if j >= n_up:
            state.append("lost")
            continue
        if name in _JOINT_PATCHES:
            tracked = bool(seen & _JOINT_PATCHES[name])
        elif name == "head":
            tracked = HEAD_PATCH in seen  # seen above the collar, else the blend's
        else:
            tracked = torso_seen
        state.append("tracked" if tracked else "inferred")
        conf[j] = (0.9 if tracked else 0.4) * match
    extras = {"cameras_used": [v.index for v in views], "mismatch": 1.0 - match,
              "classified": [(v.index, v.window, v.ids) for v in views],
              "heads": list(heads), **extras}
    return TrackResult(frames.index, frames.t, joints, tuple(state), conf, ms, q, extras=extras)
