"""The pose of a player turned away from the camera: the front pose reflected.

A silhouette does not tell front from back: the tree holds only poses facing the
camera (within ``max_yaw_deg``), so a player filmed from behind is matched by the
front-facing pose with the same silhouette, which is the player mirrored (left and
right swapped, the chest towards the camera). The back-facing pose with that
silhouette is the front pose with its depth reflected about the root and its left
and right joints swapped (turned 180 degrees about the vertical, then mirrored).

Depth here is the horizontal distance along the line of sight through the pelvis
(the level virtual camera's axis, not the real camera's, which may look down: a
reflection along a tilted axis would lean a standing body). Each joint moves
*along its own ray* from the camera centre to the reflected depth, so every joint
projects exactly where it did (the silhouette, the template and the IoU are those
of the front pose; from a camera well above the player a joint moved along its
ray also rises or sinks); the pose vector is the mirror image of the front pose
through the vertical plane at the pelvis across the line of sight (heights kept;
the two agree seen from above, within the perspective of the body's depth). The
filter keeps tracking in the tree's front-facing space; only what is reported is
reflected (``SilhouetteOptions.facing``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from bodyplay.body.joints import JOINT_INDEX, JOINT_NAMES
from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.trackers.base import JointState

__all__ = ["LR_SWAP", "reflect_joints", "reflect_output", "reflect_pose", "sight_normal"]

LR_SWAP: NDArray[np.int64] = np.array(
    [JOINT_INDEX[("r_" if n[0] == "l" else "l_") + n[2:]] if n.startswith(("l_", "r_"))
     else i for i, n in enumerate(JOINT_NAMES)], np.int64)
"""Index of each joint's left/right partner (itself for the middle joints): the
reflected pose's joint ``j`` is the front pose's joint ``LR_SWAP[j]``."""

_PELVIS = JOINT_INDEX["pelvis"]


def sight_normal(center: NDArray[np.float64], root: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit horizontal direction from the camera centre to the root (world, Y up)."""
    d = np.asarray(root, np.float64) - np.asarray(center, np.float64)
    d = np.array([d[0], 0.0, d[2]])
    n = float(np.linalg.norm(d))
    if n < 1e-6:
        raise ConfigError("the body stands under the camera: no line of sight to reflect along")
    return d / n


def reflect_joints(joints: NDArray[np.float64], center: NDArray[np.float64]
                   ) -> NDArray[np.float64]:
    """The back-facing joints (17, 3) with the same projection as ``joints``.

    Every joint P moves along its ray from the camera centre C to the depth
    ``2 z_root - z`` (z: the horizontal distance along the line of sight to the
    pelvis), then left and right joints are swapped (:data:`LR_SWAP`). Non-finite
    joints stay non-finite."""
    J = np.asarray(joints, np.float64)
    C = np.asarray(center, np.float64)
    s = sight_normal(C, J[_PELVIS])
    rel = J - C
    z = rel @ s
    zr = float(rel[_PELVIS] @ s)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(z > 1e-6, (2.0 * zr - z) / z, np.nan)
    out = C + rel * k[:, None]
    return np.asarray(out[LR_SWAP])


def reflect_pose(skeleton: Skeleton, pose: NDArray[np.float64], pelvis: NDArray[np.float64],
                 center: NDArray[np.float64]) -> NDArray[np.float64]:
    """The pose vector mirrored through the vertical plane at ``pelvis`` across the
    line of sight from ``center``: left and right nodes swapped with mirrored
    rotations (:func:`.poses.mirror_poses`), the root's orientation R turned into
    H R D (H the reflection through that plane, D = diag(-1, 1, 1) the body's own
    mirror) and its position reflected through the plane."""
    from bodyplay.trackers.silhouette.poses import mirror_poses

    q = np.asarray(pose, np.float64)
    s = sight_normal(np.asarray(center, np.float64), np.asarray(pelvis, np.float64))
    H = np.eye(3) - 2.0 * np.outer(s, s)
    out = mirror_poses(skeleton, q)
    root = q[0:3]
    out[0:3] = root - 2.0 * s * float((root - np.asarray(pelvis, np.float64)) @ s)
    R = Rotation.from_rotvec(q[3:6]).as_matrix()
    out[3:6] = Rotation.from_matrix(H @ R @ np.diag([-1.0, 1.0, 1.0])).as_rotvec()
    return out


def reflect_output(skeleton: Skeleton, joints: NDArray[np.float64], pose: NDArray[np.float64],
                   states: tuple[JointState, ...], confidence: NDArray[np.float64],
                   center: NDArray[np.float64]
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64], tuple[JointState, ...],
                              NDArray[np.float64]]:
    """A frame's output turned to face away: the joints (:func:`reflect_joints`), the
    pose vector (:func:`reflect_pose`, at the front pose's pelvis), and each joint's
    state and confidence taken from its left/right partner."""
    J = np.asarray(joints, np.float64)
    return (reflect_joints(J, center), reflect_pose(skeleton, pose, J[_PELVIS], center),
            tuple(states[k] for k in LR_SWAP), np.asarray(confidence)[LR_SWAP])
