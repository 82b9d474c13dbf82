"""Arm search: each arm chosen on its own from a library of arm configurations.

The database matches the torso *and both arms* with one stored pose; a stored *arm*
alone lies much nearer. So after the 6-DOF fit each arm is replaced by the
library's arm (the database's arm rotations, thinned by farthest-point sampling)
that best explains the classified pixels: a truncated chamfer between the arm's
surface points (facing a camera, with their patch colour) and the pixels of their
colour, both ways; the best few are blended. With one camera a candidate also pays
``pull`` for leaving the blend's elbow and wrist (the lean comes from the
database). Beyond the paper; it changes the IK's start and blend prior only.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.shirt import NUM_COLORS, PATCHES, patch_color_index
from bodyplay.body.skeleton import Skeleton
from bodyplay.body.skinning import SkinnedMesh
from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.database import blend_poses
from bodyplay.trackers.colorshirt.prediction import CropWindow, PoseRenderer
from bodyplay.trackers.colorshirt.views import CameraView

__all__ = ["ARM_NODES", "ARM_ONLY_COLORS", "ArmChoice", "ArmSearch", "ArmSearches", "ArmView",
           "arm_library", "color_distance_maps"]

ARM_NODES: dict[str, tuple[str, ...]] = {
    "l": ("l_clavicle", "l_shoulder", "l_elbow", "l_wrist"),
    "r": ("r_clavicle", "r_shoulder", "r_elbow", "r_wrist"),
}
"""The nodes whose rotations make up one arm configuration, from the neck down."""

_PARENT = "neck"
_BLEND = 5
"""How many of each arm's best candidates are blended."""
_EXTRA = 2
"""Per-frame candidates ahead of the library: the blend's arm and the previous frame's."""
_COARSE = 2
"""Stage 1 scores every candidate on every ``_COARSE``-th surface point."""
_Points = tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]
"""Surface points of one arm: bone slot, position and normal in the bone's frame, color."""


def color_distance_maps(ids: NDArray[np.uint8], colors: tuple[int, ...] | None = None
                        ) -> NDArray[np.float32]:
    """(10, H, W) distance in pixels to the nearest pixel of each color in a color map.

    ``ids`` holds color ids (0 = unclassified, k + 1 = color k). A color with no pixel
    (or not in ``colors``, when given) gets a map of large distances.
    """
    h, w = ids.shape
    out = np.empty((NUM_COLORS, h, w), np.float32)
    for k in range(NUM_COLORS):
        src = np.not_equal(ids, k + 1).view(np.uint8)  # 0 on the color
        if (colors is not None and k not in colors) or not src.size or src.all():
            out[k] = 1.0e4
        else:
            out[k] = cv2.distanceTransform(src, cv2.DIST_L2, 3)
    return out


@numba.njit(cache=True, nogil=True, fastmath=True, error_model="numpy")
def _camera_from(A: NDArray[np.float64], R: NDArray[np.float64], t: NDArray[np.float64]
                 ) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """(3, 4) camera-from-parent transform ``[R | t] @ A``."""
    C = np.empty((3, 4))
    for r in range(3):
        for k in range(4):
            C[r, k] = R[r, 0] * A[0, k] + R[r, 1] * A[1, k] + R[r, 2] * A[2, k]
        C[r, 3] += t[r]
    return C


@numba.njit(cache=True, nogil=True, fastmath=True, error_model="numpy")
def _chain(C: NDArray[np.float64], rel: NDArray[np.float64], c: int, M: NDArray[np.float64]
           ) -> None:  # pragma: no cover - compiled
    """Fill ``M`` (nodes, 3, 4) with candidate ``c``'s camera-from-node transforms."""
    for j in range(rel.shape[1]):
        for r in range(3):
            for k in range(4):
                M[j, r, k] = (C[r, 0] * rel[c, j, 0, k] + C[r, 1] * rel[c, j, 1, k]
                              + C[r, 2] * rel[c, j, 2, k])
            M[j, r, 3] += C[r, 3]


