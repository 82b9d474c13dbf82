"""Mesh data to draw a dressed body: the body capsules as triangles, the cloth's mesh.

No rendering here: renderers (the game kit's Scene.mesh, ShadedRenderer) take these
arrays. Capsule meshes are built once per (segments, rings) and moved per frame.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from bodyplay.cloth.body import BodyCapsules

__all__ = ["capsules_mesh"]


@lru_cache(maxsize=4)
def _unit_capsule(segments: int, rings: int) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                      NDArray[np.int64]]:
    """A capsule of radius 1 along +z from 0 to 1: (directions, along-axis 0/1, faces)."""
    th = 2.0 * np.pi * np.arange(segments) / segments
    lat = np.concatenate([np.linspace(-np.pi / 2, 0.0, rings + 1),
                          np.linspace(0.0, np.pi / 2, rings + 1)])
    end = np.concatenate([np.zeros(rings + 1), np.ones(rings + 1)])
    cl, sl = np.cos(lat)[:, None], np.sin(lat)[:, None]
    dirs = np.stack([cl * np.cos(th)[None], cl * np.sin(th)[None],
                     np.broadcast_to(sl, (len(lat), segments))], axis=2).reshape(-1, 3)
    along = np.repeat(end, segments)
    rows = len(lat)
    r, c = np.meshgrid(np.arange(rows - 1), np.arange(segments), indexing="ij")
    i00 = r * segments + c
    i01 = r * segments + (c + 1) % segments
    i10, i11 = i00 + segments, i01 + segments
    faces = np.concatenate([np.stack([i00, i01, i11], -1).reshape(-1, 3),
                            np.stack([i00, i11, i10], -1).reshape(-1, 3)])
    return dirs, along, faces.astype(np.int64)


def capsules_mesh(capsules: BodyCapsules, segments: int = 16, rings: int = 4
                  ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Vertices (V, 3) and outward faces (F, 3) of every capsule, one closed mesh each."""
    dirs, along, faces = _unit_capsule(segments, rings)
    verts, tris = [], []
    for c in range(len(capsules.radius)):
        a, b, r = capsules.a[c], capsules.b[c], float(capsules.radius[c])
        axis = b - a
        length = float(np.linalg.norm(axis))
        z = axis / length if length > 1e-9 else np.array([0.0, 1.0, 0.0])
        helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        x = np.cross(helper, z)
        x /= np.linalg.norm(x)
        y = np.cross(z, x)
        basis = np.stack([x, y, z])
        verts.append(a + along[:, None] * axis + r * dirs @ basis)
        tris.append(faces + c * len(dirs))
    return np.concatenate(verts), np.concatenate(tris)
