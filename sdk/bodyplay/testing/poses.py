"""Named key poses and gesture motions for scripted players (data, not code paths).

Key poses are node rotations on the :class:`~bodyplay.body.skeleton.Skeleton` (rest
pose: T-pose facing +Z, the person's left on +X). A gesture motion is a short list of
``(seconds, key pose name)`` steps, interpolated, or the name / path of a mocap clip.
Games and tests may pass their own tables to :class:`~bodyplay.testing.Timeline`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError

__all__ = ["KEY_POSES", "GESTURE_MOTIONS", "key_pose", "resolve_pose", "grounded"]

_ARMS_DOWN = {"l_shoulder": (0.0, 0.0, -1.4), "r_shoulder": (0.0, 0.0, 1.4)}

KEY_POSES: dict[str, dict[str, Any]] = {
    "t_pose": {},
    "idle": {"rotations": _ARMS_DOWN},
    "right_hand_up": {"rotations": {**_ARMS_DOWN, "r_shoulder": (0.0, 0.0, -1.5)}},
    "left_hand_up": {"rotations": {**_ARMS_DOWN, "l_shoulder": (0.0, 0.0, 1.5)}},
    "both_hands_up": {"rotations": {"l_shoulder": (0.0, 0.0, 1.5), "r_shoulder": (0.0, 0.0, -1.5)}},
    "right_punch": {"rotations": {**_ARMS_DOWN, "r_shoulder": (0.0, 1.5, 0.0)}},
    "left_punch": {"rotations": {**_ARMS_DOWN, "l_shoulder": (0.0, -1.5, 0.0)}},
    "right_guard": {
        "rotations": {**_ARMS_DOWN, "r_shoulder": (0.0, 0.9, 0.9), "r_elbow": (0.0, 1.8, 0.0)}
    },
    "left_guard": {
        "rotations": {**_ARMS_DOWN, "l_shoulder": (0.0, -0.9, -0.9), "l_elbow": (0.0, -1.8, 0.0)}
    },
    "right_wave_out": {
        "rotations": {**_ARMS_DOWN, "r_shoulder": (0.0, 0.0, -1.0), "r_elbow": (0.0, 0.4, 0.0)}
    },
    "right_wave_in": {
        "rotations": {**_ARMS_DOWN, "r_shoulder": (0.0, 0.0, -1.5), "r_elbow": (0.0, 0.4, 0.0)}
    },
    "left_wave_out": {
        "rotations": {**_ARMS_DOWN, "l_shoulder": (0.0, 0.0, 1.0), "l_elbow": (0.0, -0.4, 0.0)}
    },
    "left_wave_in": {
        "rotations": {**_ARMS_DOWN, "l_shoulder": (0.0, 0.0, 1.5), "l_elbow": (0.0, -0.4, 0.0)}
    },
    "squat": {
        "rotations": {
            **_ARMS_DOWN,
            "l_hip": (-1.3, 0.0, 0.0),
            "r_hip": (-1.3, 0.0, 0.0),
            "l_knee": (1.9, 0.0, 0.0),
            "r_knee": (1.9, 0.0, 0.0),
            "l_ankle": (-0.6, 0.0, 0.0),
            "r_ankle": (-0.6, 0.0, 0.0),
            "lumbar": (0.5, 0.0, 0.0),
        },
        "grounded": True,
    },
    "jump": {"rotations": {"l_shoulder": (0.0, 0.0, 1.2), "r_shoulder": (0.0, 0.0, -1.2)},
             "lift": 0.3},
    # The ninja's five motions (single-camera silhouette paper, section 4).
    "hit_up": {"rotations": {**_ARMS_DOWN, "r_shoulder": (0.0, 0.5, -1.9),
                             "r_elbow": (0.0, 0.3, 0.0)}},
    "double_up": {"rotations": {"l_shoulder": (0.0, -0.6, 2.0), "r_shoulder": (0.0, 0.6, -2.0),
                                "l_elbow": (0.0, -0.3, 0.0), "r_elbow": (0.0, 0.3, 0.0)}},
    "double_down": {"rotations": {"l_shoulder": (0.0, -0.9, -0.9),
                                  "r_shoulder": (0.0, 0.9, 0.9)}},
    "arms_out": {"rotations": {"l_shoulder": (0.0, 0.0, -0.1), "r_shoulder": (0.0, 0.0, 0.1)}},
    "arms_folded": {"rotations": {"l_shoulder": (0.0, -1.0, -1.3), "l_elbow": (0.0, -2.4, 0.0),
                                  "r_shoulder": (0.0, 1.0, 1.3), "r_elbow": (0.0, 2.4, 0.0)}},
    "straddle_left": {"rotations": {**_ARMS_DOWN, "l_hip": (0.0, 0.0, 0.3),
                                    "r_hip": (0.0, 0.0, -0.3)},
                      "grounded": True, "shift": (0.25, 0.0)},
    "idle_left": {"rotations": _ARMS_DOWN, "shift": (0.5, 0.0)},
    "straddle_right": {"rotations": {**_ARMS_DOWN, "l_hip": (0.0, 0.0, 0.3),
                                     "r_hip": (0.0, 0.0, -0.3)},
                       "grounded": True, "shift": (-0.25, 0.0)},
    "idle_right": {"rotations": _ARMS_DOWN, "shift": (-0.5, 0.0)},
}
"""Key poses by name: node rotations, ``grounded`` (lower the body until the lower
ankle rests at its standing height), ``lift`` (metres off the floor) and ``shift``
(x, z metres along the floor; +x is the person's left)."""

GESTURE_MOTIONS: dict[str, Sequence[tuple[float, str]] | str] = {
    "raise_right_hand": ((0.0, "idle"), (0.5, "right_hand_up"), (1.0, "right_hand_up"),
                         (1.5, "idle")),
    "raise_left_hand": ((0.0, "idle"), (0.5, "left_hand_up"), (1.0, "left_hand_up"),
                        (1.5, "idle")),
    "raise_both_hands": ((0.0, "idle"), (0.5, "both_hands_up"), (1.0, "both_hands_up"),
                         (1.5, "idle")),
    "punch_right": ((0.0, "right_guard"), (0.15, "right_punch"), (0.35, "right_guard")),
    "punch_left": ((0.0, "left_guard"), (0.15, "left_punch"), (0.35, "left_guard")),
    "wave_right": ((0.0, "idle"), (0.4, "right_wave_out"), (0.7, "right_wave_in"),
                   (1.0, "right_wave_out"), (1.3, "right_wave_in"), (1.6, "right_wave_out"),
                   (2.0, "idle")),
    "wave_left": ((0.0, "idle"), (0.4, "left_wave_out"), (0.7, "left_wave_in"),
                  (1.0, "left_wave_out"), (1.3, "left_wave_in"), (1.6, "left_wave_out"),
                  (2.0, "idle")),
    "squat": ((0.0, "idle"), (0.6, "squat"), (1.0, "squat"), (1.6, "idle")),
    "jump": ((0.0, "idle"), (0.2, "squat"), (0.45, "jump"), (0.7, "idle")),
    # The ninja's five motions, performed as the built-in gestures of the same names
    # expect them; step_left / step_right end 0.5 m to the side.
    "transfigure": ((0.0, "idle"), (0.5, "arms_out"), (0.9, "arms_out"), (1.3, "arms_folded"),
                    (1.8, "arms_folded"), (2.3, "idle")),
    "crouch": ((0.0, "idle"), (0.4, "squat"), (0.8, "squat"), (1.2, "idle")),
    "step_left": ((0.0, "idle"), (0.3, "straddle_left"), (0.6, "idle_left")),
    "step_right": ((0.0, "idle"), (0.3, "straddle_right"), (0.6, "idle_right")),
    "hit": ((0.0, "idle"), (0.35, "hit_up"), (0.5, "hit_up"), (0.8, "idle")),
    "double_hit": ((0.0, "idle"), (0.4, "double_up"), (0.6, "double_up"), (0.85, "double_down"),
                   (1.1, "idle")),
}
"""Named gestures as key-pose sequences ``(seconds from the gesture's start, pose)``."""


def grounded(skeleton: Skeleton, pose: NDArray[np.float64]) -> NDArray[np.float64]:
    """The pose moved vertically so its lower ankle is at the standing ankle height."""
    rest = skeleton.joint_positions(skeleton.rest_pose())
    j = skeleton.joint_positions(pose)
    ia, ib = JOINT_INDEX["l_ankle"], JOINT_INDEX["r_ankle"]
    out = pose.copy()
    out[1] += min(rest[ia, 1], rest[ib, 1]) - min(j[ia, 1], j[ib, 1])
    return out


def key_pose(
    name: str, skeleton: Skeleton, table: Mapping[str, Mapping[str, Any]] = KEY_POSES
) -> NDArray[np.float64]:
    """The pose vector of a named key pose at the origin, facing +Z."""
    spec = table.get(name)
    if spec is None:
        raise ConfigError(f"unknown key pose {name!r}; known: {', '.join(sorted(table))}")
    q = skeleton.pose(rotations=dict(spec.get("rotations", {})))
    if spec.get("grounded"):
        q = grounded(skeleton, q)
    q[1] += float(spec.get("lift", 0.0))
    shift = spec.get("shift")
    if shift is not None:
        q[0] += float(shift[0])
        q[2] += float(shift[1])
    return q


def resolve_pose(
    pose: Any, skeleton: Skeleton, table: Mapping[str, Mapping[str, Any]] = KEY_POSES
) -> NDArray[np.float64]:
    """A pose vector from a key-pose name, a dict of node rotations, or a vector."""
    if isinstance(pose, str):
        return key_pose(pose, skeleton, table)
    if isinstance(pose, Mapping):
        return skeleton.pose(rotations=dict(pose))
    q = np.asarray(pose, dtype=np.float64).reshape(-1)
    if q.shape != (skeleton.pose_dim,):
        raise ConfigError(
            f"a key pose must be a name, a rotation dict or a vector of {skeleton.pose_dim} "
            f"numbers, got shape {q.shape}"
        )
    return q