@numba.njit(cache=True, nogil=True, fastmath=True, error_model="numpy")
def _camera_point(M: NDArray[np.float64], j: int, local: NDArray[np.float64],
                  normal: NDArray[np.float64]
                  ) -> tuple[float, float, float, bool]:  # pragma: no cover - compiled
    """A surface point of node ``j`` in the camera's frame, and whether it faces the
    camera (in front of it, its normal pointing back towards the origin)."""
    xc = M[j, 0, 0] * local[0] + M[j, 0, 1] * local[1] + M[j, 0, 2] * local[2] + M[j, 0, 3]
    yc = M[j, 1, 0] * local[0] + M[j, 1, 1] * local[1] + M[j, 1, 2] * local[2] + M[j, 1, 3]
    zc = M[j, 2, 0] * local[0] + M[j, 2, 1] * local[1] + M[j, 2, 2] * local[2] + M[j, 2, 3]
    wx = M[j, 0, 0] * normal[0] + M[j, 0, 1] * normal[1] + M[j, 0, 2] * normal[2]
    wy = M[j, 1, 0] * normal[0] + M[j, 1, 1] * normal[1] + M[j, 1, 2] * normal[2]
    wz = M[j, 2, 0] * normal[0] + M[j, 2, 1] * normal[1] + M[j, 2, 2] * normal[2]
    return xc, yc, zc, bool(wx * xc + wy * yc + wz * zc < 0.0 and zc > 0.05)


@numba.njit(cache=True, nogil=True, fastmath=True, error_model="numpy")
def _chamfer(A: NDArray[np.float64], rel: NDArray[np.float64], pnode: NDArray[np.int64],
             plocal: NDArray[np.float64], pnormal: NDArray[np.float64],
             pcolor: NDArray[np.int64], K: NDArray[np.float64], R: NDArray[np.float64],
             t: NDArray[np.float64], x0: float, y0: float,
             scale: float, dts: NDArray[np.float32], tau: float,
             cost: NDArray[np.float64], seen: NDArray[np.float64]
             ) -> None:  # pragma: no cover - compiled
    """Add every candidate's truncated chamfer cost and visible-point count for one camera."""
    h = dts.shape[1]
    w = dts.shape[2]
    C = _camera_from(A, R, t)
    M = np.empty((rel.shape[1], 3, 4))
    fx = K[0, 0] * scale
    skew = K[0, 1] * scale
    cx = (K[0, 2] - x0) * scale
    fy = K[1, 1] * scale
    cy = (K[1, 2] - y0) * scale
    for c in range(rel.shape[0]):
        _chain(C, rel, c, M)
        total = 0.0
        vis = 0.0
        for i in range(plocal.shape[0]):
            xc, yc, zc, faces = _camera_point(M, pnode[i], plocal[i], pnormal[i])
            if not faces:
                continue
            iz = 1.0 / zc
            u = (fx * xc + skew * yc) * iz + cx
            v = fy * yc * iz + cy
            vis += 1.0
            ui = int(u + 0.5)
            vi = int(v + 0.5)
            if 0 <= ui < w and 0 <= vi < h:
                d = dts[pcolor[i], vi, ui]
                total += d if d < tau else tau
            else:
                total += tau
        cost[c] += total
        seen[c] += vis


@dataclass(frozen=True)
class ArmChoice:
    """What the search chose for one arm (before the blend of the best few).

    ``index``: the library entry, or -1 for the blend's own arm and -2 for the
    previous frame's; ``score``: the chosen pair's cost (truncated chamfer, in units
    of ``tau``); ``kept_score``: the cost of keeping both of the blend's arms.
    """

    side: str
    index: int
    score: float
    kept_score: float


