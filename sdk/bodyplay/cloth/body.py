"""The body the cloth sees: collision capsules and attachment frames built from 17 joints.

Every capsule runs between two points that are fixed blends of the joints (so they
follow any tracker's skeleton) and has a radius that is a fraction of the player's
height, like the colliders of :mod:`bodyplay.physics` (whose height estimate from the
torso, :func:`~bodyplay.physics.options.estimate_height`, it reuses). The torso is two
side-by-side capsules (an oval cross-section, 0.34 m wide and 0.22 m deep for a
1.75 m body) plus a shoulder bar and a hip bar for a garment to hang on; limbs are one
capsule each, hands and head spheres. Frames (``torso``: origin at the neck, x to the
left shoulder, y up the spine, z forward; ``hips``: origin at the pelvis, x to the left
hip) carry the garments' pinned particles.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX, NUM_JOINTS
from bodyplay.physics.options import estimate_height

__all__ = ["CAPSULE_NAMES", "FRAME_NAMES", "BodyCapsules", "body_capsules", "body_frames"]

_REFERENCE_HEIGHT = 1.75

# name, endpoint a, endpoint b (joint -> weight), radius in metres for a 1.75 m body
_SPECS: tuple[tuple[str, dict[str, float], dict[str, float], float], ...] = (
    ("head", {"head": 1.0}, {"head": 1.0}, 0.10),
    ("neck", {"neck": 1.0}, {"head": 0.6, "neck": 0.4}, 0.055),
    ("torso_l", {"pelvis": 0.33, "l_hip": 0.67},
     {"neck": 0.56, "l_shoulder": 0.32, "pelvis": 0.12}, 0.11),
    ("torso_r", {"pelvis": 0.33, "r_hip": 0.67},
     {"neck": 0.56, "r_shoulder": 0.32, "pelvis": 0.12}, 0.11),
    ("shoulders", {"l_shoulder": 1.0}, {"r_shoulder": 1.0}, 0.055),
    ("hips", {"l_hip": 1.0}, {"r_hip": 1.0}, 0.10),
    ("l_upper_arm", {"l_shoulder": 1.0}, {"l_elbow": 1.0}, 0.05),
    ("l_forearm", {"l_elbow": 1.0}, {"l_wrist": 1.0}, 0.04),
    ("l_hand", {"l_wrist": 1.3, "l_elbow": -0.3}, {"l_wrist": 1.3, "l_elbow": -0.3}, 0.05),
    ("r_upper_arm", {"r_shoulder": 1.0}, {"r_elbow": 1.0}, 0.05),
    ("r_forearm", {"r_elbow": 1.0}, {"r_wrist": 1.0}, 0.04),
    ("r_hand", {"r_wrist": 1.3, "r_elbow": -0.3}, {"r_wrist": 1.3, "r_elbow": -0.3}, 0.05),
    ("l_thigh", {"l_hip": 1.0}, {"l_knee": 1.0}, 0.075),
    ("l_shin", {"l_knee": 1.0}, {"l_ankle": 1.0}, 0.05),
    ("r_thigh", {"r_hip": 1.0}, {"r_knee": 1.0}, 0.075),
    ("r_shin", {"r_knee": 1.0}, {"r_ankle": 1.0}, 0.05),
)

CAPSULE_NAMES: tuple[str, ...] = tuple(s[0] for s in _SPECS)
"""The body's collision capsules, in the order of :class:`BodyCapsules` rows."""

FRAME_NAMES: tuple[str, ...] = ("torso", "hips")
"""Attachment frames a garment's pins can follow (index = the pin's frame id)."""


def _weights(part: int) -> NDArray[np.float64]:
    w = np.zeros((len(_SPECS), NUM_JOINTS))
    for c, (_, wa, wb, _) in enumerate(_SPECS):
        for name, weight in (wa if part == 0 else wb).items():
            w[c, JOINT_INDEX[name]] = weight
    return w


_WA = _weights(0)
_WB = _weights(1)
_RADII = np.array([s[3] for s in _SPECS]) / _REFERENCE_HEIGHT


@dataclass(frozen=True)
class BodyCapsules:
    """Capsules of one pose: endpoints ``a``, ``b`` (C, 3) and ``radius`` (C,) in metres."""

    a: NDArray[np.float64]
    b: NDArray[np.float64]
    radius: NDArray[np.float64]

    def penetration(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """(N,) how deep each point lies inside the deepest capsule (0 outside), metres."""
        ab = self.b - self.a
        ap = points[:, None, :] - self.a[None]
        denom = np.maximum(np.einsum("cd,cd->c", ab, ab), 1e-12)
        t = np.clip(np.einsum("ncd,cd->nc", ap, ab) / denom, 0.0, 1.0)
        q = self.a[None] + t[..., None] * ab[None]
        d = np.linalg.norm(points[:, None, :] - q, axis=2)
        return np.maximum(self.radius[None] - d, 0.0).max(axis=1)


def body_height(joints: NDArray[np.float64]) -> float:
    """Body height (m) estimated from the torso of (17, 3) joints; 1.75 when unknown."""
    h = estimate_height(np.asarray(joints, dtype=np.float64))
    return _REFERENCE_HEIGHT if h is None else float(np.clip(h, 1.0, 2.4))


def body_capsules(joints: NDArray[np.float64], height: float,
                  radius_scale: float = 1.0) -> BodyCapsules:
    """The collision capsules of (17, 3) finite ``joints`` for a body ``height`` m tall."""
    j = np.asarray(joints, dtype=np.float64)
    return BodyCapsules(_WA @ j, _WB @ j, _RADII * height * radius_scale)


def body_frames(joints: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Origins (2, 3) and rotations (2, 3, 3) (columns = axes) of the FRAME_NAMES frames."""
    j = np.asarray(joints, dtype=np.float64)
    up = _unit(j[JOINT_INDEX["neck"]] - j[JOINT_INDEX["pelvis"]], (0.0, 1.0, 0.0))
    origins = np.stack([j[JOINT_INDEX["neck"]], j[JOINT_INDEX["pelvis"]]])
    rots = np.empty((2, 3, 3))
    for f, (left, right) in enumerate((("l_shoulder", "r_shoulder"), ("l_hip", "r_hip"))):
        x = j[JOINT_INDEX[left]] - j[JOINT_INDEX[right]]
        x = _unit(x - up * float(x @ up), _perpendicular(up))
        z = np.cross(x, up)
        rots[f] = np.stack([x, up, z], axis=1)
    return origins, rots


def _unit(v: NDArray[np.float64], fallback: tuple[float, float, float] | NDArray[np.float64]
          ) -> NDArray[np.float64]:
    n = float(np.linalg.norm(v))
    return v / n if n > 1e-9 else np.asarray(fallback, dtype=np.float64)


def _perpendicular(up: NDArray[np.float64]) -> NDArray[np.float64]:
    x = np.array([1.0, 0.0, 0.0]) - up * up[0]
    return _unit(x, (0.0, 0.0, 1.0))
