"""Feet on the floor: analytic two-bone leg IK for a body that crouched or stepped.

When a reach lowers the pelvis (a crouch) or moves it sideways (a step), the legs
must follow or the feet sink through the floor and slide. :func:`plant_feet`
re-solves both legs so the ankles land where they should: for a crouch, where they
stood; for a step, the leading foot (on the side the body moves to) steps by the
whole shift, the trailing foot stays planted unless the leg cannot reach its old
spot, in which case it is dragged along just enough (97% of the leg's length).
Each leg is solved in closed form: the knee flexion from the law of cosines on the
hip-ankle distance, then the smallest hip rotation that swings the ankle onto its
target (so the knee keeps pointing the way it did), all inside the joint limits.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.rotations import matrix_to_rotvec, rotation_between, rotvec_to_matrix
from bodyplay.body.skeleton import NODE_NAMES, Skeleton

__all__ = ["LEG_INDICES", "leg_reach", "plant_feet", "solve_leg"]

_N = {name: i for i, name in enumerate(NODE_NAMES)}
_REACH = 0.97  # a planted leg straightens to at most this share of its length


def _rot(node: str) -> slice:
    i = 3 + 3 * _N[node]
    return slice(i, i + 3)


LEG_INDICES: NDArray[np.int64] = np.array(
    [3 + 3 * _N[n] + a for n in ("l_hip", "l_knee", "r_hip", "r_knee") for a in range(3)],
    dtype=np.int64,
)
"""Pose-vector components :func:`plant_feet` sets (hip and knee rotations)."""


def leg_reach(skeleton: Skeleton, side: str) -> float:
    """How far (m) a planted ``side`` leg reaches from hip to ankle: 97% of its length."""
    o = skeleton.offsets
    return _REACH * float(np.linalg.norm(o[_N[f"{side}_knee"]])
                          + np.linalg.norm(o[_N[f"{side}_ankle"]]))


def solve_leg(
    skeleton: Skeleton, pose: NDArray[np.float64], side: str, ankle: NDArray[np.float64]
) -> NDArray[np.float64]:
    """``pose`` with the ``side`` ("l" or "r") hip and knee turned so the ankle centre
    reaches ``ankle`` (world metres), or gets as close as the leg allows."""
    q = pose.copy()
    hip, knee, foot = f"{side}_hip", f"{side}_knee", f"{side}_ankle"
    l1 = float(np.linalg.norm(skeleton.offsets[_N[knee]]))
    l2 = float(np.linalg.norm(skeleton.offsets[_N[foot]]))
    f = skeleton.forward(q)
    h = f[_N[hip], :3, 3]
    d = float(np.linalg.norm(ankle - h))
    d = min(max(d, abs(l1 - l2) + 1e-3), l1 + l2 - 1e-6)
    cos_inner = (l1 * l1 + l2 * l2 - d * d) / (2.0 * l1 * l2)
    q[_rot(knee)] = (math.pi - math.acos(min(max(cos_inner, -1.0), 1.0)), 0.0, 0.0)
    q = skeleton.clamp(q)
    f = skeleton.forward(q)
    a = f[_N[foot], :3, 3]
    turn = rotation_between(a - h, ankle - h)
    parent = f[0, :3, :3]  # the hips hang from the pelvis
    local = rotvec_to_matrix(q[_rot(hip)])
    q[_rot(hip)] = matrix_to_rotvec(parent.T @ turn @ parent @ local)
    return skeleton.clamp(q)


def plant_feet(
    skeleton: Skeleton,
    base: NDArray[np.float64],
    pose: NDArray[np.float64],
    left: NDArray[np.float64],
) -> NDArray[np.float64]:
    """``pose`` (``base`` crouched and/or stepped) with legs re-solved: feet where
    ``base`` had them, the leading one moved by the horizontal step (``left`` is the
    body's unit left axis, to tell which foot leads)."""
    ia, ib = _N["l_ankle"], _N["r_ankle"]
    nodes = skeleton.node_positions(np.stack([base, pose]))
    feet = {"l": nodes[0, ia].copy(), "r": nodes[0, ib].copy()}
    step = pose[:3] - base[:3]
    step[1] = 0.0
    q = pose.copy()
    if float(np.linalg.norm(step)) > 1e-4:
        lead = "l" if float(step @ left) > 0 else "r"
        trail = "r" if lead == "l" else "l"
        feet[lead] = feet[lead] + step
        # the trailing foot stays unless its leg cannot reach: then the smallest drag
        length = leg_reach(skeleton, trail)
        hip = nodes[1, _N[f"{trail}_hip"]]
        rel = feet[trail] - hip
        if float(np.linalg.norm(rel)) > length:
            # |rel + a * step| = length, smallest a in 0..1
            aa, bb, cc = float(step @ step), 2.0 * float(rel @ step), float(rel @ rel) - length**2
            disc = bb * bb - 4.0 * aa * cc
            alpha = 1.0 if disc < 0 else (-bb - math.sqrt(disc)) / (2.0 * aa)
            feet[trail] = feet[trail] + min(max(alpha, 0.0), 1.0) * step
    for side in ("l", "r"):
        q = solve_leg(skeleton, q, side, feet[side])
    return q