class ArmSearch:
    """The arm library of one body (skeleton and mesh) and its per-frame search."""

    def __init__(self, skeleton: Skeleton, mesh: SkinnedMesh,
                 library: dict[str, NDArray[np.float64]], points_per_patch: int = 30) -> None:
        """``library``: per side (``"l"``, ``"r"``) the poses whose arms are the
        candidates (see :func:`arm_library`); only their arm rotations are used."""
        self.skeleton = skeleton
        self._per_patch = points_per_patch
        self._nodes = {s: np.array([skeleton.node_index(n) for n in names])
                       for s, names in ARM_NODES.items()}
        self._parent = {s: skeleton.parents[int(n[0])] for s, n in self._nodes.items()}
        self._cols = {s: (3 + 3 * n[:, None] + np.arange(3)).ravel()
                      for s, n in self._nodes.items()}
        """Per side, the pose-vector columns of the arm's node rotations."""
        self._rot: dict[str, NDArray[np.float64]] = {}
        self._rel: dict[str, NDArray[np.float64]] = {}
        for s in ARM_NODES:
            poses = np.asarray(library[s], np.float64)
            rot = poses[:, self._cols[s]]
            rel = self._relative(skeleton.forward(poses), s)
            # two leading slots for the per-frame candidates (blend, previous frame)
            self._rot[s] = np.concatenate([np.zeros((_EXTRA,) + rot.shape[1:]), rot])
            self._rel[s] = np.ascontiguousarray(
                np.concatenate([np.zeros((_EXTRA,) + rel.shape[1:]), rel]))
        self._points = {s: self._surface_points(mesh, s) for s in ARM_NODES}
        self._by_color = {s: _group_by_color(p[3]) for s, p in self._points.items()}
        """Per side, the surface points' indices grouped by color and each color's start."""
        self._coarse: dict[str, _Points] = {
            s: (np.ascontiguousarray(n[::_COARSE]), np.ascontiguousarray(lo[::_COARSE]),
                np.ascontiguousarray(nr[::_COARSE]), np.ascontiguousarray(c[::_COARSE]))
            for s, (n, lo, nr, c) in self._points.items()}
        """Every second point: enough to shortlist the candidates in stage 1."""

    def _relative(self, T: NDArray[np.float64], side: str) -> NDArray[np.float64]:
        inv = np.linalg.inv(T[:, self._parent[side]])
        return np.einsum("nij,nkjl->nkil", inv, T[:, self._nodes[side]])

    def _surface_points(self, mesh: SkinnedMesh, side: str) -> _Points:
        """One point per face of the arm's patches, in its bone's rest frame."""
        sk = self.skeleton
        faces = np.concatenate([_spread(np.nonzero(mesh.face_part == p.id)[0], self._per_patch)
                                for p in PATCHES if p.bone in ARM_NODES[side]])
        v = mesh.rest_vertices.astype(np.float64)[mesh.faces[faces]]
        centre = v.mean(axis=1)
        normal = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
        normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-12)
        part = mesh.face_part[faces]
        bone_of = {p.id: sk.node_index(p.bone) for p in PATCHES}
        node = np.array([bone_of[int(p)] for p in part])
        slot_of = {int(n): i for i, n in enumerate(self._nodes[side])}
        slot = np.array([slot_of[int(n)] for n in node])
        T_rest = sk.forward(sk.rest_pose())
        inv = np.linalg.inv(T_rest[node])
        local = np.einsum("nij,nj->ni", inv[:, :3, :3], centre) + inv[:, :3, 3]
        nloc = np.einsum("nij,nj->ni", inv[:, :3, :3], normal)
        color = patch_color_index()[part]
        return (slot.astype(np.int64), np.ascontiguousarray(local),
                np.ascontiguousarray(nloc), color.astype(np.int64))

    def search(self, q: NDArray[np.float64], cameras: tuple[Camera, ...],
               views: list[ArmView], previous: NDArray[np.float64] | None = None,
               temperature: float = 0.02, top: int = 24, min_seen: float = 0.15,
               pull: float = 0.0) -> tuple[NDArray[np.float64], list[ArmChoice]]:
        """``q`` with its arms replaced by the candidates that best explain the pixels.

        Stage 1 scores every candidate by the model-to-image chamfer; stage 2 pairs
        each arm's ``top`` (and the blend's arm) and adds the image-to-model cost of
        the arm-only colours' pixels, which an arm too short or folded leaves
        unexplained. ``pull``: cost per (10 cm)² of a candidate's elbow and wrist
        distance from the blend's arm.
        """
        if not views:
            return q.copy(), []
        T = self.skeleton.forward(q)
        A = {s: np.ascontiguousarray(T[self._parent[s]]) for s in ARM_NODES}
        extra = [(T, q)]
        if previous is not None:
            extra.append((self.skeleton.forward(previous), previous))
        n_extra = len(extra)
        first = _EXTRA - n_extra
        mean_tau = float(np.mean([v.tau for v in views]))
        stage1: dict[str, NDArray[np.float64]] = {}
        short: dict[str, NDArray[np.intp]] = {}
        rels: dict[str, NDArray[np.float64]] = {}
        rots: dict[str, NDArray[np.float64]] = {}
        for s in ARM_NODES:
            for k, (Te, qe) in enumerate(extra):
                self._rel[s][first + k] = self._relative(Te[None], s)[0]
                self._rot[s][first + k] = qe[self._cols[s]]
            rel = self._rel[s][first:]
            rot = self._rot[s][first:]
            cost = np.zeros(len(rel))
            seen = np.zeros(len(rel))
            node, local, normal, color = self._coarse[s]
            for v in views:
                cam = cameras[v.camera]
                _chamfer(A[s], rel, node, local, normal, color, cam.K, cam.R, cam.t,
                         float(v.window.x0),
                         float(v.window.y0), float(v.window.scale), v.distances,
                         float(v.tau), cost, seen)
            score = cost / (np.maximum(seen, 1.0) * mean_tau)
            score[seen < min_seen * len(local) * len(views)] = np.inf
            order = np.argsort(score, kind="stable")[:top]
            order = order[np.isfinite(score[order])]
            short[s] = np.unique(np.concatenate([np.arange(n_extra), order]))
            stage1[s] = score[short[s]]
            rels[s] = rel[short[s]]
            rots[s] = rot[short[s]]
        total = 0.5 * (stage1["l"][:, None] + stage1["r"][None, :])
        total = total + self._image_to_model(A, rels, cameras, views)
        if pull > 0:
            # the blend's arm is the first candidate of every shortlist
            total = (total + pull * _spread_from_first(rels["l"])[:, None]
                     + pull * _spread_from_first(rels["r"])[None, :])
        total[~np.isfinite(total)] = np.inf
        if not np.isfinite(total).any():
            return q.copy(), []
        i, j = np.unravel_index(int(np.argmin(total)), total.shape)
        out = q.copy()
        choices = []
        for s, k in (("l", int(i)), ("r", int(j))):
            out[self._cols[s]] = rots[s][k]
            idx = int(short[s][k])
            choices.append(ArmChoice(s, idx - n_extra if idx >= n_extra else -1 - idx,
                                     float(total[i, j]), float(total[0, 0])))
        if temperature > 0:
            best = total[i, j]
            for s, marg in (("l", total[:, j]), ("r", total[i, :])):
                w = np.exp(-(marg - best) / temperature)
                w[~np.isfinite(w)] = 0.0
                keep = np.argsort(-w, kind="stable")[:_BLEND]
                Q = np.repeat(out[None], len(keep), axis=0)
                Q[:, self._cols[s]] = rots[s][keep]
                out = blend_poses(Q, w[keep])
        return out, choices

    def _image_to_model(self, A: dict[str, NDArray[np.float64]],
                        rels: dict[str, NDArray[np.float64]],
                        cameras: tuple[Camera, ...], views: list[ArmView]
                        ) -> NDArray[np.float64]:
        """(L, R) mean truncated distance of the arm-only pixels to each pair's points."""
        total = np.zeros((len(rels["l"]), len(rels["r"])))
        weight = 0
        for v in views:
            obs = v.arm_pixels
            if not len(obs):
                continue
            cam = cameras[v.camera]
            near = {}
            for s in ARM_NODES:
                node, local, normal, color = self._points[s]
                uv, vis = _project(A[s], rels[s], node, local, normal, cam.K, cam.R, cam.t,
                                   float(v.window.x0),
                                   float(v.window.y0), float(v.window.scale))
                by_color, starts = self._by_color[s]
                near[s] = _nearest_same_color(uv, vis, by_color, starts, obs, float(v.tau))
            d = np.minimum(near["l"][:, None, :], near["r"][None, :, :])
            total += d.mean(axis=2) * len(obs) / v.tau
            weight += len(obs)
        return total / max(weight, 1)


