"""The trackers' generic body mesh: lofted elliptic tubes for a skeleton's rest pose.

The color-shirt tracker renders thousands of id maps of this mesh, the silhouette
tracker thousands of masks, so it is small (about 4.5k triangles) and smooth enough
to bend: each limb is one closed tube from inside the torso to the finger tips (or
the ankle), with skin weights blended over a few centimetres around each joint, so
elbows, shoulders and the spine bend without tearing. Parts: a tapered torso with
elliptic cross-sections, the neck, an ellipsoid head, arms with flat hands, legs and
feet. Lengths come from the skeleton, thickness from the body shape's girth and chest.
trimesh orients each part's faces outward.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import trimesh
from numpy.typing import NDArray

from bodyplay.body.dress import dress_points, torso_profile, vertex_colors
from bodyplay.body.skeleton import NODE_NAMES, Skeleton
from bodyplay.body.skinning import SkinnedMesh

__all__ = ["body_mesh", "build_body_mesh"]

_N = {name: i for i, name in enumerate(NODE_NAMES)}
_K = 4


class _Builder:
    """Accumulates closed parts (vertices, faces, per-vertex skin weights)."""

    def __init__(self) -> None:
        self.verts: list[NDArray[np.float64]] = []
        self.faces: list[NDArray[np.int64]] = []
        self.idx: list[NDArray[np.int64]] = []
        self.w: list[NDArray[np.float64]] = []
        self.count = 0

    def add(self, v: NDArray[np.float64], f: NDArray[np.int64], idx: NDArray[np.int64],
            w: NDArray[np.float64]) -> None:
        mesh = trimesh.Trimesh(v, f, process=False)
        trimesh.repair.fix_normals(mesh)
        self.verts.append(v)
        self.faces.append(np.asarray(mesh.faces) + self.count)
        pad = _K - idx.shape[1]
        self.idx.append(np.pad(idx, ((0, 0), (0, pad))))
        self.w.append(np.pad(w, ((0, 0), (0, pad))))
        self.count += len(v)


def _loft(centers: NDArray[np.float64], axis_u: NDArray[np.float64], axis_v: NDArray[np.float64],
          half_u: NDArray[np.float64], half_v: NDArray[np.float64], n: int
          ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Closed tube through elliptic rings (R rings of n vertices, plus two cap centres)."""
    R = len(centers)
    th = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    ring = (centers[:, None, :]
            + (half_u[:, None] * np.cos(th))[..., None] * axis_u[:, None, :]
            + (half_v[:, None] * np.sin(th))[..., None] * axis_v[:, None, :])
    v = np.concatenate([ring.reshape(-1, 3), centers[:1], centers[-1:]])
    i = np.arange(R - 1)[:, None] * n
    j = np.arange(n)[None, :]
    a, b = i + j, i + (j + 1) % n
    c, d = a + n, b + n
    quads = np.stack([np.stack([a, b, d], -1), np.stack([a, d, c], -1)], 2).reshape(-1, 3)
    s0, s1 = R * n, R * n + 1
    cap0 = np.stack([np.full(n, s0), (j[0] + 1) % n, j[0]], -1)
    cap1 = np.stack([np.full(n, s1), (R - 1) * n + j[0], (R - 1) * n + (j[0] + 1) % n], -1)
    return v, np.concatenate([quads, cap0, cap1]).astype(np.int64)


def _chain_weights(s: NDArray[np.float64], joints_s: list[float], nodes: list[int],
                   blend: float) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Weights along a chain: segment k (between joints k-1 and k) follows nodes[k];
    within ``blend`` of a joint the two neighbours cross-fade smoothly (50/50 at it)."""
    js = np.asarray(joints_s)
    k = np.argmin(np.abs(s[:, None] - js[None, :]), axis=1)
    t = np.clip((s - js[k]) / blend, -1.0, 1.0) * 0.5 + 0.5
    after = t * t * (3.0 - 2.0 * t)
    nd = np.asarray(nodes)
    idx = np.stack([nd[k], nd[k + 1]], -1)
    return idx, np.stack([1.0 - after, after], -1)


def _frames(d: NDArray[np.float64], hint: NDArray[np.float64]
            ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Cross-section axes: u = hint made orthogonal to d, v = d x u."""
    u = hint - np.sum(hint * d, -1, keepdims=True) * d
    u /= np.linalg.norm(u, axis=-1, keepdims=True)
    return u, np.cross(d, u)


