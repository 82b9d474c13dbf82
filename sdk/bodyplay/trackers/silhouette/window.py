"""The matching window: a level virtual camera looking at the player's floor point.

Templates and observations are compared in the same upright window (the sizes of
:data:`~.options.LEVEL_SIZES`). The window is the image of a *virtual camera* that
shares the real camera's centre but looks horizontally at the player's floor point
G, with a focal length chosen so that a fixed number of metres spans a pixel
there (``metres_per_px`` at level 3), G on the window's middle column and the floor
under G on a fixed row. The real image maps into it by one homography (a pure
rotation about the camera centre plus a change of intrinsics), so the person
appears at the same scale and place whatever their distance, world verticals stay
vertical and the body's yaw relative to the line of sight is what the templates
encode. Templates are rendered from the same kind of camera, placed at the
canonical height and distance (:class:`WindowGeometry`).

G itself comes from the silhouette and the calibration: the floor point under
the torso (the silhouette's thickest part) at the silhouette's lowest row,
refined once in the window (feet on the floor).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import cv2
import numba
import numpy as np
from numpy.typing import NDArray

from bodyplay.capture.camera import Camera
from bodyplay.trackers.silhouette.background import Silhouette
from bodyplay.trackers.silhouette.options import LEVEL_SIZES

__all__ = ["WindowGeometry", "back_project", "anchor_point", "floor_point", "ObservedWindow",
           "select_person", "dilate_disc",
           "feet_like", "farthest_person", "window_at", "sight_direction", "person_box"]

_DOWN = np.array([0.0, -1.0, 0.0])


def anchor_point(mask: NDArray[np.uint8]) -> tuple[float, float] | None:
    """(column, row) of the torso's floor contact in a mask: the centroid column of
    the thickest part (inner distance >= 70% of its maximum) and the lowest row."""
    m = (np.asarray(mask) > 0).astype(np.uint8)
    rows = np.flatnonzero(m.any(axis=1))
    if rows.size == 0:
        return None
    d = cv2.distanceTransform(m, cv2.DIST_L2, 3)
    core = d >= 0.7 * float(d.max())
    xs = np.nonzero(core)[1]
    return float(xs.mean()), float(rows[-1])


def select_person(mask: NDArray[np.uint8], near: NDArray[np.bool_] | None,
                  reach: float = 0.08,
                  stands: Callable[[NDArray[np.bool_]], bool] | None = None
                  ) -> NDArray[np.uint8]:
    """The connected components of a foreground mask that belong to the player.

    With ``near`` (where the player is believed to be: the tracker's last estimate,
    dilated) the components that touch it; without it, or when none touches it,
    the largest component -- of those ``stands`` accepts (a person standing on the
    floor in view), when it accepts any -- and those within ``reach`` x the mask's
    height of it (a silhouette often breaks into a few pieces: an arm, a foot).
    Everything else -- a second person, a flickering lamp, a reflection, a patch of
    sky a first-frame guess took for the figure -- is dropped, so that it can
    neither put the floor point under it nor be matched.
    """
    m = (np.asarray(mask) > 0).astype(np.uint8)
    n, lab, stats, _ = cv2.connectedComponentsWithStats(m, connectivity=8)
    if n <= 2:
        return m
    keep = np.zeros(n, bool)
    if near is not None and near.shape == m.shape:
        keep[np.unique(lab[near & (lab > 0)])] = True
        keep[0] = False
    if not keep.any():
        order = 1 + np.argsort(-stats[1:, cv2.CC_STAT_AREA], kind="stable")
        big = int(order[0])
        if stands is not None:
            big = next((int(k) for k in order[:8] if stands(lab == k)), big)
        r = max(1, int(reach * m.shape[0]))
        k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
        zone = cv2.dilate((lab == big).astype(np.uint8), k) > 0
        keep[np.unique(lab[zone & (lab > 0)])] = True
    return keep[lab].astype(np.uint8)


def feet_like(mask: NDArray[np.uint8], mpp: float, band: float = 0.25,
              max_width: float = 0.6) -> bool:
    """Whether the bottom of a window mask could be a person's feet and shins: no
    row of its lowest ``band`` metres is wider, filled, than ``max_width`` metres
    (``mpp`` metres per pixel). A first frame's figure/ground guess that took the
    treadmill, the sofa or the rug under the player for part of the figure fails
    it (the floor point would be put under the furniture's front edge)."""
    m = np.asarray(mask) > 0
    rows = np.flatnonzero(m.any(axis=1))
    if rows.size == 0:
        return False
    lo = rows[-1] + 1
    part = m[max(0, lo - max(1, int(round(band / mpp)))):lo]
    return bool(part.sum(axis=1).max() * mpp <= max_width)


def farthest_person(camera: Camera, working_size: int, min_px: float,
                    stature: float = 1.7) -> float:
    """How far (m) a person of ``stature`` can stand and still be ``min_px`` pixels
    tall in the background model's working image (short side ``working_size``): the
    farthest a player can be matched without the windows being mostly
    interpolation. It follows the camera's focal length and resolution, so a wide
    640x480 webcam gets about 6 m and a telephoto HD camera filming a walker across
    a field gets more."""
    scale = min(1.0, working_size / min(camera.width, camera.height))
    f = 0.5 * (camera.K[0, 0] + camera.K[1, 1]) * scale
    return float(f * stature / max(min_px, 1.0))


def floor_point(camera: Camera, u: float, v: float) -> NDArray[np.float64] | None:
    """Where the ray through pinhole pixel (u, v) meets the floor Y = 0 (None if never)."""
    ray = camera.R.T @ np.linalg.solve(camera.K, np.array([u, v, 1.0]))
    c = camera.center
    if ray[1] >= -1e-9 or c[1] <= 0:
        return None
    return c + (-c[1] / ray[1]) * ray


@dataclass(frozen=True)
class WindowGeometry:
    """Scale and placement of the window, and the canonical template view."""

    metres_per_px: float = 0.009
    floor_margin: float = 0.12
    camera_height: float = 1.2
    camera_distance: float = 3.0

    def size(self, level: int) -> tuple[int, int]:
        """(width, height) of the window at tree level 0, 1 or 2."""
        return LEVEL_SIZES[level]

    def mpp(self, level: int) -> float:
        """Metres per pixel at the floor point at ``level``."""
        return self.metres_per_px * LEVEL_SIZES[-1][0] / LEVEL_SIZES[level][0]

    def floor_row(self, level: int) -> float:
        """Row of the floor under G at ``level``."""
        h = LEVEL_SIZES[level][1]
        return (h - 0.5) - self.floor_margin / self.mpp(level)

    def view(self, center: NDArray[np.float64], ground: NDArray[np.float64],
             level: int) -> Camera:
        """The virtual camera at ``center`` looking level at floor point ``ground``."""
        c = np.asarray(center, np.float64)
        g = np.asarray(ground, np.float64)
        f = g - c
        f[1] = 0.0
        d = float(np.linalg.norm(f))
        f = f / max(d, 1e-9)
        right = np.cross(_DOWN, f)
        R = np.stack([right, _DOWN, f])
        w, h = LEVEL_SIZES[level]
        mpp = self.mpp(level)
        fw = max(d, 1e-6) / mpp
        cy = self.floor_row(level) - c[1] / mpp
        K = np.array([[fw, 0.0, (w - 1) / 2.0], [0.0, fw, cy], [0.0, 0.0, 1.0]])
        return Camera("window", w, h, K, R, -R @ c)

    def template_view(self, level: int) -> Camera:
        """The canonical view templates are rendered from (floor point at the origin)."""
        return self.view(np.array([0.0, self.camera_height, self.camera_distance]),
                         np.zeros(3), level)


@dataclass(frozen=True, eq=False)
class ObservedWindow:
    """An observed silhouette resampled into the window at every level.

    ``foreground``/``unknown``: per level uint8 masks; ``ground``: the floor point G
    (world); ``views``: the virtual camera per level; ``distance``: G's horizontal
    distance from the camera as the silhouette's lowest row gave it (before any cap);
    ``region``: the level-1 mask the floor point was found in, when not the foreground.
    """

    foreground: tuple[NDArray[np.uint8], ...]
    unknown: tuple[NDArray[np.uint8], ...]
    ground: NDArray[np.float64]
    views: tuple[Camera, ...]
    distance: float
    region: NDArray[np.uint8] | None = None


def _homography(real: Camera, view: Camera, scale: float) -> NDArray[np.float64]:
    """Working-image pixels (real image scaled by ``scale``) -> window pixels."""
    S = np.array([[scale, 0.0, 0.5 * scale - 0.5], [0.0, scale, 0.5 * scale - 0.5], [0, 0, 1.0]])
    H = view.K @ view.R @ real.R.T @ np.linalg.inv(real.K) @ np.linalg.inv(S)
    return H / H[2, 2]


def _warp(mask: NDArray[np.uint8], H: NDArray[np.float64], size: tuple[int, int]
          ) -> NDArray[np.uint8]:
    out = cv2.warpPerspective(mask * np.uint8(255), H, size, flags=cv2.INTER_LINEAR,
                              borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    return (out >= 128).astype(np.uint8)


def _down(mask: NDArray[np.uint8], size: tuple[int, int]) -> NDArray[np.uint8]:
    return (cv2.resize(mask.astype(np.float32), size, interpolation=cv2.INTER_AREA) >= 0.5
            ).astype(np.uint8)


def observe(geometry: WindowGeometry, camera: Camera, foreground: NDArray[np.uint8],
            unknown: NDArray[np.uint8], scale: float, distance_cap: float | None = None,
            region: NDArray[np.uint8] | None = None, distance_fix: float | None = None
            ) -> ObservedWindow | None:
    """Find G and resample the working-resolution masks into the window (None when
    there is no silhouette or it does not stand on the floor in view).

    ``distance_cap`` pulls G nearer when the lowest row puts it farther (a jump lifts
    the feet off the floor; the tracker passes the nearest distance of the last
    moments); ``distance_fix`` sets the distance outright (the feet are not seen).
    ``region`` (default the foreground) is where the floor point is sought.
    """
    given = region
    region = foreground if region is None else region
    a = anchor_point(region)
    if a is None:
        return None
    u = (a[0] + 0.5) / scale - 0.5
    v = (a[1] + 0.5) / scale - 0.5
    g = floor_point(camera, u, v)
    if g is None:
        return None
    c = camera.center
    for _ in range(2):  # refine G in the window (verticals are vertical there)
        view = geometry.view(c, g, 0)
        m0 = _warp(region, _homography(camera, view, scale), geometry.size(0))
        a0 = anchor_point(m0)
        if a0 is None:
            return None
        g2 = floor_point(view, a0[0], a0[1])
        if g2 is None:
            return None
        g = g2
    c = camera.center
    off = g - c
    off[1] = 0.0
    raw = float(np.linalg.norm(off))
    want = distance_fix if distance_fix is not None else (
        distance_cap if distance_cap is not None and raw > distance_cap > 0 else None)
    if want is not None and raw > 0:
        g = c + off * (want / raw)
        g[1] = 0.0
    return window_at(geometry, camera, foreground, unknown, scale, g, raw, given)


def window_at(geometry: WindowGeometry, camera: Camera, foreground: NDArray[np.uint8],
              unknown: NDArray[np.uint8], scale: float, ground: NDArray[np.float64],
              distance: float | None = None, region: NDArray[np.uint8] | None = None
              ) -> ObservedWindow:
    """The working-resolution masks resampled into the window at floor point
    ``ground`` (``distance``: the distance to report, default G's own)."""
    c = camera.center
    g = np.asarray(ground, np.float64)
    if distance is None:
        distance = float(np.hypot(*(g - c)[[0, 2]]))
    views = tuple(geometry.view(c, g, lv) for lv in range(3))
    H = _homography(camera, views[2], scale)
    fg3 = _warp(foreground, H, geometry.size(2))
    un3 = _warp(unknown, H, geometry.size(2))
    fgs = (_down(fg3, geometry.size(0)), _down(fg3, geometry.size(1)), fg3)
    uns = (_down(un3, geometry.size(0)), _down(un3, geometry.size(1)), un3)
    reg = None if region is None else _down(_warp(region, H, geometry.size(2)), geometry.size(0))
    return ObservedWindow(fgs, uns, g, views, distance, reg)


def sight_direction(camera: Camera, u: float) -> NDArray[np.float64] | None:
    """The horizontal unit direction from the camera to the floor seen at image
    column ``u`` (at the image's bottom row; None when the camera sees no floor there)."""
    g = floor_point(camera, u, camera.height - 0.5)
    if g is None:
        return None
    off = g - camera.center
    off[1] = 0.0
    n = float(np.linalg.norm(off))
    return off / n if n > 1e-9 else None


def person_box(camera: Camera, ground: NDArray[np.float64], shape: tuple[int, ...],
               scale: float, half_width: float, below: float, top: float
               ) -> NDArray[np.bool_]:
    """The pixels of a working image (``shape``, ``scale`` times ``camera``'s image,
    undistorted) that a person standing at floor point ``ground`` can fill: the
    upright rectangle facing the camera, ``half_width`` m either side of the line of
    sight through ``ground``, from ``below`` m under the floor to ``top`` m above it
    (empty when a corner lies behind the camera)."""
    c = camera.center
    f = np.asarray(ground, np.float64) - c
    f[1] = 0.0
    f /= max(float(np.linalg.norm(f)), 1e-9)
    right = np.cross(np.array([0.0, 1.0, 0.0]), f)
    corners = np.array([ground + a * half_width * right + np.array([0.0, y, 0.0])
                        for a, y in ((-1, -below), (1, -below), (1, top), (-1, top))])
    box = np.zeros(shape[:2], np.uint8)
    if (camera.world_to_camera(corners)[:, 2] <= 0.05).any():
        return box > 0
    uv = (camera.project(corners, distort=False) + 0.5) * scale - 0.5
    cv2.fillConvexPoly(box, np.round(uv).astype(np.int32), 1)
    return box > 0


@numba.njit(cache=True, nogil=True)
def _dilate_runs(src, reach, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """:func:`dilate_disc`'s kernel: a set pixel of ``src`` n columns from (y', x) in
    its row sets rows y' - reach[n] .. y' + reach[n] of column x in ``out`` (reach[n]:
    the farthest kernel row at least n wide either side); only the set pixels' box,
    widened by the kernel, is read."""
    h, w = src.shape
    out[:, :] = 0
    y0, y1, x0, x1 = h, -1, w, -1
    for y in range(h):
        for x in range(w):
            if src[y, x]:
                y0 = min(y0, y)
                y1 = max(y1, y)
                x0 = min(x0, x)
                x1 = max(x1, x)
    if y1 < 0:
        return
    widest = reach.shape[0] - 1
    big = w + widest + 10
    near = np.full((y1 - y0 + 1, w), big, np.int64)  # per row: columns to its nearest set pixel
    cx0 = max(0, x0 - widest)
    cx1 = min(w - 1, x1 + widest)
    for y in range(y0, y1 + 1):
        row = near[y - y0]
        last = -big
        for x in range(x0, cx1 + 1):
            if x <= x1 and src[y, x]:
                last = x
            row[x] = x - last
        last = 2 * big
        for x in range(x1, cx0 - 1, -1):
            if x >= x0 and src[y, x]:
                last = x
            row[x] = min(row[x], last - x)
    cover = np.zeros(h + 1, np.int64)
    for x in range(cx0, cx1 + 1):
        cover[:] = 0
        for y in range(y0, y1 + 1):
            n = near[y - y0, x]
            if n <= widest:
                cover[max(0, y - reach[n])] += 1
                cover[min(h, y + reach[n] + 1)] -= 1
        run = 0
        for y in range(h):
            run += cover[y]
            if run > 0:
                out[y, x] = 1


def dilate_disc(mask: NDArray[np.uint8], radius: int) -> NDArray[np.uint8]:
    """``cv2.dilate(mask, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 r + 1,) * 2))``
    of a 0/1 mask, the same pixels: each kernel row is a centred run, no narrower
    than the rows farther from the middle, so a set pixel n columns away in a row
    sets a run of rows in a column; a pass per column over the mask's box (a tenth
    of OpenCV's time or less at the radius of :func:`back_project`; OpenCV is used
    for any kernel not of that shape)."""
    k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1,) * 2)
    half = np.empty(k.shape[0], np.int64)
    for i in range(k.shape[0]):
        cols = np.flatnonzero(k[i])
        centred = cols.size > 0 and cols[0] + cols[-1] == 2 * radius
        if not centred or cols.size != cols[-1] - cols[0] + 1:
            return np.asarray(cv2.dilate(mask, k), np.uint8)
        half[i] = cols[-1] - radius
    up, down = half[radius::-1], half[radius:]
    if not (np.array_equal(up, down) and np.all(np.diff(down) <= 0)):
        return np.asarray(cv2.dilate(mask, k), np.uint8)
    # reach[n]: the farthest row from the middle whose run is at least n either side
    reach = np.array([int(np.flatnonzero(down >= n)[-1]) for n in range(int(down[0]) + 1)],
                     np.int64)
    src = np.ascontiguousarray(mask, np.uint8)
    out = np.empty_like(src)
    _dilate_runs(src, reach, out)
    return out


def back_project(camera: Camera, view: Camera, silhouette: Silhouette, mask: NDArray[np.uint8],
                 shift: tuple[int, int], protect_radius: float
                 ) -> tuple[NDArray[np.uint8], NDArray[np.bool_]]:
    """A level-3 template ``mask`` (moved by ``shift`` pixels) in the working image of
    ``silhouette``, and it dilated by ``protect_radius`` of the image's smaller side:
    the pixels the background model must not learn while the player stands there."""
    H = _homography(camera, view, silhouette.scale)
    h, w = silhouette.foreground.shape
    move = np.array([[1.0, 0.0, shift[0]], [0.0, 1.0, shift[1]], [0.0, 0.0, 1.0]])
    back = cv2.warpPerspective(mask * np.uint8(255), np.linalg.inv(H) @ move, (w, h),
                               flags=cv2.INTER_LINEAR) >= 128
    r = max(2, int(protect_radius * min(h, w)))
    protect = dilate_disc(back.astype(np.uint8), r) > 0
    return back.astype(np.uint8), protect
