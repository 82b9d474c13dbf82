"""Id maps and silhouettes of posed triangle meshes: a batched numba z-buffer rasterizer.

Both trackers compare camera images against many rendered poses: the color-shirt
tracker looks up 40x40 maps of patch ids, the silhouette tracker compares binary
masks at 80x60 to 320x240. Rendering those with OpenGL means one draw and one
read-back per pose; here a whole batch of poses is rasterized on the CPU in one
numba call, parallel over the batch, which is faster for small maps.

Conventions (the same as :class:`bodyplay.capture.camera.Camera` and OpenCV):

* pixel ``(x, y)`` covers ``[x - 0.5, x + 0.5] x [y - 0.5, y + 0.5]``; coverage is
  sampled at the pixel centres (integer coordinates), image row 0 is the top row;
* vertex positions are snapped to 1/256 pixel and edge functions evaluated exactly
  in integers, with the top-left fill rule (as Direct3D and OpenGL implementations
  do), so triangles sharing an edge neither leave gaps nor both cover a pixel;
* depth is the camera-space Z (distance along the optical axis); the z-test
  interpolates 1/Z, which is linear in screen space, and the nearer surface wins;
  on exact ties the earlier face wins (as with ``GL_LESS``);
* triangles with a vertex at or behind the ``near`` depth are skipped, not clipped
  (fine for bodies in front of a camera), as are triangles with a vertex more than
  a million pixels away from the image origin;
* id 0 is the background; face ids should be 1..255.

:func:`rasterize_ids` works on already-projected vertices ``(x, y, depth)`` so that
a tracker may project into any crop; :func:`project_vertices`,
:func:`crop_transform`, :func:`render_idmaps`, :func:`render_crops` and
:func:`silhouettes` are conveniences on top of it.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Literal, no_type_check, overload

import numpy as np
from numba import njit, prange
from numpy.typing import ArrayLike, NDArray

from bodyplay.capture.camera import Camera
from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types

__all__ = [
    "CropResult",
    "IdMapRenderer",
    "IdMapRendererOptions",
    "crop_transform",
    "project_vertices",
    "rasterize_ids",
    "render_crops",
    "render_idmaps",
    "silhouettes",
]

_SUB = 256  # sub-pixel resolution of snapped vertex coordinates
_LIMIT = 1.0e6  # vertices further than this many pixels make the triangle skipped
_MAX_SIZE = 8192


# ---- the kernel ----------------------------------------------------------------------


@njit(cache=True, nogil=True)
@no_type_check
def _raster_one(uvz, faces, face_ids, width, height, near, cull, ids, invz):
    """Rasterize one posed mesh into ``ids`` (H, W) uint8 and ``invz`` (H, W) 1/depth.

    Both buffers must be zeroed by the caller. ``cull`` skips faces whose vertices
    run clockwise as seen by the camera (back faces of outward-wound meshes).
    """
    sub = _SUB
    # snap every vertex once (each is shared by about six faces); rz < 0 marks a
    # vertex that is behind the near depth, too far away or not finite
    nv = uvz.shape[0]
    sx = np.empty(nv, np.int64)
    sy = np.empty(nv, np.int64)
    rz = np.empty(nv, np.float64)
    for v in range(nv):
        x = uvz[v, 0]
        y = uvz[v, 1]
        z = uvz[v, 2]
        if z > near and x > -_LIMIT and x < _LIMIT and y > -_LIMIT and y < _LIMIT:
            sx[v] = np.int64(np.floor(x * sub + 0.5))
            sy[v] = np.int64(np.floor(y * sub + 0.5))
            rz[v] = 1.0 / z
        else:
            sx[v] = 0
            sy[v] = 0
            rz[v] = -1.0
    for f in range(faces.shape[0]):
        ia = faces[f, 0]
        ib = faces[f, 1]
        ic = faces[f, 2]
        ra = rz[ia]
        rb = rz[ib]
        rc = rz[ic]
        if ra < 0.0 or rb < 0.0 or rc < 0.0:
            continue
        xa = sx[ia]
        xb = sx[ib]
        xc = sx[ic]
        # pixel centres px * sub inside [min, max]; most faces of a small map
        # cover none and leave here
        x0 = int(max((min(xa, xb, xc) + sub - 1) // sub, 0))
        x1 = int(min(max(xa, xb, xc) // sub, width - 1))
        if x0 > x1:
            continue
        ya = sy[ia]
        yb = sy[ib]
        yc = sy[ic]
        y0 = int(max((min(ya, yb, yc) + sub - 1) // sub, 0))
        y1 = int(min(max(ya, yb, yc) // sub, height - 1))
        if y0 > y1:
            continue
        area = (xb - xa) * (yc - ya) - (xc - xa) * (yb - ya)
        if area == 0:
            continue
        if cull and area > 0:
            # area > 0 is clockwise on screen (y down), i.e. counter-clockwise in a
            # y-up view turned around: the face is seen from its back
            continue
        if area < 0:
            # orient so that the edge functions are positive inside
            xb, xc = xc, xb
            yb, yc = yc, yb
            rb, rc = rc, rb
            area = -area
        # edge functions E(p) = (q - p0) x (p - p0) for edges b->c, c->a, a->b;
        # top-left rule: a pixel centre exactly on an edge belongs to the triangle
        # only if the edge is a top edge (horizontal, going right) or a left edge
        # (going up, y down)
        bias0 = 0 if (yc - yb < 0 or (yc == yb and xc - xb > 0)) else 1
        bias1 = 0 if (ya - yc < 0 or (ya == yc and xa - xc > 0)) else 1
        bias2 = 0 if (yb - ya < 0 or (yb == ya and xb - xa > 0)) else 1
        inv_area = 1.0 / float(area)
        fid = face_ids[f]
        step0 = -(yc - yb) * sub
        step1 = -(ya - yc) * sub
        step2 = -(yb - ya) * sub
        for py in range(y0, y1 + 1):
            qy = py * sub
            qx = x0 * sub
            e0 = (xc - xb) * (qy - yb) - (yc - yb) * (qx - xb) - bias0
            e1 = (xa - xc) * (qy - yc) - (ya - yc) * (qx - xc) - bias1
            e2 = (xb - xa) * (qy - ya) - (yb - ya) * (qx - xa) - bias2
            for px in range(x0, x1 + 1):
                if e0 >= 0 and e1 >= 0 and e2 >= 0:
                    w = ((e0 + bias0) * ra + (e1 + bias1) * rb + (e2 + bias2) * rc) * inv_area
                    if w > invz[py, px]:
                        invz[py, px] = w
                        ids[py, px] = fid
                e0 += step0
                e1 += step1
                e2 += step2
    return 0


@njit(parallel=True, cache=True)
@no_type_check
def _raster_batch(uvz, faces, face_ids, width, height, near, cull, ids):
    for b in prange(uvz.shape[0]):
        invz = np.zeros((height, width), np.float32)
        _raster_one(uvz[b], faces, face_ids, width, height, near, cull, ids[b], invz)
    return 0


@njit(parallel=True, cache=True)
@no_type_check
def _raster_batch_depth(uvz, faces, face_ids, width, height, near, cull, ids, invz):
    for b in prange(uvz.shape[0]):
        _raster_one(uvz[b], faces, face_ids, width, height, near, cull, ids[b], invz[b])
    return 0


@njit(cache=True)
@no_type_check
def _raster_single(uvz, faces, face_ids, width, height, near, cull, ids, invz):
    return _raster_one(uvz, faces, face_ids, width, height, near, cull, ids, invz)


# ---- the public API ------------------------------------------------------------------


def _check_size(width: int, height: int) -> tuple[int, int]:
    w, h = int(width), int(height)
    if not (0 < w <= _MAX_SIZE and 0 < h <= _MAX_SIZE):
        raise ConfigError(f"id map size {w}x{h} must be between 1 and {_MAX_SIZE} pixels a side")
    return w, h


def _check_mesh(
    faces: ArrayLike, face_ids: ArrayLike | None, n_vertices: int
) -> tuple[NDArray[np.int32], NDArray[np.uint8]]:
    f = np.ascontiguousarray(faces, dtype=np.int32)
    if f.ndim != 2 or f.shape[1] != 3:
        raise ConfigError(f"faces must have shape (F, 3), got {f.shape}")
    if f.size and (f.min() < 0 or f.max() >= n_vertices):
        raise ConfigError(f"faces index vertices outside 0..{n_vertices - 1}")
    if face_ids is None:
        ids = np.ones(len(f), dtype=np.uint8)
    else:
        raw = np.asarray(face_ids)
        if raw.shape != (len(f),):
            raise ConfigError(f"face_ids must have shape ({len(f)},), got {raw.shape}")
        if raw.size and (raw.min() < 0 or raw.max() > 255):
            raise ConfigError("face_ids must be in 0..255 (0 draws as background)")
        ids = np.ascontiguousarray(raw, dtype=np.uint8)
    return f, ids


@overload
def rasterize_ids(
    uvz: ArrayLike,
    faces: ArrayLike,
    face_ids: ArrayLike | None,
    width: int,
    height: int,
    *,
    return_depth: Literal[False] = False,
    cull_backfaces: bool = False,
    near: float = 1e-3,
) -> NDArray[np.uint8]: ...


@overload
def rasterize_ids(
    uvz: ArrayLike,
    faces: ArrayLike,
    face_ids: ArrayLike | None,
    width: int,
    height: int,
    *,
    return_depth: Literal[True],
    cull_backfaces: bool = False,
    near: float = 1e-3,
) -> tuple[NDArray[np.uint8], NDArray[np.float32]]: ...


def rasterize_ids(
    uvz: ArrayLike,
    faces: ArrayLike,
    face_ids: ArrayLike | None,
    width: int,
    height: int,
    *,
    return_depth: bool = False,
    cull_backfaces: bool = False,
    near: float = 1e-3,
) -> NDArray[np.uint8] | tuple[NDArray[np.uint8], NDArray[np.float32]]:
    """Id maps of a batch of projected meshes: (B, V, 3) pixel x, pixel y, depth.

    Returns (B, H, W) uint8 ids (0 = background), or for a single (V, 3) mesh an
    (H, W) map. With ``return_depth`` also the depth of the visible surface per
    pixel (float32, ``inf`` on background). ``face_ids`` None gives every face id 1.
    ``cull_backfaces`` skips faces seen from behind (about twice as fast; only for
    closed meshes whose faces wind counter-clockwise seen from outside).
    """
    arr = np.asarray(uvz, dtype=np.float32)
    single = arr.ndim == 2
    if single:
        arr = arr[None]
    if arr.ndim != 3 or arr.shape[2] != 3:
        raise ConfigError(f"uvz must have shape (B, V, 3) or (V, 3), got {np.shape(uvz)}")
    arr = np.ascontiguousarray(arr)
    w, h = _check_size(width, height)
    f, fid = _check_mesh(faces, face_ids, arr.shape[1])
    B = arr.shape[0]
    ids = np.zeros((B, h, w), dtype=np.uint8)
    near_f = float(near)
    cull = bool(cull_backfaces)
    if return_depth:
        invz = np.zeros((B, h, w), dtype=np.float32)
        if B == 1:
            _raster_single(arr[0], f, fid, w, h, near_f, cull, ids[0], invz[0])
        else:
            _raster_batch_depth(arr, f, fid, w, h, near_f, cull, ids, invz)
        with np.errstate(divide="ignore"):
            depth = np.where(invz > 0, 1.0 / invz, np.inf).astype(np.float32)
        return (ids[0], depth[0]) if single else (ids, depth)
    if B == 1:
        _raster_single(arr[0], f, fid, w, h, near_f, cull, ids[0], np.zeros((h, w), np.float32))
    elif B > 1:
        _raster_batch(arr, f, fid, w, h, near_f, cull, ids)
    return ids[0] if single else ids


def project_vertices(vertices_world: ArrayLike, camera: Camera) -> NDArray[np.float32]:
    """World vertices (..., V, 3) to (..., V, 3) float32 pixel x, pixel y, camera depth.

    A pinhole projection with ``camera.K``, ``R``, ``t``; lens distortion is ignored
    (straight edges stay straight, which the rasterizer needs): undistort images,
    or render with a distortion-free camera, before comparing. Points at or behind
    the camera get NaN pixel coordinates and are skipped by the rasterizer.
    """
    p = np.asarray(vertices_world, dtype=np.float64)
    if p.shape[-1] != 3:
        raise ConfigError(f"vertices must have shape (..., V, 3), got {p.shape}")
    pc = p @ camera.R.T + camera.t
    z = pc[..., 2]
    K = camera.K
    with np.errstate(divide="ignore", invalid="ignore"):
        x = pc[..., 0] / z
        y = pc[..., 1] / z
    out = np.empty(p.shape, dtype=np.float32)
    out[..., 0] = K[0, 0] * x + K[0, 1] * y + K[0, 2]
    out[..., 1] = K[1, 1] * y + K[1, 2]
    out[..., 2] = z
    behind = z <= 1e-9
    out[..., 0][behind] = np.nan
    out[..., 1][behind] = np.nan
    return out


@dataclass(frozen=True, eq=False)
class CropResult:
    """Projected vertices moved into square ``size`` x ``size`` crops, one per pose.

    ``uvz`` (B, V, 3) are the vertices in crop pixels (depth unchanged); a point at
    image pixel ``p`` lands at ``p * scale[b] + offset[b]`` in crop ``b``.
    """

    uvz: NDArray[np.float32]
    scale: NDArray[np.float64]
    offset: NDArray[np.float64]
    size: int

    def to_crop(self, uv: ArrayLike) -> NDArray[np.float64]:
        """Image pixel coordinates (B, ..., 2) to crop pixel coordinates."""
        p = np.asarray(uv, dtype=np.float64)
        B = len(self.scale)
        shape = (B,) + (1,) * (p.ndim - 2)
        return p * self.scale.reshape(shape + (1,)) + self.offset.reshape(shape + (2,))

    def to_image(self, uv: ArrayLike) -> NDArray[np.float64]:
        """Crop pixel coordinates (B, ..., 2) back to image pixel coordinates."""
        p = np.asarray(uv, dtype=np.float64)
        B = len(self.scale)
        shape = (B,) + (1,) * (p.ndim - 2)
        return (p - self.offset.reshape(shape + (2,))) / self.scale.reshape(shape + (1,))


def crop_transform(
    uvz: ArrayLike,
    size: int,
    margin: float = 0.05,
    vertex_mask: ArrayLike | None = None,
) -> CropResult:
    """Scale and shift each pose's projection so its bounding box fills a square crop.

    The bounding box of the (masked) vertices, e.g. those of the shirt, is centred
    in a ``size`` x ``size`` map with ``margin`` (a fraction of ``size``) free on the
    longer side; the aspect ratio is kept. This is how the color-shirt database
    normalizes each pose to a 40x40 map. Poses whose masked vertices are all
    invisible keep scale 1 and offset 0.
    """
    arr = np.asarray(uvz, dtype=np.float32)
    single = arr.ndim == 2
    if single:
        arr = arr[None]
    if arr.ndim != 3 or arr.shape[2] != 3:
        raise ConfigError(f"uvz must have shape (B, V, 3) or (V, 3), got {np.shape(uvz)}")
    n = int(size)
    if n <= 0 or n > _MAX_SIZE:
        raise ConfigError(f"crop size {size} must be between 1 and {_MAX_SIZE}")
    if not 0.0 <= margin < 0.5:
        raise ConfigError(f"crop margin {margin} must be in [0, 0.5)")
    sel = arr[:, :, :2].astype(np.float64)
    if vertex_mask is not None:
        mask = np.asarray(vertex_mask, dtype=bool)
        if mask.shape != (arr.shape[1],):
            raise ConfigError(f"vertex_mask must have shape ({arr.shape[1]},), got {mask.shape}")
        sel = sel[:, mask]
    finite = np.asarray(np.isfinite(sel).all(axis=2), dtype=bool)
    big = np.where(finite[..., None], sel, np.nan)
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows: invisible poses
        lo = np.nanmin(big, axis=1)
        hi = np.nanmax(big, axis=1)
    ok = np.asarray(np.isfinite(lo).all(axis=1), dtype=bool)
    extent = np.where(ok, np.max(hi - lo, axis=1), 1.0)
    extent = np.maximum(extent, 1e-6)
    scale = np.where(ok, n * (1.0 - 2.0 * margin) / extent, 1.0)
    centre = np.where(ok[:, None], 0.5 * (lo + hi), 0.0)
    # the crop's centre in pixel-centre coordinates is (n - 1) / 2
    offset = np.where(ok[:, None], (n - 1) / 2.0 - centre * scale[:, None], 0.0)
    out = arr.copy()
    out[:, :, 0] = arr[:, :, 0] * scale[:, None] + offset[:, 0:1]
    out[:, :, 1] = arr[:, :, 1] * scale[:, None] + offset[:, 1:2]
    return CropResult(uvz=out, scale=scale, offset=offset, size=n)


def _camera_for(camera: Camera, size: tuple[int, int] | None) -> Camera:
    if size is None:
        return camera
    w, h = _check_size(*size)
    return camera if (w, h) == (camera.width, camera.height) else camera.with_size(w, h)


def render_idmaps(
    vertices_world: ArrayLike,
    faces: ArrayLike,
    face_ids: ArrayLike | None,
    camera: Camera,
    size: tuple[int, int] | None = None,
    *,
    cull_backfaces: bool = False,
) -> NDArray[np.uint8]:
    """Id maps (B, H, W) of posed meshes (B, V, 3) seen by ``camera`` (no distortion).

    ``size`` (width, height) renders the camera's view resampled to another size
    (e.g. (160, 120) for a 640x480 camera); None uses the camera's own size.
    """
    cam = _camera_for(camera, size)
    uvz = project_vertices(vertices_world, cam)
    return rasterize_ids(
        uvz, faces, face_ids, cam.width, cam.height, cull_backfaces=cull_backfaces
    )


def render_crops(
    vertices_world: ArrayLike,
    faces: ArrayLike,
    face_ids: ArrayLike | None,
    camera: Camera,
    size: int = 40,
    *,
    margin: float = 0.05,
    vertex_mask: ArrayLike | None = None,
    cull_backfaces: bool = False,
) -> tuple[NDArray[np.uint8], CropResult]:
    """Square id maps of each pose's (masked) bounding box, as the color-shirt database.

    Returns the (B, size, size) maps and the :class:`CropResult` that maps image
    pixels into each crop.
    """
    crop = crop_transform(project_vertices(vertices_world, camera), size, margin, vertex_mask)
    ids = rasterize_ids(
        crop.uvz, faces, face_ids, crop.size, crop.size, cull_backfaces=cull_backfaces
    )
    return ids, crop


def silhouettes(
    vertices_world: ArrayLike,
    faces: ArrayLike,
    camera: Camera,
    size: tuple[int, int] | None = None,
    *,
    cull_backfaces: bool = False,
) -> NDArray[np.bool_]:
    """Binary silhouettes (B, H, W) of posed meshes (B, V, 3) seen by ``camera``."""
    ids = render_idmaps(vertices_world, faces, None, camera, size, cull_backfaces=cull_backfaces)
    return ids > 0


@dataclass(frozen=True)
class IdMapRendererOptions:
    """Size of the maps an :class:`IdMapRenderer` draws, and whether it culls back faces."""

    width: int = 160
    height: int = 120
    cull_backfaces: bool = False
    near: float = 1e-3

    def __post_init__(self) -> None:
        check_option_types(self)
        _check_size(self.width, self.height)
        if not self.near > 0:
            raise ConfigError(f"near depth {self.near} must be positive")


class IdMapRenderer:
    """Renders id maps of one mesh topology (faces and face ids fixed) for many poses.

    Keeping the validated faces and ids saves re-checking them on every call, which
    matters for single-map calls inside a tracker loop.
    """

    def __init__(
        self, options: IdMapRendererOptions, faces: ArrayLike, face_ids: ArrayLike | None
    ) -> None:
        self.options = options
        f = np.asarray(faces)
        n_vertices = int(f.max()) + 1 if f.size else 0
        self.faces, self.face_ids = _check_mesh(f, face_ids, n_vertices)
        self._n_needed = n_vertices
        self._zbuf = np.zeros((options.height, options.width), np.float32)

    def render_uvz(self, uvz: ArrayLike) -> NDArray[np.uint8]:
        """Id maps (B, H, W) of projected vertices (B, V, 3); (H, W) for one (V, 3)."""
        o = self.options
        arr = np.ascontiguousarray(uvz, dtype=np.float32)
        if arr.ndim < 2 or arr.shape[-2] < self._n_needed:
            raise ConfigError(
                f"uvz must hold at least {self._n_needed} vertices (the faces index them), "
                f"got shape {arr.shape}"
            )
        if arr.ndim == 2 and arr.shape[1] == 3:
            ids = np.zeros((o.height, o.width), np.uint8)
            self._zbuf.fill(0.0)
            _raster_single(
                arr, self.faces, self.face_ids, o.width, o.height, o.near, o.cull_backfaces,
                ids, self._zbuf,
            )
            return ids
        if arr.ndim != 3 or arr.shape[2] != 3:
            raise ConfigError(f"uvz must have shape (B, V, 3) or (V, 3), got {arr.shape}")
        out = np.zeros((arr.shape[0], o.height, o.width), np.uint8)
        _raster_batch(
            arr, self.faces, self.face_ids, o.width, o.height, o.near, o.cull_backfaces, out
        )
        return out

    def render(self, vertices_world: ArrayLike, camera: Camera) -> NDArray[np.uint8]:
        """Id maps of posed meshes (B, V, 3) seen by ``camera`` resampled to the options' size."""
        o = self.options
        cam = _camera_for(camera, (o.width, o.height))
        return self.render_uvz(project_vertices(vertices_world, cam))