def _limb(b: _Builder, pts: list[NDArray[np.float64]], keys: list[tuple[float, float, float]],
          joints_at: list[int], nodes: list[int], blend: float, hint: NDArray[np.float64],
          spacing: float, n: int) -> None:
    """A tube along the polyline ``pts``; ``keys`` are (fraction of arc, half_u, half_v)."""
    P = np.asarray(pts)
    seg = np.linalg.norm(np.diff(P, axis=0), axis=1)
    S = np.concatenate([[0.0], np.cumsum(seg)])
    R = max(int(np.ceil(S[-1] / spacing)) + 1, 4)
    s = np.unique(np.concatenate([np.linspace(0.0, S[-1], R), S]))
    centers = np.stack([np.interp(s, S, P[:, i]) for i in range(3)], -1)
    d = np.stack([np.interp(s, S, np.r_[np.diff(P, axis=0), np.diff(P, axis=0)[-1:]][:, i])
                  for i in range(3)], -1)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    u, v = _frames(d, np.broadcast_to(hint, d.shape))
    kf = np.array([k[0] for k in keys]) * S[-1]
    hu = np.interp(s, kf, [k[1] for k in keys])
    hv = np.interp(s, kf, [k[2] for k in keys])
    verts, faces = _loft(centers, u, v, hu, hv, n)
    idx, w = _chain_weights(s, [float(S[j]) for j in joints_at], nodes, blend)
    ring_of = np.r_[np.repeat(np.arange(len(s)), n), 0, len(s) - 1]
    b.add(verts, faces, idx[ring_of], w[ring_of])


