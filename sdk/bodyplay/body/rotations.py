"""Vectorized rotation helpers (rotation vectors <-> matrices) used by kinematics.

Rotation vectors (axis times angle, radians) are the pose parameterization; these
functions work on any leading batch shape and never loop in Python.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["rotvec_to_matrix", "matrix_to_rotvec", "rotation_between"]


def rotvec_to_matrix(rotvec: ArrayLike) -> NDArray[np.float64]:
    """Rodrigues' formula: (..., 3) rotation vectors to (..., 3, 3) matrices."""
    r = np.asarray(rotvec, dtype=np.float64)
    theta = np.linalg.norm(r, axis=-1, keepdims=True)
    small = theta < 1e-8
    safe = np.where(small, 1.0, theta)
    k = r / safe
    kx, ky, kz = k[..., 0], k[..., 1], k[..., 2]
    zeros = np.zeros_like(kx)
    K = np.stack(
        [
            np.stack([zeros, -kz, ky], axis=-1),
            np.stack([kz, zeros, -kx], axis=-1),
            np.stack([-ky, kx, zeros], axis=-1),
        ],
        axis=-2,
    )
    s = np.sin(theta)[..., None]
    c = (1.0 - np.cos(theta))[..., None]
    eye = np.broadcast_to(np.eye(3), K.shape)
    R = eye + s * K + c * (K @ K)
    # first-order expansion for tiny angles keeps the map smooth at zero
    Kr = np.stack(
        [
            np.stack([zeros, -r[..., 2], r[..., 1]], axis=-1),
            np.stack([r[..., 2], zeros, -r[..., 0]], axis=-1),
            np.stack([-r[..., 1], r[..., 0], zeros], axis=-1),
        ],
        axis=-2,
    )
    return np.where(small[..., None], eye + Kr, R)


def matrix_to_rotvec(matrix: ArrayLike) -> NDArray[np.float64]:
    """(..., 3, 3) rotation matrices to (..., 3) rotation vectors (angle in [0, pi])."""
    from scipy.spatial.transform import Rotation

    m = np.asarray(matrix, dtype=np.float64)
    flat = m.reshape(-1, 3, 3)
    out = Rotation.from_matrix(flat).as_rotvec()
    return out.reshape(m.shape[:-2] + (3,))


def rotation_between(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """The smallest rotation (as (..., 3, 3) matrices) taking direction a onto direction b."""
    ua = np.asarray(a, dtype=np.float64)
    ub = np.asarray(b, dtype=np.float64)
    ua = ua / np.maximum(np.linalg.norm(ua, axis=-1, keepdims=True), 1e-12)
    ub = ub / np.maximum(np.linalg.norm(ub, axis=-1, keepdims=True), 1e-12)
    axis = np.cross(ua, ub)
    sin = np.linalg.norm(axis, axis=-1, keepdims=True)
    cos = np.sum(ua * ub, axis=-1, keepdims=True)
    angle = np.arctan2(sin, cos)
    # antiparallel: rotate by pi about any axis orthogonal to a
    ortho = np.cross(ua, np.array([1.0, 0.0, 0.0]))
    ortho_alt = np.cross(ua, np.array([0.0, 1.0, 0.0]))
    ortho = np.where(np.linalg.norm(ortho, axis=-1, keepdims=True) < 1e-6, ortho_alt, ortho)
    axis = np.where(sin < 1e-9, ortho, axis)
    axis = axis / np.maximum(np.linalg.norm(axis, axis=-1, keepdims=True), 1e-12)
    return rotvec_to_matrix(axis * angle)
