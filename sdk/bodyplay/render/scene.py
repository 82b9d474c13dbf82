"""A body-like test mesh made of trimesh primitives, for renderer tests and benchmarks.

The renderers must be checked and timed on something shaped like a person (limbs
crossing the torso, parts occluding each other, ~4k triangles) without depending on
the skinned body mesh. :func:`primitive_figure` builds a stick figure of capsules,
a box torso and a sphere head, one id per part, and poses it: each pose swings the
arms and legs by random angles and turns the whole figure about the vertical axis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh
from numpy.typing import NDArray

from bodyplay.errors import ConfigError

__all__ = ["PrimitiveFigure", "primitive_figure"]


@dataclass(frozen=True, eq=False)
class PrimitiveFigure:
    """Posed primitive figures: ``vertices`` (B, V, 3) world metres, shared topology.

    ``face_ids`` gives each face its part (1 torso, 2 head, 3..10 upper/lower arms
    and legs); ``colors`` (V, 3) float RGB in 0..1 per vertex, one colour per part.
    The figures stand on the floor (Y = 0) around the world origin, facing +Z.
    """

    vertices: NDArray[np.float32]
    faces: NDArray[np.int32]
    face_ids: NDArray[np.uint8]
    colors: NDArray[np.float32]


_PART_COLORS = np.array(
    [
        [0.8, 0.8, 0.8],
        [0.85, 0.2, 0.2],
        [0.95, 0.8, 0.6],
        [0.2, 0.6, 0.9],
        [0.2, 0.9, 0.4],
        [0.9, 0.9, 0.2],
        [0.7, 0.3, 0.9],
        [0.1, 0.3, 0.7],
        [0.1, 0.6, 0.3],
        [0.9, 0.5, 0.1],
        [0.5, 0.2, 0.1],
    ],
    dtype=np.float32,
)


def _rot(axis: str, angle: NDArray[np.float64]) -> NDArray[np.float64]:
    """(B, 3, 3) rotations about a coordinate axis."""
    c, s = np.cos(angle), np.sin(angle)
    o, z = np.ones_like(angle), np.zeros_like(angle)
    if axis == "x":
        m = [[o, z, z], [z, c, -s], [z, s, c]]
    elif axis == "y":
        m = [[c, z, s], [z, o, z], [-s, z, c]]
    else:
        m = [[c, -s, z], [s, c, z], [z, z, o]]
    return np.moveaxis(np.array(m), (0, 1), (-2, -1))


def primitive_figure(
    n_poses: int = 1, seed: int = 0, sections: int = 16, yaw_range: float = np.pi
) -> PrimitiveFigure:
    """``n_poses`` random poses of a ~4.6k-triangle stick figure (1.7 m tall).

    ``sections`` sets the capsules' tessellation (16 gives 512 triangles a limb);
    ``yaw_range`` bounds the random turn about the vertical axis (radians, +/-).
    Pose 0 of seed 0 is not special; the same seed always gives the same poses.
    """
    if n_poses < 1:
        raise ConfigError(f"n_poses must be at least 1, got {n_poses}")
    if sections < 4:
        raise ConfigError(f"sections must be at least 4, got {sections}")
    rng = np.random.default_rng(seed)
    B = n_poses

    def capsule(length: float, radius: float) -> trimesh.Trimesh:
        # along -Y from its joint at the origin
        m = trimesh.creation.capsule(height=length, radius=radius, count=[sections, sections])
        m.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
        m.apply_translation([0.0, -length / 2.0, 0.0])
        return m

    torso = trimesh.creation.box(extents=[0.36, 0.55, 0.2])
    torso = torso.subdivide().subdivide()
    head = trimesh.creation.icosphere(subdivisions=2, radius=0.11)

    # (part mesh, id, joint position in the torso frame, swing about z, swing about x)
    hip_y, shoulder_y = 0.95, 1.42
    parts: list[tuple[trimesh.Trimesh, int, NDArray[np.float64], NDArray[np.float64]]] = []
    parts.append((torso, 1, np.array([0.0, 1.2, 0.0]), np.eye(3)[None].repeat(B, 0)))
    parts.append((head, 2, np.array([0.0, 1.6, 0.0]), np.eye(3)[None].repeat(B, 0)))
    for side, sign in (("l", 1.0), ("r", -1.0)):
        abduct = sign * rng.uniform(0.1, 2.6, B)
        flex = rng.uniform(-1.2, 1.2, B)
        R_upper = _rot("z", abduct) @ _rot("x", flex)
        R_lower = R_upper @ _rot("x", -rng.uniform(0.0, 2.0, B))
        shoulder = np.array([sign * 0.24, shoulder_y, 0.0])
        upper = capsule(0.24, 0.05)
        parts.append((upper, 3 if side == "l" else 4, shoulder, R_upper))
        elbow = shoulder[None] + (R_upper @ np.array([0.0, -0.28, 0.0]))
        parts.append((capsule(0.22, 0.04), 5 if side == "l" else 6, elbow, R_lower))
        leg = _rot("z", sign * rng.uniform(0.0, 0.5, B)) @ _rot("x", rng.uniform(-0.8, 0.6, B))
        shin = leg @ _rot("x", rng.uniform(0.0, 1.2, B))
        hip = np.array([sign * 0.1, hip_y, 0.0])
        parts.append((capsule(0.36, 0.07), 7 if side == "l" else 8, hip, leg))
        knee = hip[None] + (leg @ np.array([0.0, -0.44, 0.0]))
        parts.append((capsule(0.36, 0.05), 9 if side == "l" else 10, knee, shin))

    yaw = _rot("y", rng.uniform(-yaw_range, yaw_range, B))
    shift = np.stack([rng.uniform(-0.1, 0.1, B), np.zeros(B), rng.uniform(-0.1, 0.1, B)], 1)
    verts, faces, ids, colors = [], [], [], []
    base = 0
    for mesh, pid, joint, R in parts:
        v = np.asarray(mesh.vertices, dtype=np.float64)
        j = np.broadcast_to(joint, (B, 3)) if joint.ndim == 1 else joint
        posed = np.einsum("bij,vj->bvi", R, v) + j[:, None, :]
        posed = np.einsum("bij,bvj->bvi", yaw, posed) + shift[:, None, :]
        verts.append(posed)
        faces.append(np.asarray(mesh.faces) + base)
        ids.append(np.full(len(mesh.faces), pid, dtype=np.uint8))
        colors.append(np.repeat(_PART_COLORS[pid][None], len(v), 0))
        base += len(v)
    return PrimitiveFigure(
        vertices=np.ascontiguousarray(np.concatenate(verts, axis=1), dtype=np.float32),
        faces=np.ascontiguousarray(np.concatenate(faces), dtype=np.int32),
        face_ids=np.concatenate(ids),
        colors=np.concatenate(colors).astype(np.float32),
    )
