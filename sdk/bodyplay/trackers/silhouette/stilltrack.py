"""Whether the track follows what moves: evidence, over time, that the body being
tracked is not the player.

With the player in view from the first frame, the first frame's figure/ground
guess can take something still for the body: a photo of a person beside the
player, a statue, a pillar. The tracker then fits its templates to it, protects it
from being learned, and keeps only the foreground components that touch it
(:func:`.window.select_person`): the player's own moving limbs, in components of
their own, are dropped as "a second person". Such a track is never lost, so the
undo of a start that did not hold (``restart_within``) never sees it, and one
frame's fit does not tell it (a pictured person can fit a template as well as the
player).

What tells it is evidence accumulated over time. Over the last ``window`` seconds
of a track, the pixels that moved (frame to frame,
:attr:`.background.BackgroundModel.moving`) are counted in the foreground the track
keeps and in the foreground it drops. A track is *still* when what it keeps moved
under a tenth of ``share`` of the image per frame on average: not a limb, not a
sway, only codec noise. A still track is not the player when

* what it drops moved at least ``share`` of the image per frame (the player is the
  one who moves), or
* its templates fit it at a median distance (eq. 11) of at least ``poor_fit`` while
  the foreground it drops covers at least ``other`` of the image (median over the
  window; the tracker passes the background model's ``min_area``, the smallest
  blob its clean-up keeps): motion tells nothing when the player stands still
  too, but a pictured figure's resolution gives shreds no pose fits (distances
  about 1; the tune captures' tracks stay under 0.25, the still ones under 0.11),
  and there is something else in view to take instead.

The tracker then guesses again (:meth:`.tracker.SilhouetteTracker`: what the track
held is learned as background, the track is forgotten). A moving track is never
doubted: a player whose silhouette lost its legs fits as badly as a photo, but
moves; a player who stands still beside someone who moves, for a whole window,
is (a second person then takes the track, as it would if the player left).
"""

from __future__ import annotations

from collections import deque

import numpy as np

__all__ = ["TrackMotion"]


class TrackMotion:
    """Running evidence over a track's last ``window`` seconds (see the module
    docstring): ``share`` of the image per frame that counts as motion, ``poor_fit``
    the median distance of a still track that is no person (0: that rule off),
    ``other`` the share of the image the dropped foreground must cover for it."""

    def __init__(self, window: float, share: float, poor_fit: float = 0.0,
                 other: float = 0.002) -> None:
        self.window = window
        self.share = share
        self.poor_fit = poor_fit
        self.other = other
        self._frames: deque[tuple[float, int, int, int, float]] = deque()
        self._fits: deque[tuple[float, float]] = deque()

    def clear(self) -> None:
        """Forget the evidence (a new track)."""
        self._frames.clear()
        self._fits.clear()

    def add(self, t: float, kept: int, dropped: int, pixels: int,
            fit: float | None = None, others: float = 0.0) -> None:
        """One frame of a track at time ``t``: ``kept`` moving pixels in the foreground
        the track keeps, ``dropped`` in the foreground it drops, of ``pixels`` in all;
        ``fit``: the track's latest distance (eq. 11), when it has one; ``others``:
        the share of the image the dropped foreground covers."""
        self._frames.append((t, kept, dropped, pixels, others))
        while self._frames and t - self._frames[0][0] > self.window:
            self._frames.popleft()
        if fit is not None:
            self._fits.append((t, fit))
        while self._fits and t - self._fits[0][0] > self.window:
            self._fits.popleft()

    @property
    def span(self) -> float:
        """Seconds between the oldest and the newest frame of the evidence."""
        if not self._frames:
            return 0.0
        return self._frames[-1][0] - self._frames[0][0]

    def wrong(self) -> bool:
        """Whether, over a full window, the track was still while what it dropped
        moved, or was still, fitted no pose and had a rival (the module docstring's
        rules)."""
        if self.window <= 0 or self.span < 0.9 * self.window:
            return False
        kept = sum(f[1] for f in self._frames)
        pixels = sum(f[3] for f in self._frames)
        if kept > 0.1 * self.share * pixels:
            return False  # the track moves: it is someone
        if sum(f[2] for f in self._frames) >= self.share * pixels:
            return True
        if self.poor_fit <= 0 or len(self._fits) < 0.5 * len(self._frames):
            return False
        others = float(np.median([f[4] for f in self._frames]))
        return bool(others >= self.other
                    and float(np.median([f for _, f in self._fits])) >= self.poor_fit)
