"""Vectorized rotation helpers (rotation vectors <-> matrices) used by kinematics.

Rotation vectors (axis times angle, radians) are the pose parameterization; these
functions work on any leading batch shape and never loop in Python (numba kernels:
the IK converts a few matrices many times per frame, where scipy's ``Rotation``
spent more time on its checks than on the arithmetic).
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["rotvec_to_matrix", "matrix_to_rotvec", "rotation_between", "rodrigues_into"]


@numba.njit(cache=True, nogil=True, inline="always")
def rodrigues_into(  # pragma: no cover - compiled
    rx: float, ry: float, rz: float, out: NDArray[np.float64]
) -> None:
    """Rodrigues' formula for one rotation vector into the 3x3 ``out`` (numba only).

    Below 1e-8 rad the first-order expansion keeps the map smooth at zero. The one
    implementation behind :func:`rotvec_to_matrix`, the skeleton's forward
    kinematics and the color-shirt IK's anchor projection.
    """
    th = np.sqrt(rx * rx + ry * ry + rz * rz)
    if th < 1e-8:
        out[0, 0], out[0, 1], out[0, 2] = 1.0, -rz, ry
        out[1, 0], out[1, 1], out[1, 2] = rz, 1.0, -rx
        out[2, 0], out[2, 1], out[2, 2] = -ry, rx, 1.0
        return
    kx, ky, kz = rx / th, ry / th, rz / th
    s = np.sin(th)
    c = 1.0 - np.cos(th)
    out[0, 0] = 1.0 - c * (ky * ky + kz * kz)
    out[0, 1] = -s * kz + c * kx * ky
    out[0, 2] = s * ky + c * kx * kz
    out[1, 0] = s * kz + c * kx * ky
    out[1, 1] = 1.0 - c * (kx * kx + kz * kz)
    out[1, 2] = -s * kx + c * ky * kz
    out[2, 0] = -s * ky + c * kx * kz
    out[2, 1] = s * kx + c * ky * kz
    out[2, 2] = 1.0 - c * (kx * kx + ky * ky)


@numba.njit(cache=True, nogil=True)
def _rotvec_to_matrix_kernel(  # pragma: no cover - compiled
    r: NDArray[np.float64], out: NDArray[np.float64]
) -> None:
    for n in range(r.shape[0]):
        rodrigues_into(r[n, 0], r[n, 1], r[n, 2], out[n])


@numba.njit(cache=True, nogil=True)
def _matrix_to_rotvec_kernel(  # pragma: no cover - compiled
    m: NDArray[np.float64], out: NDArray[np.float64]
) -> None:
    # Shepperd's method: the quaternion from the largest of its four squared
    # components, stable for every angle including pi
    for n in range(m.shape[0]):
        tr = m[n, 0, 0] + m[n, 1, 1] + m[n, 2, 2]
        d0, d1, d2 = m[n, 0, 0], m[n, 1, 1], m[n, 2, 2]
        if tr >= d0 and tr >= d1 and tr >= d2:
            w = 0.5 * np.sqrt(max(1.0 + tr, 0.0))
            f = 0.25 / w
            x = (m[n, 2, 1] - m[n, 1, 2]) * f
            y = (m[n, 0, 2] - m[n, 2, 0]) * f
            z = (m[n, 1, 0] - m[n, 0, 1]) * f
        elif d0 >= d1 and d0 >= d2:
            x = 0.5 * np.sqrt(max(1.0 + d0 - d1 - d2, 0.0))
            f = 0.25 / x
            w = (m[n, 2, 1] - m[n, 1, 2]) * f
            y = (m[n, 0, 1] + m[n, 1, 0]) * f
            z = (m[n, 0, 2] + m[n, 2, 0]) * f
        elif d1 >= d2:
            y = 0.5 * np.sqrt(max(1.0 + d1 - d0 - d2, 0.0))
            f = 0.25 / y
            w = (m[n, 0, 2] - m[n, 2, 0]) * f
            x = (m[n, 0, 1] + m[n, 1, 0]) * f
            z = (m[n, 1, 2] + m[n, 2, 1]) * f
        else:
            z = 0.5 * np.sqrt(max(1.0 + d2 - d0 - d1, 0.0))
            f = 0.25 / z
            w = (m[n, 1, 0] - m[n, 0, 1]) * f
            x = (m[n, 0, 2] + m[n, 2, 0]) * f
            y = (m[n, 1, 2] + m[n, 2, 1]) * f
        if w < 0.0:
            w, x, y, z = -w, -x, -y, -z
        v = np.sqrt(x * x + y * y + z * z)
        # tiny angle: the rotation vector is twice the vector part
        k = 2.0 if v < 1e-12 else 2.0 * np.arctan2(v, w) / v
        out[n, 0] = k * x
        out[n, 1] = k * y
        out[n, 2] = k * z


def rotvec_to_matrix(rotvec: ArrayLike) -> NDArray[np.float64]:
    """Rodrigues' formula: (..., 3) rotation vectors to (..., 3, 3) matrices."""
    r = np.asarray(rotvec, dtype=np.float64)
    flat = np.ascontiguousarray(r.reshape(-1, 3))
    out = np.empty((flat.shape[0], 3, 3))
    _rotvec_to_matrix_kernel(flat, out)
    return out.reshape(r.shape[:-1] + (3, 3))


def matrix_to_rotvec(matrix: ArrayLike) -> NDArray[np.float64]:
    """(..., 3, 3) rotation matrices to (..., 3) rotation vectors (angle in [0, pi])."""
    m = np.asarray(matrix, dtype=np.float64)
    flat = np.ascontiguousarray(m.reshape(-1, 3, 3))
    out = np.empty((flat.shape[0], 3))
    _matrix_to_rotvec_kernel(flat, out)
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
