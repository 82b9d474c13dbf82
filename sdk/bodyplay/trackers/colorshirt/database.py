"""The pose database: tiny id maps of rendered poses, nearest-neighbour search, blending.

Poses from :func:`bodyplay.motion.sample_poses`, turned towards a *canonical camera*
(within ``yaw_deg``), are rendered as 40x40 id maps of their shirt's bounding box (with the
root's place and depth, to place a blend in any camera). A query ranks every map by
pooled one-hot features on principal components and re-ranks the best
``candidates`` by the exact per-pixel mismatch. Cached on disk under a hash of
everything that shapes it.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from dataclasses import asdict, dataclass
from functools import cached_property
from pathlib import Path

import numba
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.mesh import body_mesh
from bodyplay.body.rotations import matrix_to_rotvec, rotvec_to_matrix
from bodyplay.body.shirt import NUM_COLORS, patch_color_index
from bodyplay.body.skeleton import NODE_NAMES, Skeleton
from bodyplay.body.skinning import SkinnedMesh
from bodyplay.capture.camera import Camera, look_at
from bodyplay.errors import ConfigError
from bodyplay.files import default_cache_dir, load_cache, save_cache
from bodyplay.optiontypes import check_option_types
from bodyplay.render.idmap import rasterize_ids

__all__ = ["DatabaseOptions", "PoseDatabase", "Neighbours", "BlendedPose", "canonical_camera",
           "sample_database_poses", "build_database", "load_or_build_database",
           "shirt_color_face_ids", "mismatch", "blend_poses"]

_FORMAT_VERSION = 4
_CACHE_KIND = "colorshirt_pose_database"
_POOL = 4  # feature pooling block (40x40 -> 10x10)


@dataclass(frozen=True)
class DatabaseOptions:
    """What the database holds and how it is searched: ``size`` poses (paper: 80,000),
    ``map_size`` the id maps' side, ``yaw_deg`` and ``tilt_deg`` (largest lean) about
    the canonical camera, the coarse search (``pca_dims``, ``candidates``),
    ``neighbours`` blended, ``margin`` the crop's margin."""

    size: int = 20_000
    map_size: int = 40
    seed: int = 0
    yaw_deg: float = 80.0
    tilt_deg: float = 12.0
    pca_dims: int = 64
    candidates: int = 128
    neighbours: int = 10
    margin: float = 0.05

    def __post_init__(self) -> None:
        check_option_types(self)
        if self.size < 20:
            raise ConfigError("the pose database needs at least 20 poses")
        if self.map_size % _POOL or self.map_size < 8:
            raise ConfigError(f"map_size must be a multiple of {_POOL} and at least 8")
        if not 1 <= self.neighbours <= self.candidates:
            raise ConfigError("neighbours must be between 1 and candidates")
        if self.pca_dims < 4:
            raise ConfigError("pca_dims must be at least 4")
        if not 0 < self.yaw_deg <= 180:
            raise ConfigError(f"yaw_deg must be within (0, 180] degrees, got {self.yaw_deg}")

    def cache_key(self, skeleton: Skeleton, mesh: SkinnedMesh, sampler: str) -> str:
        """Hash of the options, skeleton, mesh and pose sampler: the cache file's name."""
        h = hashlib.sha1()
        h.update(repr((_FORMAT_VERSION, sorted(asdict(self).items()), sampler)).encode())
        h.update(np.ascontiguousarray(skeleton.offsets, np.float64).tobytes())
        for arr in (mesh.rest_vertices, mesh.faces, mesh.face_part, mesh.bone_weights,
                    mesh.bone_indices):
            h.update(np.ascontiguousarray(arr).tobytes())
        return h.hexdigest()[:16]


def canonical_camera() -> Camera:
    """The camera database poses are rendered from: 640x480, 60 degrees, 3 m away."""
    R, t = look_at((0.0, 1.25, 3.0), (0.0, 1.25, 0.0))
    return Camera.from_fov("canonical", 640, 480, 60.0, R, t)


