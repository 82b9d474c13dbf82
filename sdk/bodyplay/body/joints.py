"""The joint set every tracker, the synthetic truth and every file use (DESIGN.md).

Positions are world metres, Y up, floor at Y = 0. ``pelvis`` is the midpoint of the
hip centres, ``neck`` the midpoint of the shoulder centres, ``spine``/``chest`` one
and two thirds of the way from pelvis to neck, ``head`` the centre of the head.
"""

from __future__ import annotations

__all__ = ["JOINT_NAMES", "UPPER_BODY", "JOINT_INDEX", "JOINT_PARENTS", "BONES", "NUM_JOINTS"]

JOINT_NAMES: tuple[str, ...] = (
    "pelvis",
    "spine",
    "chest",
    "neck",
    "head",
    "l_shoulder",
    "l_elbow",
    "l_wrist",
    "r_shoulder",
    "r_elbow",
    "r_wrist",
    "l_hip",
    "l_knee",
    "l_ankle",
    "r_hip",
    "r_knee",
    "r_ankle",
)
"""The 17 output joints, in the order of every (..., 17, 3) array bodyplay returns."""

NUM_JOINTS = len(JOINT_NAMES)

UPPER_BODY: tuple[str, ...] = JOINT_NAMES[:11]
"""The first eleven joints: what an upper-body tracker (the color shirt) reports."""

JOINT_INDEX: dict[str, int] = {name: i for i, name in enumerate(JOINT_NAMES)}

JOINT_PARENTS: dict[str, str | None] = {
    "pelvis": None,
    "spine": "pelvis",
    "chest": "spine",
    "neck": "chest",
    "head": "neck",
    "l_shoulder": "neck",
    "l_elbow": "l_shoulder",
    "l_wrist": "l_elbow",
    "r_shoulder": "neck",
    "r_elbow": "r_shoulder",
    "r_wrist": "r_elbow",
    "l_hip": "pelvis",
    "l_knee": "l_hip",
    "l_ankle": "l_knee",
    "r_hip": "pelvis",
    "r_knee": "r_hip",
    "r_ankle": "r_knee",
}
"""Parent of each output joint, for drawing stick figures."""

BONES: tuple[tuple[str, str], ...] = tuple(
    (parent, child) for child, parent in JOINT_PARENTS.items() if parent is not None
)
"""(parent, child) pairs of the stick figure drawn by overlays and viewers."""
