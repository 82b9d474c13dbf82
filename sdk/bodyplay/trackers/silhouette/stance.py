"""A stance cue for the root's depth: the two feet's floor rows, observed and templated.

The floor point G (:mod:`.window`) is under the silhouette's lowest pixel: the
front foot's toe. The body is placed there by the chosen template's own offset
from its lowest pixel, so a template with a foot set forward placed on a player
standing with the feet together (or the other way round) puts the whole body
too far (too near) by about half the feet's depth spread: the tune captures' root
errors, 4 to 14 cm, were mostly this, along the line of sight, with a sign of its
own per clip. Here the lowest row of each half (left and right of the middle of
the feet) of the silhouette's lowest ``band`` pixels gives each foot's floor
point; the mean of the two, observed against the template's (moved by its fitted
shift, placed at G), says how much nearer or farther the feet -- and the body on
them -- stand than the template says. In the window (a level camera at height c,
focal ``d / mpp``) a floor row r lies at distance ``d c / (mpp (r - r_floor) + c)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["feet_rows", "stance_offset"]


def feet_rows(mask: NDArray[np.uint8], band: int) -> tuple[float, float] | None:
    """The lowest row of the left and of the right half of a window mask's lowest
    ``band`` rows (halves split at the middle of those rows' columns), None when
    the mask is empty."""
    m = np.asarray(mask) > 0
    rows = np.flatnonzero(m.any(axis=1))
    if rows.size == 0:
        return None
    lo = int(rows[-1])
    top = max(0, lo - band)
    part = m[top:lo + 1]
    cols = np.flatnonzero(part.any(axis=0))
    mid = 0.5 * (cols[0] + cols[-1])
    out = []
    for sel in (cols[cols <= mid], cols[cols > mid]):
        if sel.size == 0:
            sel = cols
        out.append(float(top + np.flatnonzero(part[:, sel].any(axis=1))[-1]))
    return out[0], out[1]


def _distance(row: float, floor_row: float, mpp: float, distance: float,
              camera_height: float) -> float | None:
    den = mpp * (row - floor_row) + camera_height
    if den < 0.5 * camera_height:  # more than twice G's distance: no floor contact
        return None
    return distance * camera_height / den


def stance_offset(observed: NDArray[np.uint8], template: NDArray[np.uint8], floor_row: float,
                  mpp: float, distance: float, camera_height: float, band: int,
                  max_offset: float = 0.4) -> float | None:
    """How much farther (m; negative: nearer) the observed feet's mean floor point
    lies than the template's, both in the window built for G at ``distance`` (level-3
    masks, the template already moved by its fitted shift). None when either mask
    is empty, the camera is not above the floor, a foot's row lies farther than
    twice G's distance or the offset exceeds ``max_offset`` m (no stance differs so
    much: a limb or a shadow at the bottom, not feet)."""
    if camera_height <= 0:
        return None
    fo, ft = feet_rows(observed, band), feet_rows(template, band)
    if fo is None or ft is None:
        return None
    ds = [_distance(r, floor_row, mpp, distance, camera_height) for r in (*fo, *ft)]
    if any(d is None for d in ds):
        return None
    off = 0.5 * (ds[0] + ds[1]) - 0.5 * (ds[2] + ds[3])  # type: ignore[operator]
    return float(off) if abs(off) <= max_offset else None
