"""Skinned triangle meshes: rest vertices, skin weights, materials; linear blend skinning.

Both the generic body mesh the trackers render (:mod:`bodyplay.body.mesh`) and the
synthetic actor (:mod:`bodyplay.body.actor`) are :class:`SkinnedMesh` values. A mesh
is modelled in its skeleton's rest T-pose; :meth:`SkinnedMesh.pose` moves it to any
batch of pose vectors with linear blend skinning (each vertex follows a weighted
blend of up to K node transforms ``forward(q) @ inverse(forward(rest))``).

The inner loop is a numba kernel, parallel over the batch: a 4k-triangle mesh skins
in a few microseconds per pose once the forward kinematics are done (see
``benchmarks/bench_skinning.py``).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np
from numba import njit, prange
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError

__all__ = ["Material", "MATERIAL_RGB", "SkinnedMesh", "skinning_transforms"]


class Material(IntEnum):
    """Per-vertex material label of a body mesh (what the surface is made of)."""

    SKIN = 0
    SHIRT = 1
    TROUSERS = 2
    SHOES = 3
    HAIR = 4


MATERIAL_RGB: dict[Material, tuple[int, int, int]] = {
    Material.SKIN: (222, 171, 140),
    Material.SHIRT: (200, 200, 200),
    Material.TROUSERS: (48, 54, 72),
    Material.SHOES: (28, 28, 30),
    Material.HAIR: (62, 44, 32),
}
"""Default sRGB of each material; shirt vertices take their patch color instead."""


@njit(cache=True, fastmath=True)
def _lbs_pose(M, rest, idx, w, out):
    """out[v] = sum_k w[v, k] * M[idx[v, k]] @ [rest[v], 1] for one pose (M is (N, 3, 4))."""
    V = rest.shape[0]
    K = idx.shape[1]
    for v in range(V):
        x = rest[v, 0]
        y = rest[v, 1]
        z = rest[v, 2]
        ox = np.float32(0.0)
        oy = np.float32(0.0)
        oz = np.float32(0.0)
        for k in range(K):
            wk = w[v, k]
            if wk == 0.0:
                continue
            n = idx[v, k]
            ox += wk * (M[n, 0, 0] * x + M[n, 0, 1] * y + M[n, 0, 2] * z + M[n, 0, 3])
            oy += wk * (M[n, 1, 0] * x + M[n, 1, 1] * y + M[n, 1, 2] * z + M[n, 1, 3])
            oz += wk * (M[n, 2, 0] * x + M[n, 2, 1] * y + M[n, 2, 2] * z + M[n, 2, 3])
        out[v, 0] = ox
        out[v, 1] = oy
        out[v, 2] = oz


@njit(cache=True, parallel=True, fastmath=True)
def _lbs_kernel(M, rest, idx, w, out):
    """:func:`_lbs_pose` for every pose of M (B, N, 3, 4), parallel over the batch."""
    for b in prange(M.shape[0]):
        _lbs_pose(M[b], rest, idx, w, out[b])


@njit(cache=True, fastmath=True)
def _lbs_serial(M, rest, idx, w, out):
    """Single-threaded :func:`_lbs_kernel` for small batches (no thread start-up)."""
    for b in range(M.shape[0]):
        _lbs_pose(M[b], rest, idx, w, out[b])


def skinning_transforms(skeleton: Skeleton, poses: ArrayLike) -> NDArray[np.float64]:
    """(..., N, 3, 4) skinning matrices ``forward(q) @ inverse(forward(rest))``."""
    G = skeleton.forward(poses)
    rest = skeleton.forward(skeleton.rest_pose())
    inv_rest = np.linalg.inv(rest)
    return np.einsum("...nij,njk->...nik", G[..., :3, :], inv_rest)


@dataclass(frozen=True, eq=False)
class SkinnedMesh:
    """A triangle mesh bound to a skeleton's rest pose, with skin weights and materials.

    ``rest_vertices`` (V, 3) float32 metres in the rest T-pose; ``faces`` (F, 3) int32
    wound counter-clockwise seen from outside; ``bone_indices``/``bone_weights`` (V, K)
    skeleton node indices and weights (rows sum to 1); ``face_part`` (F,) uint8 shirt
    patch id 1..20 (0 for faces not on the shirt); ``vertex_material`` (V,) uint8
    :class:`Material` labels; ``vertex_rgb`` (V, 3) uint8 base sRGB colors.
    """

    rest_vertices: NDArray[np.float32]
    faces: NDArray[np.int32]
    bone_indices: NDArray[np.int32]
    bone_weights: NDArray[np.float32]
    face_part: NDArray[np.uint8]
    vertex_material: NDArray[np.uint8]
    vertex_rgb: NDArray[np.uint8]

    def __post_init__(self) -> None:
        conv = {
            "rest_vertices": np.float32,
            "faces": np.int32,
            "bone_indices": np.int32,
            "bone_weights": np.float32,
            "face_part": np.uint8,
            "vertex_material": np.uint8,
            "vertex_rgb": np.uint8,
        }
        for name, dtype in conv.items():
            arr = np.ascontiguousarray(np.asarray(getattr(self, name)), dtype=dtype)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        V = self.rest_vertices.shape[0]
        if self.rest_vertices.shape != (V, 3):
            raise ConfigError(f"rest_vertices must be (V, 3), got {self.rest_vertices.shape}")
        if self.faces.ndim != 2 or self.faces.shape[1] != 3:
            raise ConfigError(f"faces must be (F, 3), got {self.faces.shape}")
        if self.faces.size and (self.faces.min() < 0 or self.faces.max() >= V):
            raise ConfigError("faces index vertices that do not exist")
        if self.bone_indices.shape != self.bone_weights.shape or self.bone_indices.shape[0] != V:
            raise ConfigError("bone_indices and bone_weights must both be (V, K)")
        if self.face_part.shape != (self.faces.shape[0],):
            raise ConfigError("face_part must have one entry per face")
        if self.vertex_material.shape != (V,) or self.vertex_rgb.shape != (V, 3):
            raise ConfigError("vertex_material must be (V,) and vertex_rgb (V, 3)")
        sums = self.bone_weights.sum(axis=1)
        if V and not np.allclose(sums, 1.0, atol=1e-3):
            raise ConfigError("skin weights of every vertex must sum to 1")

    @property
    def num_vertices(self) -> int:
        """Number of vertices V."""
        return int(self.rest_vertices.shape[0])

    @property
    def num_faces(self) -> int:
        """Number of triangles F."""
        return int(self.faces.shape[0])

    def dominant_node(self) -> NDArray[np.int32]:
        """(V,) the skeleton node with the largest skin weight of each vertex."""
        k = np.argmax(self.bone_weights, axis=1)
        return self.bone_indices[np.arange(self.num_vertices), k]

    def face_rgb(self) -> NDArray[np.uint8]:
        """(F, 3) sRGB of each face: its patch color on the shirt, else the color of
        a vertex of the face that is not on the shirt (its first one, if none is)."""
        from bodyplay.body.shirt import patch_colors_rgb

        off = self.vertex_material[self.faces] != Material.SHIRT
        pick = np.where(off.any(axis=1), np.argmax(off, axis=1), 0)
        out = self.vertex_rgb[self.faces[np.arange(self.num_faces), pick]].copy()
        on = self.face_part > 0
        out[on] = patch_colors_rgb()[self.face_part[on]]
        return out

    def pose(self, skeleton: Skeleton, poses: ArrayLike) -> NDArray[np.float32]:
        """Skin the mesh: (..., pose_dim) pose vectors -> (..., V, 3) float32 vertices.

        ``skeleton`` must be the one the mesh was built for (its rest pose is the
        mesh's rest pose). Skinning the rest pose returns ``rest_vertices``.
        """
        if int(self.bone_indices.max(initial=0)) >= skeleton.num_nodes:
            raise ConfigError("mesh skin weights reference nodes the skeleton does not have")
        M = skinning_transforms(skeleton, poses)
        batch = M.shape[:-3]
        flat = np.ascontiguousarray(M.reshape((-1,) + M.shape[-3:]), dtype=np.float32)
        out = np.empty((flat.shape[0], self.num_vertices, 3), dtype=np.float32)
        kernel = _lbs_kernel if flat.shape[0] >= 8 else _lbs_serial
        kernel(flat, self.rest_vertices, self.bone_indices, self.bone_weights, out)
        return out.reshape(batch + (self.num_vertices, 3))