class ArmSearches:
    """One tracker's arm searches: the library, thinned from ``poses`` on first use,
    and an :class:`ArmSearch` per body, built when the tracker first fits it."""

    def __init__(self, poses: NDArray[np.floating], size: int) -> None:
        self._poses = poses
        self._size = size
        self._library: dict[str, NDArray[np.float64]] | None = None
        self._searches: dict[str, ArmSearch] = {}
        self._inputs: list[tuple[NDArray[np.uint8], ArmView]] = []
        """Recent :class:`ArmView`-s, reused by the start-up's candidate bodies."""

    def _input(self, view: CameraView, tau: float) -> ArmView:
        """:meth:`ArmView.from_ids` of ``view``, reused when the same classification
        (the same array, never written in place) was searched with the same crop."""
        for ids, arm in self._inputs:
            if (ids is view.ids and arm.camera == view.index and arm.window == view.window
                    and arm.tau == float(tau)):
                return arm
        arm = ArmView.from_ids(view.index, view.window, view.ids, tau)
        self._inputs = [*self._inputs[-7:], (view.ids, arm)]
        return arm

    def search(self, body: str, renderer: PoseRenderer, q: NDArray[np.float64],
               cameras: tuple[Camera, ...], views: list[CameraView],
               previous: NDArray[np.float64] | None, tau: float, temperature: float,
               top: int, pull: float = 0.0) -> tuple[NDArray[np.float64], list[ArmChoice]]:
        """:meth:`ArmSearch.search` of ``body`` on the tracker's camera views: ``tau`` the
        truncation in shirt sizes, ``top`` the shortlist per arm that stage 2 pairs,
        ``pull`` the cost per (10 cm)² of an arm's distance from the blend's."""
        search = self._searches.get(body)
        if search is None:
            if self._library is None:
                self._library = arm_library(renderer.skeleton,
                                            np.asarray(self._poses, np.float64), self._size)
            search = ArmSearch(renderer.skeleton, renderer.mesh, self._library)
            self._searches[body] = search
        inputs = [self._input(v, tau * v.shirt_scale) for v in views]
        return search.search(q, cameras, inputs, previous, temperature=temperature, top=top,
                             pull=pull)