def build_body_mesh(skeleton: Skeleton) -> SkinnedMesh:
    """Build the generic mesh for ``skeleton`` (uncached; see :func:`body_mesh`)."""
    J = skeleton.node_positions(skeleton.rest_pose())
    shape = skeleton.shape
    u = float(J[_N["head_top"], 1] / 1.74)
    g = shape.girth * u
    k = shape.chest / 0.98
    b = _Builder()
    X, Y, Z = np.eye(3)

    # torso: tapered elliptic rings from below the hips to the top of the shoulders
    pel, lum, tho = J[_N["pelvis"]], J[_N["lumbar"]], J[_N["thorax"]]
    x_sh = 0.5 * (J[_N["l_shoulder"], 0] - J[_N["r_shoulder"], 0])
    y_sh = 0.5 * (J[_N["l_shoulder"], 1] + J[_N["r_shoulder"], 1])
    z_sh = 0.5 * (J[_N["l_shoulder"], 2] + J[_N["r_shoulder"], 2])
    rings = [  # height, half width, half depth, z offset
        (pel[1] - 0.13 * u, 0.11 * k, 0.065 * k, 0.0),
        (pel[1] - 0.10 * u, 0.155 * k, 0.095 * k, 0.0),
        (pel[1] - 0.05 * u, 0.168 * k, 0.102 * k, 0.0),
        (pel[1] + 0.02 * u, 0.165 * k, 0.100 * k, 0.01),
        (pel[1] + 0.10 * u, 0.148 * k, 0.095 * k, 0.015),
        (pel[1] + 0.18 * u, 0.150 * k, 0.105 * k, 0.02),
        (pel[1] + 0.27 * u, 0.165 * k, 0.118 * k, 0.025),
        (pel[1] + 0.36 * u, 0.172 * k, 0.122 * k, 0.025),
        (y_sh - 0.07 * u, max(0.175 * k, x_sh - 0.01), 0.115 * k, 0.02),
        (y_sh - 0.02 * u, x_sh + 0.035 * u, 0.10 * k, 0.01),
        (y_sh + 0.025 * u, x_sh + 0.015 * u, 0.085 * k, 0.0),
        (y_sh + 0.05 * u, 0.6 * x_sh, 0.07 * k, 0.0),
        (y_sh + 0.065 * u, 0.35 * x_sh, 0.055 * k, 0.0),
    ]
    ry = np.array([r[0] for r in rings])
    zax = np.interp(ry, [pel[1], lum[1], tho[1], y_sh], [pel[2], lum[2], tho[2], z_sh])
    centers = np.stack([np.zeros_like(ry), ry, zax + np.array([r[3] for r in rings]) * u], -1)
    ones = np.ones_like(ry)
    tv, tf = _loft(centers, np.tile(X, (len(ry), 1)), np.tile(Z, (len(ry), 1)),
                   np.array([r[1] for r in rings]) * ones, np.array([r[2] for r in rings]) * ones,
                   24)
    ti, tw = _chain_weights(tv[:, 1], [lum[1], tho[1]],
                            [_N["pelvis"], _N["lumbar"], _N["thorax"]], 0.06 * u)
    ti = np.concatenate([ti, np.where(tv[:, :1] >= 0, _N["l_clavicle"], _N["r_clavicle"])], 1)
    t1 = np.clip((np.abs(tv[:, 0]) - 0.07 * u) / (x_sh - 0.07 * u), 0, 1)
    t2 = np.clip((tv[:, 1] - (y_sh - 0.13 * u)) / (0.09 * u), 0, 1)
    wc = 0.8 * (t1 * t1 * (3 - 2 * t1)) * (t2 * t2 * (3 - 2 * t2))
    tw = np.concatenate([tw * (1.0 - wc[:, None]), wc[:, None]], 1)
    b.add(tv, tf, ti, tw)

    # neck and head
    neck, head = J[_N["neck"]], J[_N["head"]]
    _limb(b, [neck - 0.03 * u * Y, neck, head - 0.02 * u * Y],
          [(0.0, 0.058 * g, 0.058 * g), (1.0, 0.05 * g, 0.052 * g)],
          [1, 2], [_N["thorax"], _N["neck"], _N["head"]], 0.04 * u, Z, 0.03 * u, 12)
    sphere = trimesh.creation.icosphere(subdivisions=2)
    hv = np.asarray(sphere.vertices) * np.array([0.078, 0.112, 0.097]) * u
    hv = hv + head + np.array([0.0, 0.012, 0.012]) * u
    b.add(hv, np.asarray(sphere.faces, dtype=np.int64), np.full((len(hv), 1), _N["head"]),
          np.ones((len(hv), 1)))

    for sd in ("l", "r"):
        sh, el, wr, hd = (J[_N[f"{sd}_{n}"]] for n in ("shoulder", "elbow", "wrist", "hand"))
        clav = J[_N[f"{sd}_clavicle"]]
        out = (sh - clav) / np.linalg.norm(sh - clav)
        tip = hd + 0.085 * u * (hd - wr) / np.linalg.norm(hd - wr)
        pts = [sh - 0.06 * u * out, sh, el, wr, hd, tip]
        L = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
        f = L / L[-1]
        _limb(b, pts,
              [(0.0, 0.06 * g, 0.06 * g), (f[1], 0.058 * g, 0.06 * g),
               (0.5 * (f[1] + f[2]), 0.047 * g, 0.05 * g), (f[2], 0.039 * g, 0.042 * g),
               (f[2] + 0.3 * (f[3] - f[2]), 0.041 * g, 0.045 * g), (f[3], 0.027 * g, 0.033 * g),
               (0.5 * (f[3] + f[4]), 0.016 * g, 0.045 * g), (f[4], 0.014 * g, 0.044 * g),
               (1.0, 0.008 * g, 0.03 * g)],
              [1, 2, 3], [_N[f"{sd}_clavicle"], _N[f"{sd}_shoulder"], _N[f"{sd}_elbow"],
                          _N[f"{sd}_wrist"]], 0.045 * u, Y, 0.028 * u, 12)

        hip, knee, ank, toe = (J[_N[f"{sd}_{n}"]] for n in ("hip", "knee", "ankle", "toe"))
        pts = [hip + 0.07 * u * Y, hip, knee, ank - 0.01 * u * Y]
        L = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
        f = L / L[-1]
        _limb(b, pts,
              [(0.0, 0.085 * g, 0.085 * g), (f[1], 0.088 * g, 0.085 * g),
               (0.5 * (f[1] + f[2]), 0.072 * g, 0.07 * g), (f[2], 0.053 * g, 0.05 * g),
               (f[2] + 0.3 * (f[3] - f[2]), 0.056 * g, 0.052 * g), (1.0, 0.036 * g, 0.034 * g)],
              [1, 2], [_N["pelvis"], _N[f"{sd}_hip"], _N[f"{sd}_knee"]], 0.06 * u, Z,
              0.045 * u, 12)
        # foot: flat-bottomed along +Z from heel to toe tip, on the floor
        fz = np.linspace(ank[2] - 0.065 * u, toe[2] + 0.055 * u, 10)
        t = (fz - fz[0]) / (fz[-1] - fz[0])
        hh = np.interp(t, [0, 0.3, 0.75, 1], [0.045, 0.05, 0.028, 0.018]) * u
        hw = np.interp(t, [0, 0.3, 0.75, 1], [0.033, 0.04, 0.047, 0.035]) * u
        fx = np.interp(t, [0, 1], [ank[0], toe[0] + 0.1 * (toe[0] - hip[0])])
        centers = np.stack([fx, hh + 0.002 * u, fz], -1)
        fv, ff = _loft(centers, np.tile(Y, (10, 1)), np.tile(X, (10, 1)), hh, hw, 12)
        b.add(fv, ff, np.full((len(fv), 1), _N[f"{sd}_ankle"]), np.ones((len(fv), 1)))

    verts = np.concatenate(b.verts)
    faces = np.concatenate(b.faces)
    idx = np.concatenate(b.idx)
    w = np.concatenate(b.w)
    w /= w.sum(1, keepdims=True)
    dom = idx[np.arange(len(idx)), np.argmax(w, 1)]
    prof = torso_profile(verts, dom, J)
    mat, vpart = dress_points(verts, dom, J, prof, hair=True)
    fw = np.zeros((len(faces), len(NODE_NAMES)))
    for c in range(3):
        np.add.at(fw, (np.arange(len(faces))[:, None], idx[faces[:, c]]), w[faces[:, c]])
    fmat, fpart = dress_points(verts[faces].mean(1), np.argmax(fw, 1), J, prof, hair=True)
    return SkinnedMesh(verts.astype(np.float32), faces.astype(np.int32), idx.astype(np.int32),
                       w.astype(np.float32), fpart, mat, vertex_colors(mat, vpart))


@lru_cache(maxsize=32)
def body_mesh(skeleton: Skeleton) -> SkinnedMesh:
    """The generic body mesh for a skeleton, built once per skeleton (body shape)."""
    return build_body_mesh(skeleton)
