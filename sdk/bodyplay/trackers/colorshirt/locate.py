"""Finding the shirt: chrominance-histogram uniformity search (paper §4).

For windows on a 6 px grid at six scales, the 100-bin histogram of ``(r, g) /
(r + g + b)``, normalized by the window's area, gives ``u = sum_i min(h_i, tau)``;
the shirt is the average of the windows near the best one, weighted by
``exp(-(u - u_max)^2 / (u_max / 10)^2)``. :class:`BackgroundMask` wraps OpenCV's
MOG2 for the mask.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba
import numpy as np
from numpy.typing import NDArray

from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types

__all__ = ["LocateOptions", "ShirtLocation", "ShirtLocator", "BackgroundMask", "chroma_bins",
           "reduce_box", "reduce_image"]

BINS_PER_AXIS = 10
NUM_BINS = BINS_PER_AXIS * BINS_PER_AXIS


@dataclass(frozen=True)
class LocateOptions:
    """Histogram-search settings (defaults are the paper's).

    ``scales`` are window sides as fractions of the image height; ``min_brightness``
    is the least ``r + g + b`` whose chrominance is trusted; ``min_uniformity`` is
    the least ``u_max`` reported as a shirt.
    """

    tau: float = 0.1
    stride: int = 6
    scales: tuple[float, ...] = (0.14, 0.2, 0.27, 0.36, 0.48, 0.64)
    min_brightness: int = 60
    min_uniformity: float = 0.45

    def __post_init__(self) -> None:
        check_option_types(self)
        if self.stride < 1:
            raise ConfigError("locate stride must be at least 1 pixel")
        if not self.scales or any(s <= 0 or s > 1 for s in self.scales):
            raise ConfigError("locate scales must be fractions of the image height in (0, 1]")
        if not 0 < self.tau <= 1:
            raise ConfigError("locate tau must be in (0, 1]")


@dataclass(frozen=True)
class ShirtLocation:
    """Where the shirt is: centre ``(x, y)`` and window side ``scale`` in pixels."""

    x: float
    y: float
    scale: float
    uniformity: float
    found: bool

    def box(self, margin: float = 1.0) -> tuple[int, int, int, int]:
        """Integer ``(x0, y0, x1, y1)`` of the square window enlarged by ``margin``."""
        half = 0.5 * self.scale * margin
        return (
            int(round(self.x - half)),
            int(round(self.y - half)),
            int(round(self.x + half)),
            int(round(self.y + half)),
        )


@numba.njit(cache=True, nogil=True)
def _chroma_bin_image(  # pragma: no cover - compiled
    image: NDArray[np.uint8], mask: NDArray[np.bool_], use_mask: bool, min_brightness: int
) -> NDArray[np.int16]:
    h, w = image.shape[0], image.shape[1]
    out = np.full((h, w), -1, np.int16)
    # floor(n / s) of integers as floor((n + 0.5) / s) by a reciprocal: (n + 0.5) / s
    # lies at least 0.5 / s from an integer, far beyond a float64 rounding (and no
    # integer division per pixel)
    inv = np.zeros(3 * 255 + 1)
    for n in range(1, 3 * 255 + 1):
        inv[n] = 1.0 / n
    for y in range(h):
        for x in range(w):
            if use_mask and not mask[y, x]:
                continue
            r = np.int32(image[y, x, 0])
            g = np.int32(image[y, x, 1])
            b = np.int32(image[y, x, 2])
            s = r + g + b
            if s < min_brightness or s == 0:
                continue
            br = int((r * BINS_PER_AXIS + 0.5) * inv[s])
            bg = int((g * BINS_PER_AXIS + 0.5) * inv[s])
            out[y, x] = min(br, BINS_PER_AXIS - 1) * BINS_PER_AXIS + min(bg, BINS_PER_AXIS - 1)
    return out


@numba.njit(cache=True, nogil=True)
def _cell_integral(  # pragma: no cover - compiled
    bins: NDArray[np.int16], stride: int
) -> NDArray[np.int32]:
    hc = bins.shape[0] // stride
    wc = bins.shape[1] // stride
    integ = np.zeros((hc + 1, wc + 1, NUM_BINS), np.int32)
    row = np.empty(NUM_BINS, np.int32)
    for cy in range(1, hc + 1):
        # the row's cell histograms, then the integral: the row's running sums plus
        # the integral of the row above (the same integers as summing the four corners)
        for y in range((cy - 1) * stride, cy * stride):
            for cx in range(1, wc + 1):
                cell = integ[cy, cx]
                for x in range((cx - 1) * stride, cx * stride):
                    b = bins[y, x]
                    if b >= 0:
                        cell[b] += 1
        row[:] = 0
        for cx in range(1, wc + 1):
            for b in range(NUM_BINS):
                row[b] += integ[cy, cx, b]
                integ[cy, cx, b] = integ[cy - 1, cx, b] + row[b]
    return integ


@numba.njit(cache=True, nogil=True)
def _window_uniformity(  # pragma: no cover - compiled
    integ: NDArray[np.int32], s: int, area: float, tau: float, active: NDArray[np.bool_]
) -> NDArray[np.float32]:
    hc = integ.shape[0] - 1
    wc = integ.shape[1] - 1
    ny = hc - s + 1
    nx = wc - s + 1
    u = np.zeros((max(ny, 0), max(nx, 0)), np.float32)
    cap = tau * area
    for y0 in range(ny):
        for x0 in range(nx):
            if not active[y0 + s // 2, x0 + s // 2]:
                continue
            # sum min(c, cap) as the counts under the cap plus the capped bins times
            # the cap: integers, no float chain per bin (float64's last bit may differ
            # from a bin-by-bin sum; the float32 u did not on 474,354 windows compared)
            low = 0
            capped = 0
            for b in range(NUM_BINS):
                c = (
                    integ[y0 + s, x0 + s, b]
                    - integ[y0, x0 + s, b]
                    - integ[y0 + s, x0, b]
                    + integ[y0, x0, b]
                )
                if c < cap:
                    low += c
                else:
                    capped += 1
            u[y0, x0] = (float(low) + capped * cap) / area
    return u


def chroma_bins(
    image: NDArray[np.uint8], mask: NDArray[np.bool_] | None = None, min_brightness: int = 60
) -> NDArray[np.int16]:
    """(H, W) chrominance bin 0..99 of each pixel, -1 where masked out or too dark."""
    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ConfigError(f"expected an (H, W, 3) uint8 RGB image, got {image.shape} {image.dtype}")
    use_mask = mask is not None
    m = np.ascontiguousarray(mask, np.bool_) if mask is not None else np.ones((1, 1), np.bool_)
    return _chroma_bin_image(np.ascontiguousarray(image), m, use_mask, int(min_brightness))


class ShirtLocator:
    """Locates the shirt in RGB frames by histogram uniformity (stateless apart from options)."""

    def __init__(self, options: LocateOptions | None = None) -> None:
        self.options = options or LocateOptions()

    def uniformity_maps(
        self, image: NDArray[np.uint8], mask: NDArray[np.bool_] | None = None,
        frame_height: int | None = None,
    ) -> list[tuple[int, NDArray[np.float32]]]:
        """Per scale: (window side in cells, u over window top-left cells).

        Window sides are fractions of ``frame_height`` (default the image's own
        height; a part of a frame passes the whole frame's).
        """
        o = self.options
        bins = chroma_bins(image, mask, o.min_brightness)
        integ = _cell_integral(bins, o.stride)
        hc, wc = integ.shape[0] - 1, integ.shape[1] - 1
        if mask is not None:
            cells = cv2.resize(
                mask.astype(np.uint8)[: hc * o.stride, : wc * o.stride],
                (wc, hc),
                interpolation=cv2.INTER_AREA,
            )
            active = cells > 0
            # windows centred near foreground are evaluated too
            active = cv2.dilate(active.astype(np.uint8), np.ones((5, 5), np.uint8)) > 0
        else:
            active = np.ones((hc, wc), np.bool_)
        out = []
        h = image.shape[0] if frame_height is None else frame_height
        for frac in o.scales:
            s = max(2, int(round(frac * h / o.stride)))
            if s > min(hc, wc):
                continue
            area = float(s * s * o.stride * o.stride)
            out.append((s, _window_uniformity(integ, s, area, o.tau, active)))
        return out

    def locate(
        self, image: NDArray[np.uint8], mask: NDArray[np.bool_] | None = None,
        region: tuple[int, int, int, int] | None = None,
    ) -> ShirtLocation:
        """Centre and scale of the most colorful region (the weighted average of §4),
        searched first within ``region`` ``(x0, y0, x1, y1)`` (image pixels) if given."""
        if region is not None:
            st = self.options.stride
            h, w = image.shape[:2]
            x0, y0 = max(0, region[0] // st * st), max(0, region[1] // st * st)
            x1, y1 = min(w, region[2]), min(h, region[3])
            if x1 - x0 > 2 * st and y1 - y0 > 2 * st:
                sub, sub_mask = image[y0:y1, x0:x1], None if mask is None else mask[y0:y1, x0:x1]
                loc = self._average(self.uniformity_maps(sub, sub_mask, h), sub.shape)
                if loc.found:
                    return ShirtLocation(loc.x + x0, loc.y + y0, loc.scale, loc.uniformity,
                                         True)
        return self._average(self.uniformity_maps(image, mask), image.shape)

    def candidates(self, image: NDArray[np.uint8], mask: NDArray[np.bool_] | None = None,
                   count: int = 3) -> list[ShirtLocation]:
        """Up to ``count`` shirt-like regions of the whole frame, best first, each found
        as :meth:`locate` finds the best once the windows overlapping the regions
        before it are left out."""
        maps = self.uniformity_maps(image, mask)
        out: list[ShirtLocation] = []
        for _ in range(count):
            loc = self._average(maps, image.shape)
            if not loc.found:
                break
            out.append(loc)
            st = self.options.stride
            for s, u in maps:  # leave out every window overlapping the one found
                if not u.size:
                    continue
                ys, xs = np.indices(u.shape)
                reach = 0.5 * (s * st + loc.scale)
                u[(np.abs((xs + 0.5 * s) * st - loc.x) < reach)
                  & (np.abs((ys + 0.5 * s) * st - loc.y) < reach)] = 0.0
        return out

    def _average(self, maps: list[tuple[int, NDArray[np.float32]]],
                 shape: tuple[int, ...]) -> ShirtLocation:
        """The weighted average of the windows around the best one of ``maps``."""
        o = self.options
        maxima = [(s, u, float(u.max())) for s, u in maps if u.size]
        u_max = max((m for _, _, m in maxima), default=0.0)
        if u_max <= 0.0:
            return ShirtLocation(shape[1] / 2, shape[0] / 2, 0.0, 0.0, False)
        sigma = 0.1 * u_max
        # only the windows overlapping the best one: another colorful region cannot pull
        bs, bu, _ = max(maxima, key=lambda m: m[2])
        by, bx = np.unravel_index(int(np.argmax(bu)), bu.shape)
        best_c = ((bx + 0.5 * bs) * o.stride, (by + 0.5 * bs) * o.stride)
        wsum = 0.0
        acc = np.zeros(3)
        for s, u, _ in maxima:
            w = u.astype(np.float64)  # exp(-((u - u_max) / sigma)^2), in place
            w -= u_max
            w /= sigma
            np.square(w, out=w)
            np.negative(w, out=w)
            np.exp(w, out=w)
            w[u <= 0] = 0.0
            # window centres per column and row (the grid is separable, so the
            # windows beyond reach are whole rows and columns)
            gx = (np.arange(u.shape[1]) + 0.5 * s) * o.stride
            gy = (np.arange(u.shape[0]) + 0.5 * s) * o.stride
            reach = 0.5 * (s + bs) * o.stride
            w[:, np.abs(gx - best_c[0]) > reach] = 0.0
            w[np.abs(gy - best_c[1]) > reach] = 0.0
            tot = float(w.sum())
            if tot < 1e-12:
                continue
            cx = (gx[None, :] * w).sum()
            cy = (gy[:, None] * w).sum()
            acc += (cx, cy, s * o.stride * tot)
            wsum += tot
        x, y, scale = acc / wsum
        return ShirtLocation(float(x), float(y), float(scale), u_max, u_max >= o.min_uniformity)


def reduce_image(image: NDArray[np.uint8], downscale: int) -> NDArray[np.uint8]:
    """``image`` ``downscale`` times smaller (area averaging; itself when 1)."""
    if downscale == 1:
        return image
    h, w = image.shape[:2]
    return np.asarray(cv2.resize(image, (w // downscale, h // downscale),
                                 interpolation=cv2.INTER_AREA), dtype=np.uint8)


def reduce_box(box: tuple[int, int, int, int], downscale: int, width: int, height: int
               ) -> tuple[int, int, int, int]:
    """A full-resolution box ``(x0, y0, x1, y1)`` at ``downscale``, widened to whole
    pixels and clipped to the reduced image's ``width`` and ``height``."""
    d = downscale
    return (max(box[0] // d, 0), max(box[1] // d, 0),
            min(-(-box[2] // d), width), min(-(-box[3] // d), height))


class BackgroundMask:
    """Coarse foreground mask from OpenCV's MOG2 subtractor, run at reduced resolution;
    :meth:`apply` gives None during the ``warmup`` frames and for an almost empty mask."""

    def __init__(
        self, downscale: int = 2, history: int = 500, warmup: int = 1, min_fraction: float = 0.01
    ) -> None:
        self.downscale = max(1, int(downscale))
        self.warmup = warmup
        self.min_fraction = min_fraction
        self._sub = cv2.createBackgroundSubtractorMOG2(history=history, varThreshold=16,
                                                       detectShadows=False)
        self._frames = 0
        self.raw: NDArray[np.bool_] | None = None
        """The last frame's undilated foreground at the model's resolution."""

    def moving(self, box: tuple[int, int, int, int]) -> float | None:
        """Share of the last frame's pixels inside ``box`` (full-resolution px) that
        the model saw change (None during the warm-up or for an empty box)."""
        if self.raw is None:
            return None
        h, w = self.raw.shape
        x0, y0, x1, y1 = reduce_box(box, self.downscale, w, h)
        if x1 <= x0 or y1 <= y0:
            return None
        return float(self.raw[y0:y1, x0:x1].mean())

    def reduce(self, image: NDArray[np.uint8]) -> NDArray[np.uint8]:
        """``image`` at the model's resolution (what :meth:`apply` works on)."""
        return reduce_image(image, self.downscale)

    def apply(self, image: NDArray[np.uint8], small: NDArray[np.uint8] | None = None
              ) -> NDArray[np.bool_] | None:
        """Update the model with an RGB frame; the dilated foreground mask or None.

        ``small`` is the frame already reduced by :meth:`reduce`, if the caller has it.
        """
        h, w = image.shape[:2]
        if small is None:
            small = self.reduce(image)
        fg = self._sub.apply(small)
        self._frames += 1
        if self._frames <= self.warmup:
            self.raw = None
            return None
        self.raw = fg > 0
        fg = cv2.dilate((fg > 0).astype(np.uint8), np.ones((5, 5), np.uint8))
        if fg.mean() < self.min_fraction:
            return None
        if self.downscale > 1:
            fg = cv2.resize(fg, (w, h), interpolation=cv2.INTER_NEAREST)
        return fg > 0
