"""The shape hierarchy (paper section 2.1, Algorithm 1), built once and cached.

Poses (:mod:`.poses`) are rendered as window templates of the reference body
(:mod:`.templates`) and clustered level by level with Algorithm 1: in every node
of the parent level, start from the pose of smallest mean silhouette distance to
the others, keep adding the pose farthest (largest distance to its nearest
prototype) as a new prototype while that distance exceeds the level's threshold
t_L, then assign every pose to its nearest prototype; each cluster is a child
node holding its prototype's pose and silhouette. Level L's distances are the
normalized core-weighted XOR distance at level L's resolution (80x60, 160x120,
320x240 in pixel count), the prototype as the observed shape.

The mean distance of step 1 is estimated on a random sample (at most 48 candidates
against 256 members) instead of all pairs, which at the top node would be 10^7
distance evaluations.

The tree stores, per level, each node's prototype pose and parent; leaves are
ordered so that every node's leaves are contiguous. Templates are rendered from
the tracker's own body at every body-size preset (same tree, each body's own
silhouettes and anchor offsets). The transition histograms count leaf-to-leaf
steps of the training sequences (eq. 5); per-part standard deviations of the
first-order dynamic model (eq. 13) and each leaf's occluded parts (eq. 14) come
from the same data.

Cached as one ``.npz`` (no pickles) keyed by a hash of the options, the clips'
contents, the bodies and :data:`FORMAT_VERSION`; written to a temporary file and
renamed, so a killed build never leaves half a file.
"""

from __future__ import annotations

import hashlib
import logging
import os
import sys
import time
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.mesh import body_mesh
from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette.distance import (
    TemplateRuns,
    distance_maps,
    score_runs,
)
from bodyplay.trackers.silhouette.options import HierarchyOptions
from bodyplay.trackers.silhouette.poses import clip_fingerprint, training_poses
from bodyplay.trackers.silhouette.templates import PART_NAMES, render_templates
from bodyplay.trackers.silhouette.window import WindowGeometry

__all__ = [
    "FORMAT_VERSION",
    "ShapeTree",
    "BodyTemplates",
    "cluster_level",
    "build_tree",
    "load_or_build_tree",
    "tree_cache_path",
]

_log = logging.getLogger("bodyplay.silhouette")

FORMAT_VERSION = 3

PART_JOINTS: tuple[tuple[str, ...], ...] = (
    ("pelvis", "spine", "chest", "neck", "head"),
    ("l_shoulder", "l_elbow", "l_wrist"),
    ("r_shoulder", "r_elbow", "r_wrist"),
    ("l_hip", "l_knee", "l_ankle"),
    ("r_hip", "r_knee", "r_ankle"),
)


class _MemberCosts:
    """The tracker's per-pixel cost of every member's silhouette as the *observed*
    shape (eq. 11 with the tracker's beta), as one dense matrix: the distance the
    filter will give a prototype's template when that member is in front of the
    camera is one gather-and-sum per prototype."""

    def __init__(self, runs: TemplateRuns, members: NDArray[np.int64], beta: float) -> None:
        masks = runs.masks(members)
        self.cost = np.empty((len(members), runs.width * runs.height), np.float32)
        self.base = np.empty(len(members), np.float64)
        for k, m in enumerate(masks):
            dm = distance_maps(m, beta=beta)
            self.cost[k] = dm.cost.ravel()
            self.base[k] = dm.base
        self.area = float(runs.width * runs.height)
        self.runs = runs

    def score(self, template: int, rows: NDArray[np.int64] | slice = slice(None)
              ) -> NDArray[np.float64]:
        """d(member observed, ``template``) for the members ``rows``."""
        pix = np.flatnonzero(self.runs.masks(np.array([template]))[0].ravel())
        return (self.cost[rows][:, pix].sum(axis=1, dtype=np.float64)
                + self.base[rows]) / self.area


