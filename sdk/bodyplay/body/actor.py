"""The synthetic actor: a detailed human mesh (MakeHuman, CC0) with its own skeleton.

The synthetic camera films this actor, not the trackers' generic mesh, so that the
trackers are tested against a body they were not built from. The vendored asset
``bodyplay/assets/actor.npz`` (made by ``tools/convert_makehuman.py``) holds the body
in bodyplay's rest T-pose, skin weights on skeleton nodes, the shirt patches and the
skeleton rest offsets measured from the mesh's joint centres, so that the truth joints
(skeleton forward kinematics) sit inside the body.

Body presets are a documented simplification of real body variation: every length
(and the mesh) is scaled uniformly to the preset height, shoulders and hips are moved
outward by the preset's ``breadth``, and limbs and torso are thickened radially about
their bones by its ``girth`` (heads, hands and feet keep their size).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.dress import vertex_colors
from bodyplay.body.shapes import BodyShape, body_shape
from bodyplay.body.skeleton import NODE_NAMES, NODE_PARENTS, Skeleton
from bodyplay.body.skinning import SkinnedMesh
from bodyplay.errors import ConfigError

__all__ = ["Actor", "load_actor", "actor_asset_path"]

_N = {name: i for i, name in enumerate(NODE_NAMES)}
_BREADTH_NODES = ("l_clavicle", "r_clavicle", "l_shoulder", "r_shoulder", "l_hip", "r_hip")
_RIGID_NODES = ("neck", "head", "head_top", "l_wrist", "r_wrist", "l_hand", "r_hand",
                "l_ankle", "r_ankle", "l_toe", "r_toe")
# the child whose direction defines each node's bone (for radial thickening)
_BONE_CHILD = {
    "pelvis": "lumbar", "lumbar": "thorax", "thorax": "neck", "l_clavicle": "l_shoulder",
    "r_clavicle": "r_shoulder", "l_shoulder": "l_elbow", "r_shoulder": "r_elbow",
    "l_elbow": "l_wrist", "r_elbow": "r_wrist", "l_hip": "l_knee", "r_hip": "r_knee",
    "l_knee": "l_ankle", "r_knee": "r_ankle",
}


@dataclass(frozen=True, eq=False)
class Actor:
    """The synthetic actor of one body preset: its skeleton and its skinned mesh."""

    skeleton: Skeleton
    mesh: SkinnedMesh

    def pose(self, poses: NDArray[np.floating]) -> NDArray[np.float32]:
        """(..., pose_dim) pose vectors -> (..., V, 3) posed mesh vertices."""
        return self.mesh.pose(self.skeleton, poses)


def actor_asset_path() -> str:
    """Filesystem path of the vendored actor asset."""
    return str(resources.files("bodyplay") / "assets" / "actor.npz")


@lru_cache(maxsize=1)
def _asset() -> dict[str, NDArray[np.generic]]:
    try:
        with np.load(actor_asset_path(), allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
    except FileNotFoundError:
        raise ConfigError(
            "the actor asset bodyplay/assets/actor.npz is missing; reinstall bodyplay or "
            "run tools/convert_makehuman.py"
        ) from None
    if tuple(str(n) for n in data["node_names"]) != NODE_NAMES:
        raise ConfigError("actor.npz was made for another skeleton; rerun the converter")
    return data


def _positions(offsets: NDArray[np.float64]) -> NDArray[np.float64]:
    pos = np.zeros_like(offsets)
    for i, p in enumerate(NODE_PARENTS):
        pos[i] = offsets[i] + (pos[p] if p >= 0 else 0.0)
    return pos


@lru_cache(maxsize=16)
def _load(shape: BodyShape) -> Actor:
    a = _asset()
    verts = a["vertices"].astype(np.float64)
    offsets = a["rest_offsets"].astype(np.float64)
    idx = a["bone_indices"].astype(np.int32)
    w = a["bone_weights"].astype(np.float64)
    w /= w.sum(1, keepdims=True)

    # lengths: uniform scale to the preset's standing height (floor stays at y = 0)
    s = shape.height / float(verts[:, 1].max())
    verts = verts * s
    offsets = offsets * s
    rest_pos = _positions(offsets) + a["pelvis"].astype(np.float64) * s

    # thickness: radial about each vertex's bones (weight-blended), by girth
    girth = np.ones(len(NODE_NAMES))
    for name in _BONE_CHILD:
        girth[_N[name]] = shape.girth
    for name in _RIGID_NODES:
        girth[_N[name]] = 1.0
    a_pt = rest_pos
    b_pt = rest_pos.copy()
    for name, child in _BONE_CHILD.items():
        b_pt[_N[name]] = rest_pos[_N[child]]
    A = a_pt[idx]
    D = b_pt[idx] - A
    t = np.clip(np.einsum("vkj,vkj->vk", verts[:, None, :] - A, D)
                / np.maximum(np.einsum("vkj,vkj->vk", D, D), 1e-12), 0.0, 1.0)
    closest = A + t[..., None] * D
    gk = girth[idx][..., None]
    verts = np.einsum("vk,vkj->vj", w, closest + gk * (verts[:, None, :] - closest))

    # breadth: shoulders and hips move outward; vertices follow their nodes
    new_off = offsets.copy()
    for name in _BREADTH_NODES:
        new_off[_N[name], 0] *= shape.breadth
    moved = _positions(new_off) - _positions(offsets)
    verts = verts + np.einsum("vk,vkj->vj", w, moved[idx])

    rest_offsets = tuple((float(o[0]), float(o[1]), float(o[2])) for o in new_off)
    skeleton = Skeleton(shape, rest_offsets=rest_offsets)
    # put the pelvis where the skeleton's rest pose has it
    rest_root = skeleton.rest_pose()[:3]
    verts = verts - rest_pos[0] + rest_root
    vmat = np.asarray(a["vertex_material"], dtype=np.uint8)
    vpart = np.asarray(a["vertex_part"], dtype=np.uint8)
    mesh = SkinnedMesh(
        rest_vertices=verts.astype(np.float32),
        faces=a["faces"].astype(np.int32),
        bone_indices=idx,
        bone_weights=w.astype(np.float32),
        face_part=np.asarray(a["face_part"], dtype=np.uint8),
        vertex_material=vmat,
        vertex_rgb=vertex_colors(vmat, vpart),
    )
    return Actor(skeleton, mesh)


def load_actor(shape: str | BodyShape = "m") -> Actor:
    """The actor dressed in the color shirt, sized to a body preset (cached)."""
    return _load(body_shape(shape))
