"""The normalized core-weighted XOR distance (paper eq. 10-12, beta = 1).

For an observed silhouette S and a template mask T in a window w,

    d(S, T) = ( sum_{T=1} D(S) + sum_{T=0} W ) / |w|,   W = beta D(~S) / (D(~S) + D(S_skl))

with D(S) the distance transform of S (0 inside, growing outside), D(~S) that of the
complement (0 outside, growing towards the core) and D(S_skl) that of the shape
skeleton (the ridge of D(~S)). W is zero outside S, so with A = D(S) - W

    d(S, T) = ( T . A + sum W ) / |w|

is *linear in the template mask*: a whole set of templates scores as one matrix
product (:func:`score_dense`), or, as the paper does, by reading a horizontal
integral image of A at the ends of each template's horizontal runs
(:func:`score_runs`, eq. 12). Both give the same numbers; the tracker uses the runs,
which touch only the contour (about 70 times fewer operations at 240x320; see
docs/silhouette-history.md, section 9, for the measured speeds).

Pixels of unknown background (:mod:`.background`) are "don't care": they count as
silhouette for D(S) (a template may cover them freely) and carry no weight W.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba
import numpy as np
from numpy.typing import NDArray

from bodyplay.errors import ConfigError

__all__ = [
    "DistanceMaps",
    "TemplateRuns",
    "distance_maps",
    "encode_runs",
    "score_dense",
    "score_direct",
    "score_runs",
    "shape_skeleton",
]


@numba.njit(cache=True, nogil=True)
def _ridge(d, mask, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """:func:`shape_skeleton`'s test for every pixel (outside the image counts 0)."""
    h, w = d.shape
    for i in range(h):
        for j in range(w):
            out[i, j] = 0
            c = d[i, j]
            if not (mask[i, j] > 0 and c >= 1.0):
                continue
            for di, dj in ((0, 1), (1, 0), (1, 1), (1, -1)):  # the four directions
                ia, ja, ib, jb = i - di, j - dj, i + di, j + dj
                a = d[ia, ja] if 0 <= ia < h and 0 <= ja < w else np.float32(0.0)
                b = d[ib, jb] if 0 <= ib < h and 0 <= jb < w else np.float32(0.0)
                if c >= a and c >= b and (c > a or c > b):
                    out[i, j] = 1
                    break