def cluster_level(runs: TemplateRuns, members: NDArray[np.int64], threshold: float,
                  rng: np.random.Generator, membership: str = "prototype",
                  beta: float = 5.0) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Algorithm 1 for one node: prototypes (indices into ``runs``) and, per member,
    the position of its prototype in that list.

    ``membership`` is the direction of the distance: "prototype" scores the
    member's template against the prototype as the observed shape (beta 1: a
    compact pose lies inside a spread-out prototype at little cost); "member"
    scores the prototype's template against the member as the observed shape
    with the tracker's ``beta`` (the distance the filter computes when that
    member is in front of the camera); "both" takes the larger of the two, so a
    member is near its prototype whichever shape is observed."""
    members = np.asarray(members, np.int64)
    if len(members) == 1:
        return members.copy(), np.zeros(1, np.int64)
    if membership not in ("prototype", "member", "both"):
        raise ConfigError(f"membership must be 'prototype', 'member' or 'both', got "
                          f"{membership!r}")
    masks_cache: dict[int, object] = {}
    costs = _MemberCosts(runs, members, beta) if membership != "prototype" else None
    position = {int(m): k for k, m in enumerate(members)}

    def maps(i: int):  # type: ignore[no-untyped-def]
        if i not in masks_cache:
            masks_cache[i] = distance_maps(runs.masks(np.array([i]))[0])
        return masks_cache[i]

    def dist(p: int, among: NDArray[np.int64]) -> NDArray[np.float64]:
        """Distance of each of ``among`` (members) to prototype ``p``."""
        if costs is None:
            return score_runs(maps(p), runs, among)  # type: ignore[arg-type]
        rev = costs.score(p, np.array([position[int(m)] for m in among], np.int64))
        if membership == "member":
            return rev
        return np.maximum(rev, score_runs(maps(p), runs, among))  # type: ignore[arg-type]

    # 1. the pose of smallest mean distance to the others (estimated on a sample)
    cand = members if len(members) <= 48 else rng.choice(members, 48, replace=False)
    refs = members if len(members) <= 256 else rng.choice(members, 256, replace=False)
    means = [float(dist(int(c), refs).mean()) for c in cand]
    protos = [int(cand[int(np.argmin(means))])]
    dmin = dist(protos[0], members)
    assign = np.zeros(len(members), np.int64)
    # 2. add the farthest pose while it is farther than the threshold
    while True:
        far = int(np.argmax(dmin))
        if dmin[far] <= threshold:
            break
        p = int(members[far])
        protos.append(p)
        d = dist(p, members)
        closer = d < dmin
        dmin = np.where(closer, d, dmin)
        assign[closer] = len(protos) - 1
        dmin[far] = 0.0
        assign[far] = len(protos) - 1
    # 3. every prototype is in its own cluster
    for k, p in enumerate(protos):
        assign[members == p] = k
    return np.array(protos, np.int64), assign


@dataclass(frozen=True, eq=False)
class BodyTemplates:
    """One body preset's templates: node silhouettes per level and leaf offsets."""

    name: str
    runs: tuple[TemplateRuns, ...]
    offset: NDArray[np.float64]

    @property
    def nbytes(self) -> int:
        """Memory held by this body's templates."""
        return sum(r.nbytes for r in self.runs) + int(self.offset.nbytes)