@dataclass(frozen=True, eq=False)
class ArmView:
    """One camera's input to the arm search.

    ``distances``: :func:`color_distance_maps` of the classification; ``arm_pixels``:
    (N, 3) crop x, y and color index of (a sample of) the pixels classified as one of
    the four arm-only colors; ``tau``: truncation of every distance, crop pixels.
    """

    camera: int
    window: CropWindow
    distances: NDArray[np.float32]
    arm_pixels: NDArray[np.float64]
    tau: float

    @classmethod
    def from_ids(cls, camera: int, window: CropWindow, ids: NDArray[np.uint8], tau: float,
                 max_pixels: int = 250) -> ArmView:
        """Distance maps and arm-only pixels of a classified crop (color ids 1..10)."""
        k = ids.astype(np.int64) - 1
        ys, xs = np.nonzero(np.isin(k, ARM_ONLY_COLORS))
        pick = _spread(np.arange(len(xs)), max_pixels)
        ys, xs = ys[pick], xs[pick]
        pix = np.column_stack([xs, ys, k[ys, xs]]).astype(np.float64)
        return cls(camera, window, color_distance_maps(ids, ARM_COLORS), pix, float(tau))


ARM_ONLY_COLORS = tuple(sorted({p.color for p in PATCHES
                                if p.bone.endswith(("shoulder", "elbow"))}))
"""Colors worn only on the arms (upper arms and forearms, front and back)."""

ARM_COLORS = tuple(sorted({p.color for p in PATCHES if p.bone in ARM_NODES["l"] + ARM_NODES["r"]}))
"""Colors of the arms' patches (shoulder caps included)."""