def shape_skeleton(dt_inside: NDArray[np.float32], mask: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """The ridge of the inner distance transform: pixels of the silhouette whose
    distance is a local maximum along at least one of the four directions."""
    out = np.empty(np.shape(dt_inside), np.uint8)
    _ridge(np.ascontiguousarray(dt_inside, np.float32), np.ascontiguousarray(mask), out)
    return out


@numba.njit(cache=True, nogil=True)
def _terms(fg, d_in, d_skl, d_out, beta, weight, cost, integral):  # type: ignore[no-untyped-def]  # pragma: no cover
    """W, A = D(S) - W and A's horizontal integral image, float32 as the numpy
    expressions they replace (the integral accumulated in float64, left to right)."""
    h, w = fg.shape
    tiny = np.float32(1e-6)
    for i in range(h):
        acc = 0.0
        integral[i, 0] = 0.0
        for j in range(w):
            wt = np.float32(0.0)
            if fg[i, j] > 0:
                wt = (beta * d_in[i, j]) / max(d_in[i, j] + d_skl[i, j], tiny)
            weight[i, j] = wt
            a = d_out[i, j] - wt
            cost[i, j] = a
            acc += np.float64(a)
            integral[i, j + 1] = acc


@dataclass(frozen=True, eq=False)
class DistanceMaps:
    """The per-pixel terms of one observed silhouette at one level.

    ``cost`` is A = D(S) - W (float32, (H, W)); ``base`` is sum W; ``area`` |w|;
    ``integral`` the horizontal integral image of A, (H, W + 1) float64, column 0
    zero; ``weight`` is W (for figures).
    """

    cost: NDArray[np.float32]
    base: float
    area: int
    integral: NDArray[np.float64]
    weight: NDArray[np.float32]


def distance_maps(foreground: NDArray[np.uint8], unknown: NDArray[np.uint8] | None = None,
                  beta: float = 1.0) -> DistanceMaps:
    """Distance transforms of the silhouette, its complement and its skeleton, and
    the terms of eq. 11 (pixel units of this level)."""
    fg = (np.asarray(foreground) > 0).astype(np.uint8)
    possible = fg if unknown is None else (fg | (np.asarray(unknown) > 0)).astype(np.uint8)
    if not possible.any():
        d_out: NDArray[np.float32] = np.full(fg.shape, float(sum(fg.shape)), np.float32)
    else:
        d_out = np.asarray(cv2.distanceTransform(1 - possible, cv2.DIST_L2, 5), np.float32)
    d_in = np.asarray(cv2.distanceTransform(fg, cv2.DIST_L2, 5), np.float32)
    skl = shape_skeleton(d_in, fg)
    if skl.any():
        d_skl = np.asarray(cv2.distanceTransform(1 - skl, cv2.DIST_L2, 5), np.float32)
    else:
        d_skl = np.zeros(fg.shape, np.float32)
    h, w = fg.shape
    W = np.empty((h, w), np.float32)
    A = np.empty((h, w), np.float32)
    integ = np.empty((h, w + 1), np.float64)
    _terms(fg, d_in, d_skl, d_out, np.float32(beta), W, A, integ)
    return DistanceMaps(A, float(W.sum(dtype=np.float64)), int(A.size), integ, W)


def score_direct(maps: DistanceMaps, template: NDArray[np.uint8]) -> float:
    """eq. 11 summed pixel by pixel (the reference the fast forms are tested against)."""
    t = np.asarray(template) > 0
    if t.shape != maps.cost.shape:
        raise ConfigError(f"template is {t.shape}, the distance maps {maps.cost.shape}")
    d_out = maps.cost + maps.weight
    return float((d_out[t].sum(dtype=np.float64) + maps.weight[~t].sum(dtype=np.float64))
                 / maps.area)


def score_dense(maps: DistanceMaps, templates: NDArray[np.float32]) -> NDArray[np.float64]:
    """All templates at once as one matrix product: (N, H*W) 0/1 float32 -> (N,)."""
    a = maps.cost.reshape(-1)
    if templates.ndim != 2 or templates.shape[1] != a.size:
        raise ConfigError(f"templates must be (N, {a.size}), got {templates.shape}")
    return (templates @ a + maps.base).astype(np.float64) / maps.area


@numba.njit(cache=True, nogil=True)
def _fill_masks(offsets, row, x0, x1, index, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    for k in range(index.shape[0]):
        i = index[k]
        for j in range(offsets[i], offsets[i + 1]):
            out[k, row[j], x0[j]:x1[j]] = 1


@dataclass(frozen=True, eq=False)
class TemplateRuns:
    """Many template masks of one size as horizontal runs (the paper's contour pairs).

    Template ``i``'s runs are ``row/x0/x1[offsets[i]:offsets[i+1]]``: pixels
    ``x0 <= x < x1`` of ``row`` are inside.
    """

    width: int
    height: int
    offsets: NDArray[np.int64]
    row: NDArray[np.uint16]
    x0: NDArray[np.uint16]
    x1: NDArray[np.uint16]

    def __len__(self) -> int:
        return int(self.offsets.shape[0] - 1)

    @property
    def nbytes(self) -> int:
        """Memory held by the runs."""
        return int(self.offsets.nbytes + self.row.nbytes + self.x0.nbytes + self.x1.nbytes)

    def masks(self, index: NDArray[np.int64] | None = None) -> NDArray[np.uint8]:
        """Decode templates back to (N, H, W) 0/1 masks."""
        idx = np.arange(len(self)) if index is None else np.asarray(index)
        out = np.zeros((len(idx), self.height, self.width), np.uint8)
        _fill_masks(self.offsets, self.row, self.x0, self.x1, idx.astype(np.int64), out)
        return out


@numba.njit(cache=True)
def _count_runs(masks: NDArray[np.uint8]) -> NDArray[np.int64]:  # pragma: no cover
    n, h, w = masks.shape
    out = np.zeros(n, np.int64)
    for i in range(n):
        c = 0
        for y in range(h):
            prev = 0
            for x in range(w):
                v = masks[i, y, x]
                if v and not prev:
                    c += 1
                prev = v
        out[i] = c
    return out


@numba.njit(cache=True)
def _fill_runs(masks, offsets, row, x0, x1):  # type: ignore[no-untyped-def]  # pragma: no cover
    n, h, w = masks.shape
    for i in range(n):
        k = offsets[i]
        for y in range(h):
            start = -1
            for x in range(w):
                v = masks[i, y, x]
                if v and start < 0:
                    start = x
                elif not v and start >= 0:
                    row[k] = y
                    x0[k] = start
                    x1[k] = x
                    k += 1
                    start = -1
            if start >= 0:
                row[k] = y
                x0[k] = start
                x1[k] = w
                k += 1


def encode_runs(masks: NDArray[np.uint8]) -> TemplateRuns:
    """(N, H, W) masks -> :class:`TemplateRuns`."""
    m = np.ascontiguousarray((np.asarray(masks) > 0).astype(np.uint8))
    if m.ndim != 3:
        raise ConfigError(f"masks must be (N, H, W), got {m.shape}")
    counts = _count_runs(m)
    offsets = np.zeros(len(m) + 1, np.int64)
    np.cumsum(counts, out=offsets[1:])
    total = int(offsets[-1])
    row = np.zeros(total, np.uint16)
    x0 = np.zeros(total, np.uint16)
    x1 = np.zeros(total, np.uint16)
    _fill_runs(m, offsets, row, x0, x1)
    return TemplateRuns(m.shape[2], m.shape[1], offsets, row, x0, x1)


@numba.njit(cache=True, nogil=True)
def _score_runs(integral, offsets, row, x0, x1, index, base, area):  # type: ignore[no-untyped-def]  # pragma: no cover
    out = np.empty(index.shape[0], np.float64)
    for k in range(index.shape[0]):
        i = index[k]
        s = 0.0
        for j in range(offsets[i], offsets[i + 1]):
            r = row[j]
            s += integral[r, x1[j]] - integral[r, x0[j]]
        out[k] = (s + base) / area
    return out


def score_runs(maps: DistanceMaps, runs: TemplateRuns,
               index: NDArray[np.int64] | None = None) -> NDArray[np.float64]:
    """eq. 11-12 for templates ``index`` (default all) from the integral image."""
    if (runs.height, runs.width) != maps.cost.shape:
        raise ConfigError(f"templates are {runs.width}x{runs.height}, the maps "
                          f"{maps.cost.shape[1]}x{maps.cost.shape[0]}")
    idx = np.arange(len(runs), dtype=np.int64) if index is None else np.asarray(index, np.int64)
    return _score_runs(maps.integral, runs.offsets, runs.row, runs.x0, runs.x1, idx,
                       maps.base, float(maps.area))


@numba.njit(cache=True, nogil=True)
def _score_runs_shifted(integral, offsets, row, x0, x1, index, dx, dy, base, area):  # type: ignore[no-untyped-def]  # pragma: no cover
    h = integral.shape[0]
    w = integral.shape[1] - 1
    out = np.empty(index.shape[0], np.float64)
    for k in range(index.shape[0]):
        i = index[k]
        sx = dx[k]
        sy = dy[k]
        s = 0.0
        for j in range(offsets[i], offsets[i + 1]):
            r = np.int64(row[j]) + sy
            if r < 0 or r >= h:
                continue
            a = min(max(np.int64(x0[j]) + sx, 0), w)
            b = min(max(np.int64(x1[j]) + sx, 0), w)
            s += integral[r, b] - integral[r, a]
        out[k] = (s + base) / area
    return out


def score_runs_shifted(maps: DistanceMaps, runs: TemplateRuns, index: NDArray[np.int64],
                       dx: NDArray[np.int64], dy: NDArray[np.int64]) -> NDArray[np.float64]:
    """eq. 11-12 for template ``index[k]`` moved by ``(dx[k], dy[k])`` pixels (the
    search over the body's position in the window); template pixels moved out of
    the window are dropped."""
    if (runs.height, runs.width) != maps.cost.shape:
        raise ConfigError(f"templates are {runs.width}x{runs.height}, the maps "
                          f"{maps.cost.shape[1]}x{maps.cost.shape[0]}")
    return _score_runs_shifted(maps.integral, runs.offsets, runs.row, runs.x0, runs.x1,
                               np.asarray(index, np.int64), np.asarray(dx, np.int64),
                               np.asarray(dy, np.int64), maps.base, float(maps.area))