@dataclass(frozen=True, eq=False)
class ShapeTree:
    """The hierarchy: see the module docstring.

    ``poses``: (N, pose_dim) the kept poses; ``node_pose[l]``: prototype pose of each
    level-l node; ``node_parent[l]``: its parent at level l-1 (-1 at level 0);
    ``thresholds``: t_L; ``trans_src/dst/count``: leaf transition histogram;
    ``part_sigma``: per-part std of a frame step (m); ``part_features``: (leaves,
    5, 3) part centroids relative to the pelvis; ``occluded``: (leaves, 5) bool;
    ``leaf_joints``: (leaves, 17, 3) joints relative to the pelvis (template
    frame); ``bodies``: per body-size preset its templates.
    """

    options: HierarchyOptions
    poses: NDArray[np.float64]
    node_pose: tuple[NDArray[np.int64], ...]
    node_parent: tuple[NDArray[np.int64], ...]
    trans_src: NDArray[np.int64]
    trans_dst: NDArray[np.int64]
    trans_count: NDArray[np.float64]
    part_sigma: NDArray[np.float64]
    part_features: NDArray[np.float64]
    occluded: NDArray[np.bool_]
    leaf_joints: NDArray[np.float64]
    bodies: dict[str, BodyTemplates]
    build_seconds: float = 0.0
    dedup_deg: float = 5.0
    frames: int = 0

    @property
    def level_sizes(self) -> tuple[int, ...]:
        """Number of nodes at each level."""
        return tuple(len(p) for p in self.node_pose)

    @property
    def num_leaves(self) -> int:
        """Number of leaves (the filter's states)."""
        return len(self.node_pose[-1])

    @property
    def nbytes(self) -> int:
        """Memory held by the tree and every body's templates."""
        arrays = [self.poses, self.trans_src, self.trans_dst, self.trans_count,
                  self.part_features, self.occluded, self.leaf_joints,
                  *self.node_pose, *self.node_parent]
        return sum(int(a.nbytes) for a in arrays) + sum(b.nbytes for b in self.bodies.values())

    @cached_property
    def children(self) -> tuple[tuple[NDArray[np.int64], NDArray[np.int64]], ...]:
        """Per level 1..2: (start, end) of each parent's children at that level."""
        out = []
        for lv in range(1, len(self.node_pose)):
            par = self.node_parent[lv]
            n_par = len(self.node_pose[lv - 1])
            start = np.searchsorted(par, np.arange(n_par), side="left").astype(np.int64)
            end = np.searchsorted(par, np.arange(n_par), side="right").astype(np.int64)
            out.append((start, end))
        return tuple(out)

    @cached_property
    def leaf_ancestor(self) -> tuple[NDArray[np.int64], ...]:
        """Per level, the level's node above each leaf."""
        out = [np.arange(self.num_leaves, dtype=np.int64)]
        for lv in range(len(self.node_pose) - 1, 0, -1):
            out.append(self.node_parent[lv][out[-1]])
        return tuple(reversed(out))

    # ---- persistence --------------------------------------------------------------
    def save(self, path: Path, key: str) -> Path:
        """Write atomically (temporary file, then rename) as an ``.npz`` without pickles."""
        arrays: dict[str, NDArray[np.generic]] = {
            "version": np.array([FORMAT_VERSION]), "key": np.array([key]),
            "poses": self.poses, "trans_src": self.trans_src, "trans_dst": self.trans_dst,
            "trans_count": self.trans_count, "part_sigma": self.part_sigma,
            "part_features": self.part_features, "occluded": self.occluded,
            "leaf_joints": self.leaf_joints, "body_names": np.array(list(self.bodies)),
            "meta": np.array([self.build_seconds, self.dedup_deg, self.frames]),
        }
        for lv, (p, q) in enumerate(zip(self.node_pose, self.node_parent, strict=True)):
            arrays[f"node_pose{lv}"] = p
            arrays[f"node_parent{lv}"] = q
        for name, b in self.bodies.items():
            arrays[f"{name}__offset"] = b.offset
            for lv, r in enumerate(b.runs):
                for f in ("offsets", "row", "x0", "x1"):
                    arrays[f"{name}__l{lv}_{f}"] = getattr(r, f)
                arrays[f"{name}__l{lv}_size"] = np.array([r.width, r.height])
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp.npz")
        try:
            np.savez(tmp, **arrays)  # type: ignore[arg-type]
            os.replace(tmp, path)
        finally:
            tmp.unlink(missing_ok=True)
        return path

    @classmethod
    def load(cls, path: Path, options: HierarchyOptions, key: str) -> ShapeTree:
        """Read a tree written by :meth:`save`; ValueError when it is of another
        version or built from other inputs."""
        with np.load(path, allow_pickle=False) as z:
            if int(z["version"][0]) != FORMAT_VERSION or str(z["key"][0]) != key:
                raise ValueError("stale shape hierarchy cache")
            levels = sum(1 for k in z.files if k.startswith("node_pose"))
            bodies = {}
            for name in [str(s) for s in z["body_names"]]:
                runs = []
                for lv in range(levels):
                    w, h = (int(v) for v in z[f"{name}__l{lv}_size"])
                    runs.append(TemplateRuns(w, h, *(z[f"{name}__l{lv}_{f}"]
                                                     for f in ("offsets", "row", "x0", "x1"))))
                bodies[name] = BodyTemplates(name, tuple(runs), z[f"{name}__offset"])
            meta = z["meta"]
            return cls(options, z["poses"],
                       tuple(z[f"node_pose{lv}"] for lv in range(levels)),
                       tuple(z[f"node_parent{lv}"] for lv in range(levels)),
                       z["trans_src"], z["trans_dst"], z["trans_count"], z["part_sigma"],
                       z["part_features"], z["occluded"], z["leaf_joints"], bodies,
                       float(meta[0]), float(meta[1]), int(meta[2]))


