"""Whether the track follows what moves: evidence, over time, that the body being
tracked is not the player.

With the player in view from the first frame, the first frame's figure/ground
guess can take something still for the body: a photo of a person beside the
player, a statue, a pillar. The tracker then fits its templates to it, protects it
from being learned, and keeps only the foreground components that touch it
(:func:`.window.select_person`): the player's own moving limbs, in components of
their own, are dropped as "a second person". Such a track is never lost, so the
undo of a start that did not hold (``restart_within``) never sees it, and the fit
alone does not tell it (a pictured person fits a template as well as the player).

What tells it is motion, accumulated over time: the player is the one who moves.
Over the last ``window`` seconds of a track, the pixels that moved (frame to frame,
:attr:`.background.BackgroundModel.moving`) are counted in the foreground the track
keeps and in the foreground it drops. When what it drops moved at least ``share``
of the image per frame on average and what it keeps moved at most ``ratio`` times
that, the track follows something that stands still while something else moves,
and the tracker guesses again (:meth:`.tracker.SilhouetteTracker`: what the track
kept is learned as background, the track is forgotten).

A player who stands still while something else moves (a second person walking
behind) keeps the track only while that motion stays under ``share``, or their
own motion over ``ratio`` of it; a player's waving arm is part of the component
the track keeps, so it counts as the track's own motion.

When the player, too, stands still, motion tells nothing; then the fit does. A
track whose kept foreground has not moved at all over the window (under a tenth
of ``share`` per frame) and whose templates fit it at a median distance (eq. 11)
of at least ``poor_fit`` is not a person either: the resolution of a pictured
figure beside the player gives shreds no pose fits (distances about 1), while the
tune captures' tracks, moving or not, stay under 0.25 (still ones under 0.11).
A poor fit alone is not enough: the player with a broken silhouette (legs
resolved as the floor) fits as badly, and then the kept foreground moves; nor is
a still poor track without another candidate: the rule asks that the foreground
the track drops covers at least ``other`` of the image (median over the window),
so that there is something else to guess (the player standing still beside a
photo; once the photo is learned as the room, the player's own still track with
a poor fit is kept).
"""

from __future__ import annotations

from collections import deque

import numpy as np

__all__ = ["TrackMotion"]


class TrackMotion:
    """Running sums of the moving pixels a track keeps and drops over a time window
    (see the module docstring). ``window`` seconds, ``share`` of the image per frame,
    ``ratio`` of the dropped motion, ``poor_fit`` the median distance of a still track
    that is not a person (0: off)."""

    def __init__(self, window: float, share: float, ratio: float, poor_fit: float = 0.0,
                 other: float = 0.01) -> None:
        self.window = window
        self.share = share
        self.ratio = ratio
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
        """Whether, over a full window, the track kept what stood still while what it
        dropped moved, or kept what stood still and fitted no pose (the module
        docstring's rules)."""
        if self.window <= 0 or self.span < 0.9 * self.window:
            return False
        kept = sum(f[1] for f in self._frames)
        dropped = sum(f[2] for f in self._frames)
        pixels = sum(f[3] for f in self._frames)
        if dropped >= self.share * pixels and kept <= self.ratio * dropped:
            return True
        others = float(np.median([f[4] for f in self._frames]))
        return bool(self.poor_fit > 0 and kept <= 0.1 * self.share * pixels
                    and others >= self.other and len(self._fits) >= 0.5 * len(self._frames)
                    and float(np.median([f for _, f in self._fits])) >= self.poor_fit)
