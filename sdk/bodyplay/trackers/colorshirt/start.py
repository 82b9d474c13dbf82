"""Where a track starts: the combination of candidate regions, one (or none) per
camera, that a fit explains best (docs/colorshirt.md, "The start").

A combination counts only if its fit is plausible and upright; the one with the
most cameras, then (one camera) the region lying most in what moved
(:data:`MOVED_SHARE`), the most patches anchored, then the lowest residual wins. A
region nothing moved in is *held* (maybe a still player), unless one camera's fit
anchors enough of the shirt (:data:`STILL_PATCHES`), or ignored when the room plate
learned it on frames without a player (the empty room).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from bodyplay.trackers.colorshirt.views import CameraView

__all__ = ["MOVED_SHARE", "STILL_PATCHES", "START_PATCHES", "StartChoice", "choose_start"]

STILL_PATCHES = 8
"""Patches (of 20) a one-camera fit of a region nothing moved in must anchor to start
the track anyway (a still player shows about 10, clutter 2-5)."""

START_PATCHES = 6
"""Patches (of 20) a one-camera start must anchor (a player facing the camera: 7-11)."""

MOVED_SHARE = 0.5
"""Share of a one-camera start region's shirt box that must lie where the room plate
saw a player move for the region to rank before those that do not (a still poster
beside the player lies outside; a lone camera's first frame and a player waiting
still lie in nothing that moved, and still start when nothing else fits)."""

StartFit = tuple[NDArray[np.float64], int, float]
"""A combination's fit: pose vector, patches anchored, mean relative residual."""


@dataclass
class StartChoice:
    """The combination chosen (None: none qualified) and the regions held: they fit a
    shirt but never moved."""

    views: list[CameraView] | None
    held: list[CameraView] = field(default_factory=list)


def choose_start(candidates: list[list[CameraView]], tracked: list[CameraView],
                 lone: int | None, moved: Callable[[CameraView], bool],
                 fit: Callable[[list[CameraView]], StartFit | None],
                 root_band: tuple[float, float], motion_known: bool,
                 seen_empty: Callable[[CameraView], bool] | None = None,
                 moved_share: Callable[[CameraView], float] | None = None) -> StartChoice:
    """The best combination of ``candidates`` (per camera), each region or none.

    ``tracked``: the view of the camera ``lone`` that alone started the track (every
    combination holds it; empty when there is none); ``moved``: whether MOG2 saw a
    region move (read only when ``motion_known``); ``fit``: a combination's fit, None
    when implausible; ``root_band``: metres, where an upright fit's root may be;
    ``seen_empty``: whether a region was learned as the empty room (a region nothing
    moved in there is room: neither started on nor held, so the plates learn it);
    ``moved_share``: (one camera) how much of a region lies where the room plate saw a
    player move: a region of :data:`MOVED_SHARE` or more ranks first.
    """
    one = len(candidates) == 1
    lo, hi = root_band
    best: tuple[tuple[int, int, int, int, float], list[CameraView]] | None = None
    held: list[CameraView] = []
    choices: list[list[CameraView | None]] = [
        [*tracked] or [None] if i == lone else [*c, None] for i, c in enumerate(candidates)]
    for combo in itertools.product(*choices):
        chosen = [v for v in combo if v is not None]
        still = motion_known and not all(moved(v) for v in chosen if v.index != lone)
        if len(chosen) <= len(tracked) or (still and len(chosen) > 1):
            continue  # nothing added, or a camera saw nothing move there
        if still and seen_empty is not None and any(
                seen_empty(v) for v in chosen if v.index != lone and not moved(v)):
            continue  # the room, seen empty: the plates learn it
        result = fit(chosen)
        if result is None:
            continue
        q, patches, residual = result
        if not np.isfinite(residual) or not lo <= q[1] <= hi:
            continue
        if still and (patches < STILL_PATCHES or not one):
            held += chosen  # a shirt that fits but never moved: maybe a player
            continue  # standing still, whom the plates must not learn
        if one and patches < START_PATCHES:
            continue  # too little of the shirt's layout to tell it from clutter
        lying = one and moved_share is not None and moved_share(chosen[0]) >= MOVED_SHARE
        key = (int(still), -len(chosen), -int(lying), -patches if one else 0, residual)
        if best is None or key < best[0]:
            best = (key, chosen)
    return StartChoice(None if best is None else best[1], held)