def geometry_of(options: HierarchyOptions) -> WindowGeometry:
    """The window geometry the hierarchy's templates are rendered in."""
    return WindowGeometry(options.metres_per_px, camera_height=options.camera_height,
                          camera_distance=options.camera_distance)


def _part_features(skeleton: Skeleton, poses: NDArray[np.float64]
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    J = skeleton.joint_positions(poses)
    J = J - J[:, JOINT_INDEX["pelvis"] : JOINT_INDEX["pelvis"] + 1]
    feats = np.stack([J[:, [JOINT_INDEX[j] for j in names]].mean(axis=1)
                      for names in PART_JOINTS], axis=1)
    return feats, J


def build_tree(options: HierarchyOptions, progress: bool = False) -> ShapeTree:
    """Run the whole build (see the module docstring)."""
    from tqdm import tqdm

    t0 = time.perf_counter()
    ref = Skeleton.from_shape("m")
    tp = training_poses(ref, options)
    geo = geometry_of(options)
    n = len(tp.poses)
    total = n + 2 * n * len(options.bodies)  # a rough count of the renders ahead
    bar = tqdm(total=total, desc="silhouette hierarchy", unit="pose", disable=not progress)
    rendered = render_templates(ref, tp.poses, geo, progress=bar)
    rng = np.random.default_rng(options.seed)
    # Algorithm 1, level by level; children are appended parent by parent, so every
    # node's children (and leaves) are contiguous
    node_pose: list[NDArray[np.int64]] = []
    node_parent: list[NDArray[np.int64]] = []
    groups: list[NDArray[np.int64]] = [np.arange(n, dtype=np.int64)]
    owner_leaf = np.zeros(n, np.int64)
    for lv in range(3):
        protos_l: list[int] = []
        parents_l: list[int] = []
        new_groups: list[NDArray[np.int64]] = []
        for parent, members in enumerate(groups):
            protos, assign = cluster_level(rendered.runs[lv], members, options.thresholds[lv],
                                           rng, options.membership[lv], options.membership_beta)
            for k, p in enumerate(protos):
                new_groups.append(members[assign == k])
                protos_l.append(int(p))
                parents_l.append(parent if lv else -1)
        node_pose.append(np.array(protos_l, np.int64))
        node_parent.append(np.array(parents_l, np.int64))
        groups = new_groups
        bar.set_postfix_str(f"level {lv + 1}: {len(protos_l)} nodes")
    for leaf, members in enumerate(groups):
        owner_leaf[members] = leaf
    # transition histograms over leaves (eq. 5) from the training sequences
    pairs: dict[tuple[int, int], float] = {}
    for seq in tp.sequences:
        leaves = np.where(seq >= 0, owner_leaf[np.maximum(seq, 0)], -1)
        for a, b in zip(leaves[:-1], leaves[1:], strict=True):
            if a < 0 or b < 0:
                continue
            pairs[(int(a), int(b))] = pairs.get((int(a), int(b)), 0.0) + 1.0
    src = np.array([k[0] for k in pairs], np.int64)
    dst = np.array([k[1] for k in pairs], np.int64)
    cnt = np.array(list(pairs.values()), np.float64)
    # per-part std of one frame's step (eq. 13), from the training sequences
    feats_all, _ = _part_features(ref, tp.poses)
    steps = [np.linalg.norm(feats_all[s[1:]] - feats_all[s[:-1]], axis=-1)[
        (s[1:] >= 0) & (s[:-1] >= 0)] for s in tp.sequences if len(s) > 1]
    st = np.concatenate(steps) if steps else np.zeros((1, len(PART_NAMES)))
    part_sigma = np.maximum(np.sqrt(np.mean(st**2, axis=0)), 0.01)
    leaf_pose = node_pose[2]
    feats, joints = _part_features(ref, tp.poses[leaf_pose])
    px = rendered.part_pixels[leaf_pose].astype(np.float64)
    typical = np.maximum(np.median(px, axis=0), 1.0)
    occluded = px < 0.2 * typical
    bodies: dict[str, BodyTemplates] = {}
    for name in options.bodies:
        sk = Skeleton.from_shape(name)
        if name == "m":
            r = rendered
            runs = tuple(_subset(r.runs[lv], node_pose[lv]) for lv in range(3))
            offset = r.offset[leaf_pose]
            bar.update(2 * n)
        else:
            runs_l = []
            offset = np.zeros((len(leaf_pose), 3))
            for lv in range(3):
                q = tp.poses[node_pose[lv]].copy()
                q[:, 1] *= sk.pelvis_height / ref.pelvis_height
                r = render_templates(sk, q, geo, levels=(lv,))
                runs_l.append(r.runs[0])
                if lv == 2:
                    offset = r.offset
            runs = tuple(runs_l)
            bar.update(2 * n)
        bodies[name] = BodyTemplates(name, runs, offset)
    bar.close()
    return ShapeTree(options, tp.poses, tuple(node_pose), tuple(node_parent), src, dst, cnt,
                     part_sigma, feats, occluded, joints, bodies,
                     time.perf_counter() - t0, tp.dedup_deg, tp.frames)


def _subset(runs: TemplateRuns, index: NDArray[np.int64]) -> TemplateRuns:
    offs = [np.zeros(1, np.int64)]
    rows, x0s, x1s = [], [], []
    base = 0
    for i in index:
        a, b = runs.offsets[i], runs.offsets[i + 1]
        rows.append(runs.row[a:b])
        x0s.append(runs.x0[a:b])
        x1s.append(runs.x1[a:b])
        base += int(b - a)
        offs.append(np.array([base], np.int64))
    return TemplateRuns(runs.width, runs.height, np.concatenate(offs), np.concatenate(rows),
                        np.concatenate(x0s), np.concatenate(x1s))


def tree_key(options: HierarchyOptions) -> str:
    """Hash of everything that shapes the hierarchy (the cache file's name)."""
    h = hashlib.sha1()
    h.update(repr((FORMAT_VERSION, options.key_items(), clip_fingerprint(options.clips))
                  ).encode())
    for name in options.bodies:
        sk = Skeleton.from_shape(name)
        h.update(np.ascontiguousarray(sk.offsets).tobytes())
        mesh = body_mesh(sk)
        h.update(np.ascontiguousarray(mesh.rest_vertices).tobytes())
        h.update(np.ascontiguousarray(mesh.faces).tobytes())
    return h.hexdigest()[:16]


def tree_cache_path(options: HierarchyOptions, cache_dir: Path | None = None) -> Path:
    """Where the hierarchy for these options is cached."""
    from bodyplay.files import default_cache_dir

    folder = cache_dir or default_cache_dir()
    return folder / f"silhouette_tree_{tree_key(options)}.npz"


def load_or_build_tree(options: HierarchyOptions, cache_dir: Path | None = None,
                       progress: bool | None = None) -> ShapeTree:
    """The cached hierarchy for these options, built (and cached) when missing, of
    another version or damaged.

    A build is announced with a WARNING on the ``bodyplay.silhouette`` logger (it
    takes minutes and happens once per option set); ``progress`` shows a tqdm bar on
    stderr, by default only when stderr is a terminal.
    """
    path = tree_cache_path(options, cache_dir)
    key = path.stem.rsplit("_", 1)[-1]
    reason = "first use"
    if path.exists():
        try:
            return ShapeTree.load(path, options, key)
        except (OSError, ValueError, KeyError):
            path.unlink(missing_ok=True)
            reason = "the cached one is stale or damaged"
    if progress is None:
        progress = sys.stderr.isatty()
    _log.warning("building the silhouette shape hierarchy (%s): this happens once and "
                 "takes about two minutes with the default options (longer with more "
                 "clips or bodies); it is cached in %s and loaded in seconds afterwards. "
                 "`bodyplay build-db --tracker silhouette` builds it ahead of time.",
                 reason, path)
    tree = build_tree(options, progress=progress)
    try:
        tree.save(path, key)
    except OSError as exc:
        raise ConfigError(f"cannot write the shape hierarchy cache {path}: {exc}; pass a "
                          "writable cache folder") from None
    _log.info("silhouette shape hierarchy built in %.0f s, cached in %s",
              tree.build_seconds, path)
    return tree