def shirt_color_face_ids(mesh: SkinnedMesh) -> NDArray[np.uint8]:
    """(F,) color id (color index + 1) of each shirt face, 0 for other faces."""
    cidx = patch_color_index()
    fp = mesh.face_part.astype(np.int64)
    return np.where(fp > 0, cidx[fp] + 1, 0).astype(np.uint8)


def shirt_vertex_mask(mesh: SkinnedMesh) -> NDArray[np.bool_]:
    """(V,) whether each vertex belongs to a shirt face."""
    m = np.zeros(mesh.num_vertices, bool)
    m[mesh.faces[mesh.face_part > 0].ravel()] = True
    return m


def sample_database_poses(
    skeleton: Skeleton, n: int, rng: np.random.Generator, options: DatabaseOptions
) -> NDArray[np.float64]:
    """``n`` upper-body poses from :func:`bodyplay.motion.sample_poses`, facing the
    canonical camera within ``options.yaw_deg``."""
    from bodyplay.motion import list_builtin_clips, sample_poses

    yaw = float(np.radians(options.yaw_deg))
    q = np.array(
        sample_poses(
            skeleton, n, rng, mode="mixed" if list_builtin_clips() else "upper_body",
            yaw_range=(-yaw, yaw), max_tilt=float(np.radians(options.tilt_deg)),
            oversample=1.0,
        ),
        dtype=np.float64,
    )
    if q.shape != (n, skeleton.pose_dim):
        raise ConfigError(f"sample_poses returned {q.shape}, expected {(n, skeleton.pose_dim)}")
    return q


@numba.njit(cache=True, parallel=True)
def _project_crops(  # pragma: no cover - compiled
    verts: NDArray[np.float32],
    R: NDArray[np.float64],
    t: NDArray[np.float64],
    K: NDArray[np.float64],
    vmask: NDArray[np.bool_],
    size: int,
    margin: float,
) -> tuple[NDArray[np.float32], NDArray[np.float64], NDArray[np.float64]]:
    """Pinhole projection and the crop normalization of ``crop_transform`` in one pass."""
    B, V = verts.shape[0], verts.shape[1]
    uvz = np.empty((B, V, 3), np.float32)
    scale = np.ones(B)
    offset = np.zeros((B, 2))
    for b in numba.prange(B):
        lo0 = np.inf
        lo1 = np.inf
        hi0 = -np.inf
        hi1 = -np.inf
        for v in range(V):
            x = verts[b, v, 0]
            y = verts[b, v, 1]
            z = verts[b, v, 2]
            cx = R[0, 0] * x + R[0, 1] * y + R[0, 2] * z + t[0]
            cy = R[1, 0] * x + R[1, 1] * y + R[1, 2] * z + t[1]
            cz = R[2, 0] * x + R[2, 1] * y + R[2, 2] * z + t[2]
            u = K[0, 0] * cx / cz + K[0, 1] * cy / cz + K[0, 2]
            w = K[1, 1] * cy / cz + K[1, 2]
            uvz[b, v, 0] = u
            uvz[b, v, 1] = w
            uvz[b, v, 2] = cz
            if vmask[v] and cz > 1e-9:
                lo0 = min(lo0, u)
                hi0 = max(hi0, u)
                lo1 = min(lo1, w)
                hi1 = max(hi1, w)
        if lo0 < hi0 or lo1 < hi1:
            extent = max(max(hi0 - lo0, hi1 - lo1), 1e-6)
            s = size * (1.0 - 2.0 * margin) / extent
            o0 = (size - 1) / 2.0 - 0.5 * (lo0 + hi0) * s
            o1 = (size - 1) / 2.0 - 0.5 * (lo1 + hi1) * s
            scale[b] = s
            offset[b, 0] = o0
            offset[b, 1] = o1
            for v in range(V):
                uvz[b, v, 0] = uvz[b, v, 0] * s + o0
                uvz[b, v, 1] = uvz[b, v, 1] * s + o1
    return uvz, scale, offset


