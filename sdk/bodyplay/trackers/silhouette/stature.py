"""Readings of a silhouette's shape in the window: the head top, the shoulder row, how
far a template reaches against an observed silhouette (the body-size cue) and the
least silhouette a whole person makes (the start check), all in window pixels of a
:class:`~bodyplay.trackers.silhouette.window.WindowGeometry`, where one pixel is a
fixed size wherever the player stands."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from bodyplay.trackers.silhouette.hierarchy import ShapeTree
from bodyplay.trackers.silhouette.window import WindowGeometry


def head_top(mask: NDArray[np.uint8], half: float = 0.03) -> float | None:
    """The highest silhouette row in the window's middle columns (the head above the
    floor point, ``half`` of the width either side), None when empty."""
    w = mask.shape[1]
    a, b = int(round(w * (0.5 - half))), int(round(w * (0.5 + half))) + 1
    rows = np.flatnonzero(np.asarray(mask)[:, a:b].any(axis=1))
    return float(rows[0]) if rows.size else None


def shoulder_row(mask: NDArray[np.uint8], wide: float, search: float = 0.03) -> float | None:
    """The highest row whose run of silhouette through the window's middle (a
    silhouette pixel within ``search`` of the width of the centre) is at least
    ``wide`` pixels wide: the shoulders (a head, a neck or a raised forearm is
    narrower), None when no row is."""
    m = np.asarray(mask) > 0
    h, w = m.shape
    c = w // 2
    r = max(1, int(round(w * search)))
    for y in np.flatnonzero(m[:, c - r:c + r + 1].any(axis=1)):
        row = m[y]
        near = np.flatnonzero(row[c - r:c + r + 1])
        x = c - r + int(near[len(near) // 2])
        gaps = np.flatnonzero(~row)
        left = gaps[gaps < x]
        right = gaps[gaps > x]
        lo = int(left[-1]) + 1 if left.size else 0
        hi = int(right[0]) if right.size else w
        if hi - lo >= wide:
            return float(y)
    return None


def stature_reading(observed: NDArray[np.uint8], template: NDArray[np.uint8],
                    shift: tuple[int, int], wide: float, head_gap: float
                    ) -> tuple[float, bool] | None:
    """How far (window rows, + = lower) the template (its mask, placed moved by
    ``shift``) reaches from the observed silhouette's top, in the same pose: the head
    tops where the observed silhouette shows a head (its head top at least
    ``head_gap`` of the template's head-to-shoulder height above its shoulder row),
    else the shoulder rows (``wide``: the shoulder width in pixels); with whether
    the head was used. None when either lacks the reading."""
    ho, ht = head_top(observed), head_top(template)
    if ho is None or ht is None:
        return None
    ht += shift[1]
    if head_gap <= 0:
        return ht - ho, True
    so, st = shoulder_row(observed, wide), shoulder_row(shifted(template, shift), wide)
    if so is None or st is None:
        return ht - ho, True
    if so - ho >= head_gap * (st - ht):
        return ht - ho, True
    return st - so, False


def smallest_template_area(tree: ShapeTree, geometry: WindowGeometry, level: int = 0) -> float:
    """The area (m2, in the window) of the smallest template of any body preset at
    ``level``: the least silhouette a whole person standing in view makes."""
    areas = []
    for bt in tree.bodies.values():
        runs = bt.runs[level]
        if len(runs):
            px = np.add.reduceat((runs.x1.astype(np.int64) - runs.x0), runs.offsets[:-1])
            areas.append(float(px.min()))
    return min(areas, default=0.0) * geometry.mpp(level) ** 2


def shifted(mask: NDArray[np.uint8], shift: tuple[int, int]) -> NDArray[np.uint8]:
    """``mask`` moved by whole pixels (x right, y down), zeros coming in."""
    out = np.zeros_like(mask)
    h, w = mask.shape
    dx, dy = shift
    out[max(dy, 0):h + min(dy, 0), max(dx, 0):w + min(dx, 0)] = \
        mask[max(-dy, 0):h + min(-dy, 0), max(-dx, 0):w + min(-dx, 0)]
    return out
