"""Where a track starts: the combination of candidate regions, one (or none) per
camera, that a fit explains best.

With the player in view from the first frame there is no background mask: the most
colourful region can be a poster or a fruit bowl, which neither moves nor fits an
upright torso that both cameras see. So every combination of each camera's
candidate regions is fitted, and a combination starts the track only if its fit is
plausible and upright; among those the one that counts the most cameras, then (one
camera) anchors the most of the shirt's patches, then fits best, wins. A region
nothing was seen to move in is *held* instead (a player standing still looks just
like it, and the room plates must not learn it), unless one camera's fit anchors
enough of the shirt to be a player (:data:`STILL_PATCHES`). docs/colorshirt.md,
"The start"; history section 2.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from bodyplay.trackers.colorshirt.views import CameraView

__all__ = ["STILL_PATCHES", "START_PATCHES", "StartChoice", "choose_start"]

STILL_PATCHES = 8
"""Patches of the shirt (of 20) that the fit of a start region nothing was seen to
move in must anchor for the region to start the track anyway: a player standing
still facing the camera shows about 10 (the ninja's virtual player waiting for its
first gesture: 10), while clutter in shirt colours whose fit passes the upright test
showed 2-5; those regions are held instead (not started on, and not learned by the
room plates). With several cameras a still region is always held: a start from one
camera's region is placed by the shirt's size alone."""

START_PATCHES = 6
"""Patches of the shirt (of 20) that the fit of any start region must anchor with one
camera (a still region: :data:`STILL_PATCHES`), and among the regions that qualify
the one anchoring the most starts the track: how much of the shirt's layout a fit
explains tells the player from shirt-coloured clutter, its residual does not (a fit
of 3 patches reprojects as well as one of 10). A player facing the camera shows 7-11;
in the clothes room under coloured light the first frames offered the shirt merged
with the clothes rail behind it (not upright) and a moving piece of it (3-5
patches, low residual), which started the track 1-2 m off."""

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
                 root_band: tuple[float, float], motion_known: bool) -> StartChoice:
    """The best combination of ``candidates`` (per camera), each region or none.

    ``tracked``: the view of the camera ``lone`` that alone started the track (every
    combination holds it; empty when there is none); ``moved``: whether MOG2 saw a
    region move (read only when ``motion_known``); ``fit``: a combination's fit, None
    when implausible; ``root_band``: metres, where an upright fit's root may be.
    """
    one = len(candidates) == 1
    lo, hi = root_band
    best: tuple[tuple[int, int, int, float], list[CameraView]] | None = None
    held: list[CameraView] = []
    choices: list[list[CameraView | None]] = [
        [*tracked] or [None] if i == lone else [*c, None] for i, c in enumerate(candidates)]
    for combo in itertools.product(*choices):
        chosen = [v for v in combo if v is not None]
        still = motion_known and not all(moved(v) for v in chosen if v.index != lone)
        if len(chosen) <= len(tracked) or (still and len(chosen) > 1):
            continue  # nothing added, or a camera saw nothing move there
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
        key = (int(still), -len(chosen), -patches if one else 0, residual)
        if best is None or key < best[0]:
            best = (key, chosen)
    return StartChoice(None if best is None else best[1], held)