@numba.njit(cache=True, nogil=True)
def _pooled_onehot(  # pragma: no cover - compiled
    ids: NDArray[np.uint8], pool: int, ncls: int
) -> NDArray[np.float32]:
    """(B, S, S) id maps -> (B, (S / pool)^2 * ncls) one-hot colors averaged over blocks,
    on the calling thread."""
    B, S = ids.shape[0], ids.shape[1]
    g = S // pool
    out = np.zeros((B, g, g, ncls), np.float32)
    inv = np.float32(1.0 / (pool * pool))
    for b in range(B):
        for y in range(S):
            for x in range(S):
                out[b, y // pool, x // pool, ids[b, y, x]] += inv
    return out.reshape(B, g * g * ncls)


@numba.njit(cache=True, nogil=True, fastmath=True)
def _matvec(A: NDArray[np.float32], x: NDArray[np.float32]
            ) -> NDArray[np.float32]:  # pragma: no cover - compiled
    """``A @ x`` on the calling thread (numpy's would wake OpenBLAS's thread pool)."""
    out = np.empty(A.shape[0], np.float32)
    for i in range(A.shape[0]):
        s = np.float32(0.0)
        for j in range(A.shape[1]):
            s += A[i, j] * x[j]
        out[i] = s
    return out


def _features(ids: NDArray[np.uint8]) -> NDArray[np.float32]:
    """(B, S, S) color id maps -> (B, (S/4)^2 * 11) pooled one-hot features."""
    return _pooled_onehot(np.ascontiguousarray(ids, np.uint8), _POOL, NUM_COLORS + 1)


def mismatch(a: NDArray[np.uint8], b: NDArray[np.uint8]) -> NDArray[np.int64]:
    """Per-pixel mismatch count between id maps (broadcasting over leading axes)."""
    return np.count_nonzero(a != b, axis=(-2, -1))


def blend_poses(poses: NDArray[np.float64], weights: NDArray[np.float64]) -> NDArray[np.float64]:
    """Weighted blend of pose vectors: roots averaged, every node rotation averaged on SO(3).

    The weighted mean of the rotation matrices is projected back onto SO(3) (SVD),
    which stays sensible for the spread of a few nearest neighbours.
    """
    w = np.asarray(weights, dtype=np.float64)
    w = w / w.sum()
    q = np.asarray(poses, dtype=np.float64)
    n = len(NODE_NAMES)
    R = rotvec_to_matrix(q[:, 3:].reshape(-1, n, 3))
    M = np.einsum("b,bnij->nij", w, R)
    U, _, Vt = np.linalg.svd(M)
    D = np.ones((n, 3))
    D[:, 2] = np.sign(np.linalg.det(U @ Vt))
    Rm = np.einsum("nij,nj,njk->nik", U, D, Vt)
    out = q[0].copy()
    out[0:3] = w @ q[:, 0:3]
    out[3:] = matrix_to_rotvec(Rm).reshape(-1)
    return out


@dataclass(frozen=True, eq=False)
class Neighbours:
    """The nearest database entries of a query: indices and mismatch fractions."""

    index: NDArray[np.int64]
    distance: NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class BlendedPose:
    """A weighted blend of neighbours, relative to the canonical camera.

    ``pose`` has the canonical root and orientation; ``root_crop`` is where the root
    projects in the normalized crop, ``root_depth`` its depth and ``crop_scale`` the
    crop pixels per canonical image pixel, all blended.
    """

    pose: NDArray[np.float64]
    root_crop: NDArray[np.float64]
    root_depth: float
    crop_scale: float
    distance: float


@dataclass(frozen=True, eq=False)
class PoseDatabase:
    """Rendered poses and their search structure (see the module docstring)."""

    options: DatabaseOptions
    poses: NDArray[np.float32]
    ids: NDArray[np.uint8]
    root_crop: NDArray[np.float32]
    root_depth: NDArray[np.float32]
    crop_scale: NDArray[np.float32]
    pca_mean: NDArray[np.float32]
    pca_basis: NDArray[np.float32]
    features: NDArray[np.float32]

    def __len__(self) -> int:
        return int(self.poses.shape[0])

    @cached_property
    def _feature_norms(self) -> NDArray[np.float32]:
        return np.einsum("nd,nd->n", self.features, self.features)

    @cached_property
    def facings(self) -> NDArray[np.float64]:
        """Each pose's forward axis (its root's z) in the canonical camera's frame."""
        R = rotvec_to_matrix(self.poses[:, 3:6].astype(np.float64))
        return np.asarray(np.einsum("ij,nj->ni", canonical_camera().R, R[:, :, 2]))

    def query_features(self, idmap: NDArray[np.uint8]) -> NDArray[np.float32]:
        """Project one id map onto the principal components."""
        f = _features(idmap[None])[0] - self.pca_mean
        return _matvec(self.pca_basis, np.asarray(f, np.float32))

    def query(self, idmap: NDArray[np.uint8], exact: bool = False,
              facing: NDArray[np.float64] | None = None, min_cos: float = 0.0) -> Neighbours:
        """The ``options.neighbours`` nearest maps by pixel mismatch.

        ``exact`` scans every map (slow; for measuring the coarse search's recall).
        ``facing``: the forward axis expected (camera frame, as :attr:`facings`);
        only poses whose own is within ``arccos(min_cos)`` of it are searched, when
        there are enough (front and back of the shirt can look alike in 40x40).
        """
        o = self.options
        if idmap.shape != (o.map_size, o.map_size):
            raise ConfigError(f"query id map must be {o.map_size}x{o.map_size}")
        if exact:
            cand = np.arange(len(self))
        else:
            f = self.query_features(idmap)
            d = self._feature_norms - 2.0 * _matvec(self.features, f)
            m = min(o.candidates, len(self) - 1)
            if facing is not None:
                ok = self.facings @ np.asarray(facing, np.float64) >= min_cos
                if int(ok.sum()) > m:
                    d = np.where(ok, d, np.inf).astype(np.float32)
            cand = np.argpartition(d, m)[:m]
        mis = mismatch(self.ids[cand], idmap[None])
        order = np.argsort(mis, kind="stable")[:o.neighbours]
        return Neighbours(cand[order].astype(np.int64),
                          mis[order].astype(np.float64) / float(idmap.size))

    def blend(self, nb: Neighbours) -> BlendedPose:
        """Inverse-distance blend of the neighbours' poses (rotations averaged on SO(3))."""
        w = 1.0 / (nb.distance + 0.02)
        w = w / w.sum()
        return BlendedPose(
            blend_poses(self.poses[nb.index].astype(np.float64), w),
            w @ self.root_crop[nb.index].astype(np.float64),
            float(w @ self.root_depth[nb.index]),
            float(w @ self.crop_scale[nb.index]),
            float(nb.distance[0]),
        )

    # ---- persistence --------------------------------------------------------------
    def save(self, path: Path, key: str = "") -> Path:
        """Write as a compressed ``.npz`` stamped with ``key`` (see
        :meth:`DatabaseOptions.cache_key`) and the format version, atomically
        (:func:`bodyplay.files.save_cache`: a killed build never leaves half a file)."""
        arrays: dict[str, NDArray[np.generic]] = {
            "poses": self.poses, "ids": self.ids, "root_crop": self.root_crop,
            "root_depth": self.root_depth, "crop_scale": self.crop_scale,
            "pca_mean": self.pca_mean, "pca_basis": self.pca_basis}
        return save_cache(path, arrays, kind=_CACHE_KIND, key=key, version=_FORMAT_VERSION)

    @classmethod
    def load(cls, path: Path, options: DatabaseOptions, key: str = "") -> PoseDatabase:
        """Read a database written by :meth:`save` with the same ``key`` (features are
        recomputed); ConfigError if it is missing, damaged or made for other inputs or
        another version (never loaded with pickle)."""
        data = load_cache(path, kind=_CACHE_KIND, key=key, version=_FORMAT_VERSION)
        if data is None:
            raise ConfigError(f"{path}: not a pose database of this version for these inputs")
        ids = data["ids"]
        feats = (_features(ids) - data["pca_mean"]) @ data["pca_basis"].T
        return cls(options, data["poses"], ids, data["root_crop"], data["root_depth"],
                   data["crop_scale"], data["pca_mean"], data["pca_basis"],
                   np.ascontiguousarray(feats, np.float32))


def build_database(
    skeleton: Skeleton,
    options: DatabaseOptions,
    poses: NDArray[np.float64],
    progress: bool = False,
    chunk: int = 2000,
) -> PoseDatabase:
    """Render the database: ``poses`` (e.g. :func:`sample_database_poses`) as id maps."""
    from tqdm import tqdm

    mesh = body_mesh(skeleton)
    poses = np.asarray(poses, dtype=np.float64)
    n = poses.shape[0]
    cam = canonical_camera()
    face_ids = shirt_color_face_ids(mesh)
    vmask = shirt_vertex_mask(mesh)
    S = options.map_size
    ids = np.zeros((n, S, S), np.uint8)
    root_crop = np.zeros((n, 2), np.float32)
    root_depth = np.zeros(n, np.float32)
    crop_scale = np.zeros(n, np.float32)
    bar = tqdm(total=n, desc="rendering pose database", unit="pose", disable=not progress)
    for s in range(0, n, chunk):
        q = poses[s : s + chunk]
        verts = mesh.pose(skeleton, q)
        uvz, scale, offset = _project_crops(verts, cam.R, cam.t, cam.K, vmask, S,
                                            options.margin)
        out = rasterize_ids(uvz, mesh.faces, face_ids, S, S)
        ids[s : s + len(q)] = out
        root_px = cam.project(q[:, 0:3])
        root_crop[s : s + len(q)] = root_px * scale[:, None] + offset
        root_depth[s : s + len(q)] = cam.world_to_camera(q[:, 0:3])[:, 2]
        crop_scale[s : s + len(q)] = scale
        bar.update(len(q))
    bar.close()
    feats = _features(ids)
    rng = np.random.default_rng(options.seed + 1)
    sub = feats[rng.choice(n, size=min(n, 8000), replace=False)]
    mean = sub.mean(axis=0)
    _, _, Vt = np.linalg.svd(sub - mean, full_matrices=False)
    basis = Vt[: options.pca_dims].astype(np.float32)
    proj = ((feats - mean) @ basis.T).astype(np.float32)
    return PoseDatabase(options, poses.astype(np.float32), ids, root_crop, root_depth, crop_scale,
                        mean.astype(np.float32), basis, np.ascontiguousarray(proj))


def load_or_build_database(
    skeleton: Skeleton,
    options: DatabaseOptions,
    cache_dir: Path | None = None,
    progress: bool = False,
    pose_source: Callable[[Skeleton, int, np.random.Generator, DatabaseOptions],
                          NDArray[np.float64]] | None = None,
) -> PoseDatabase:
    """The cached database for these inputs, building (and caching) it when missing."""
    sampler = pose_source or sample_database_poses
    mesh = body_mesh(skeleton)
    name = f"{getattr(sampler, '__module__', '')}.{getattr(sampler, '__qualname__', 'poses')}"
    key = options.cache_key(skeleton, mesh, name)
    folder = cache_dir or default_cache_dir()
    path = folder / f"colorshirt_db_{options.size}_{key}.npz"
    if path.exists():
        try:
            return PoseDatabase.load(path, options, key)
        except (OSError, ValueError, KeyError):
            pass  # damaged, or made by another version or for another body: rebuilt
    poses = sampler(skeleton, options.size, np.random.default_rng(options.seed), options)
    db = build_database(skeleton, options, poses, progress=progress)
    try:
        db.save(path, key)
    except OSError as exc:
        raise ConfigError(f"cannot write the pose database cache {path}: {exc}; "
                          "pass a writable --cache folder") from None
    return db
