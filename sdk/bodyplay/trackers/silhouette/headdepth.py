"""A second depth cue: the head top's row in the window and the chosen template's.

The floor point G (:mod:`.window`) fixes the distance of the silhouette's lowest
pixel, and the body is placed there by the chosen template's own offset from its
floor point. The silhouette hardly tells a foot set forward from one set back, so
that offset is often a template's, not the player's: the tune captures' median
root error was 4 to 14 cm, mostly along the line of sight, with a sign of its own
per clip. The head top is a second, independent cue: the window is a level camera
at the real camera's height c with ``d / mpp`` pixels of focal length, so a head top
at height H > c seen from distance d' instead of d sits

    row(d') - row(d) = (H - c) (d' - d) / (mpp d)

pixels lower. The template's head top (its pose, at G) against the observed one
thus gives d' - d. The cue is weak when the head is near the camera's height (a
bow, a camera at head height), so it is skipped below a lever ``min_lever``; it is
noisier than the floor (whole pixels of hair, the body preset's stature), so the
tracker blends it in with a weight and takes its median over a short window.
"""

from __future__ import annotations

from collections import deque

import numpy as np

__all__ = ["head_depth_offset", "RunningMedian"]


def head_depth_offset(observed_top: float, template_top: float, floor_row: float, mpp: float,
                      distance: float, camera_height: float, min_lever: float = 0.3
                      ) -> float | None:
    """How much farther (m; negative: nearer) the player stands than the template
    placed at G says, from the head tops' window rows (level-3 pixels, the template's
    with its fitted shift), the window's floor row and metres per pixel at G,
    G's horizontal ``distance`` and the camera's height. None when the template's
    head top is less than ``min_lever`` m above the camera (no leverage)."""
    head = (floor_row - template_top) * mpp
    lever = head - camera_height
    if lever < min_lever or distance <= 0:
        return None
    return float((observed_top - template_top) * mpp * distance / lever)


class RunningMedian:
    """A depth cue's running median over the last ``window`` seconds (the head top's
    and the stance's)."""

    def __init__(self, window: float) -> None:
        self.window = window
        self._seen: deque[tuple[float, float]] = deque()

    def add(self, t: float, offset: float | None) -> float:
        """Record the offset of time ``t`` (None: no cue this frame) and return the
        median over the window (0 when there is none)."""
        if offset is not None:
            self._seen.append((t, offset))
        while self._seen and t - self._seen[0][0] > self.window:
            self._seen.popleft()
        if not self._seen:
            return 0.0
        return float(np.median([o for _, o in self._seen]))