@numba.njit(cache=True, nogil=True, fastmath=True, error_model="numpy")
def _project(A: NDArray[np.float64], rel: NDArray[np.float64], pnode: NDArray[np.int64],
             plocal: NDArray[np.float64], pnormal: NDArray[np.float64],
             K: NDArray[np.float64], R: NDArray[np.float64], t: NDArray[np.float64],
             x0: float, y0: float, scale: float
             ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:  # pragma: no cover
    """Crop coordinates (C, P, 2) of every candidate's points and whether each faces the camera."""
    uv = np.zeros((rel.shape[0], plocal.shape[0], 2))
    vis = np.zeros((rel.shape[0], plocal.shape[0]), np.bool_)
    C = _camera_from(A, R, t)
    M = np.empty((rel.shape[1], 3, 4))
    for c in range(rel.shape[0]):
        _chain(C, rel, c, M)
        for i in range(plocal.shape[0]):
            xc, yc, zc, faces = _camera_point(M, pnode[i], plocal[i], pnormal[i])
            if not faces:
                continue
            uv[c, i, 0] = ((K[0, 0] * xc + K[0, 1] * yc) / zc + K[0, 2] - x0) * scale
            uv[c, i, 1] = (K[1, 1] * yc / zc + K[1, 2] - y0) * scale
            vis[c, i] = True
    return uv, vis


@numba.njit(cache=True, nogil=True)
def _nearest_same_color(uv: NDArray[np.float64], vis: NDArray[np.bool_],
                        by_color: NDArray[np.int64], starts: NDArray[np.int64],
                        obs: NDArray[np.float64], tau: float
                        ) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """(C, N) distance of each observed pixel to the candidate's nearest visible point
    of its color, at most ``tau``; ``by_color`` lists the points grouped by color,
    color ``k``'s from ``starts[k]`` to ``starts[k + 1]``."""
    n_cand = vis.shape[0]
    n_colors = starts.shape[0] - 1
    out = np.full((n_cand, obs.shape[0]), tau)
    xs = np.empty(by_color.shape[0])
    ys = np.empty(by_color.shape[0])
    first = np.empty(n_colors + 1, np.int64)
    for c in range(n_cand):
        m = 0  # the candidate's visible points, grouped by color, packed
        for k in range(n_colors):
            first[k] = m
            for j in range(starts[k], starts[k + 1]):
                i = by_color[j]
                if vis[c, i]:
                    xs[m] = uv[c, i, 0]
                    ys[m] = uv[c, i, 1]
                    m += 1
        first[n_colors] = m
        for o in range(obs.shape[0]):
            best = tau * tau
            k = int(obs[o, 2])
            ox = obs[o, 0]
            oy = obs[o, 1]
            for j in range(first[k], first[k + 1]):
                dx = xs[j] - ox
                dy = ys[j] - oy
                d = dx * dx + dy * dy
                if d < best:
                    best = d
            out[c, o] = np.sqrt(best)
    return out


def _group_by_color(color: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Point indices sorted by color, and where each color's run starts (NUM_COLORS + 1)."""
    order = np.argsort(color, kind="stable").astype(np.int64)
    starts = np.searchsorted(color[order], np.arange(NUM_COLORS + 1)).astype(np.int64)
    return order, starts


def _spread_from_first(rel: NDArray[np.float64], unit: float = 0.1) -> NDArray[np.float64]:
    """Per candidate, mean squared distance of its elbow and wrist (slots 2 and 3 of
    the neck-relative transforms ``rel``) from candidate 0's, in ``unit`` squared."""
    p = rel[:, 2:, :3, 3]
    return np.asarray(((p - p[0]) ** 2).sum(axis=-1).mean(axis=-1) / unit**2, np.float64)


def _spread(items: NDArray[np.intp], n: int) -> NDArray[np.intp]:
    """At most ``n`` of ``items``, evenly spaced in their order (a patch's faces: rings
    of a loft)."""
    if len(items) <= n:
        return items
    return items[np.linspace(0, len(items) - 1, n).round().astype(np.intp)]


def arm_library(skeleton: Skeleton, poses: NDArray[np.float64], size: int, seed: int = 0
                ) -> dict[str, NDArray[np.float64]]:
    """Per side, ``size`` of ``poses`` whose arms are spread evenly.

    Greedy farthest-point sampling on the shoulder, elbow and wrist positions
    relative to the neck, in the neck's frame (the torso does not matter).
    """
    poses = np.asarray(poses, np.float64)
    T = skeleton.forward(poses)
    inv = np.linalg.inv(T[:, skeleton.node_index(_PARENT)])
    rng = np.random.default_rng(seed)
    out = {}
    for s in ARM_NODES:
        nodes = [skeleton.node_index(f"{s}_{n}") for n in ("shoulder", "elbow", "wrist")]
        rel = (np.einsum("nij,nkj->nki", inv[:, :3, :3], T[:, nodes][..., :3, 3])
               + inv[:, None, :3, 3])
        X = np.ascontiguousarray(rel.reshape(len(rel), -1), np.float32)
        keep = _farthest(X, min(size, len(rel)), int(rng.integers(len(X))))
        out[s] = poses[keep.astype(np.intp)]
    return out


@numba.njit(cache=True, nogil=True)
def _farthest(X: NDArray[np.float32], n: int, first: int
              ) -> NDArray[np.int64]:  # pragma: no cover - compiled
    """Indices of ``n`` rows of ``X`` spread by greedy farthest-point sampling from
    row ``first``."""
    m, d = X.shape
    chosen = np.empty(n, np.int64)
    chosen[0] = first
    dist = np.full(m, np.inf, np.float32)
    for k in range(n):
        if k > 0:
            chosen[k] = int(np.argmax(dist))
        c = chosen[k]
        for i in range(m):
            s = np.float32(0.0)
            for j in range(d):
                e = X[i, j] - X[c, j]
                s += e * e
            if s < dist[i]:
                dist[i] = s
    return chosen
