"""The room behind the player, learned from what the player uncovers (beyond the paper).

A player who starts in view never shows the empty room, and MOG2 absorbs clutter
and a still player alike. :class:`RoomPlate` learns the room from where the player
is *not*: every pixel outside the dilated silhouette of the pose just reported that
stayed still follows a running mean and after a few frames is *known*; a known
pixel that matches the plate is room, every other pixel may be the player. A change
of light scales the plate by one gain per channel.
"""

from __future__ import annotations

import cv2
import numba
import numpy as np
from numpy.typing import NDArray

__all__ = ["RoomPlate", "column_median"]


def column_median(x: NDArray[np.floating]) -> NDArray[np.floating]:
    """``np.median(x, axis=0)`` of an (N, C) array with N >= 1 and no NaN, the same
    values, several times faster (one partition of the contiguous transpose)."""
    n = x.shape[0]
    h = n // 2
    part = np.partition(np.ascontiguousarray(x.T), h, axis=1)
    if n % 2:
        return part[:, h] / 1
    return (part[:, :h].max(axis=1) + part[:, h]) / 2


@numba.njit(cache=True, nogil=True)
def _learn(mean: NDArray[np.float32], count: NDArray[np.uint8], f: NDArray[np.float32],
           learn: NDArray[np.bool_], rate: np.float32) -> None:  # pragma: no cover - compiled
    """In place, where ``learn``: the running mean moves towards ``f`` by
    ``max(1 / (count + 1), rate)`` and the count grows (at most 255)."""
    h, w = count.shape
    one = np.float32(1.0)
    for y in range(h):
        for x in range(w):
            if not learn[y, x]:
                continue
            n = count[y, x]
            a = one / (np.float32(n) + one)
            if a < rate:
                a = rate
            for k in range(3):  # RGB (a constant count: unrolled)
                m = mean[y, x, k]
                mean[y, x, k] = m + a * (f[y, x, k] - m)
            if n < 255:
                count[y, x] = n + 1


@numba.njit(cache=True, nogil=True)
def _light_ratios(f: NDArray[np.float32], mean: NDArray[np.float32], count: NDArray[np.uint8],
                  known_frames: int, away: NDArray[np.bool_], use_away: bool, step: int
                  ) -> NDArray[np.float32]:  # pragma: no cover - compiled
    """(N, 3) ``f / max(mean, 1)`` at every ``step``-th row and column's known pixels
    (and ``away``, if ``use_away``), in row order."""
    h, w = count.shape
    out = np.empty((((h + step - 1) // step) * ((w + step - 1) // step), 3), np.float32)
    one = np.float32(1.0)
    n = 0
    for y in range(0, h, step):
        for x in range(0, w, step):
            if count[y, x] < known_frames or (use_away and not away[y, x]):
                continue
            for k in range(3):
                m = mean[y, x, k]
                out[n, k] = f[y, x, k] / (m if m > one else one)
            n += 1
    return out[:n]


@numba.njit(cache=True, nogil=True)
def _stillness(f: NDArray[np.float32], prev: NDArray[np.float32], run: NDArray[np.uint8],
               count: NDArray[np.uint8], still: np.float32, known_frames: int
               ) -> tuple[NDArray[np.bool_], NDArray[np.uint8], int, int]:  # pragma: no cover
    """Per pixel whether its summed R + G + B change from ``prev`` is under ``still``,
    the frames in a row it has been still (at most 255), and how many known pixels
    there are and how many of them moved."""
    h, w = run.shape
    is_still = np.empty((h, w), np.bool_)
    new_run = np.empty((h, w), np.uint8)
    known = 0
    moving = 0
    for y in range(h):
        for x in range(w):
            d = (abs(f[y, x, 0] - prev[y, x, 0]) + abs(f[y, x, 1] - prev[y, x, 1])
                 + abs(f[y, x, 2] - prev[y, x, 2]))
            s = d < still
            is_still[y, x] = s
            r = run[y, x]
            new_run[y, x] = (r + 1 if r < 255 else 255) if s else 0
            if count[y, x] >= known_frames:
                known += 1
                if not s:
                    moving += 1
    return is_still, new_run, known, moving


@numba.njit(cache=True, nogil=True)
def _room(small: NDArray[np.float32], mean: NDArray[np.float32], count: NDArray[np.uint8],
          known_frames: int, threshold: np.float32, alike: NDArray[np.bool_], use_alike: bool
          ) -> NDArray[np.uint8]:  # pragma: no cover - compiled
    """1 where a known pixel's summed R + G + B difference from the plate is at most
    ``threshold``, or an unknown one is seen alike."""
    h, w = count.shape
    out = np.zeros((h, w), np.uint8)
    for y in range(h):
        for x in range(w):
            if count[y, x] >= known_frames:
                d = (abs(small[y, x, 0] - mean[y, x, 0]) + abs(small[y, x, 1] - mean[y, x, 1])
                     + abs(small[y, x, 2] - mean[y, x, 2]))
                if d <= threshold:
                    out[y, x] = 1
            elif use_alike and alike[y, x]:
                out[y, x] = 1
    return out


class RoomPlate:
    """One camera's plate of the room at reduced resolution (see the module docstring).

    Per frame: :meth:`start`, :meth:`foreground`, then :meth:`learn`. A pixel is
    still under a summed R + G + B change of ``still``, learned after
    ``still_frames`` still frames in a row, known after ``known_frames`` learned
    ones; ``rate`` is the slowest weight of a new frame; ``threshold`` and
    ``contrast_level`` as :class:`.floor.BackgroundPlate`'s.
    """

    def __init__(self, still: float = 30.0, still_frames: int = 3, known_frames: int = 4,
                 rate: float = 0.05, threshold: float = 45.0,
                 contrast_level: float = 330.0) -> None:
        self.still = float(still)
        self.still_frames = int(still_frames)
        self.known_frames = int(known_frames)
        self.rate = float(rate)
        self.threshold = float(threshold)
        self.contrast_level = float(contrast_level)
        self._mean: NDArray[np.float32] | None = None
        self._count: NDArray[np.uint8] | None = None
        self._run: NDArray[np.uint8] | None = None
        self._prev: NDArray[np.float32] | None = None
        self._small: NDArray[np.float32] | None = None
        self.empty_room: NDArray[np.bool_] | None = None
        """Pixels learned on frames before the player was seen (an empty-room start;
        None if there were none)."""
        self._moved: NDArray[np.bool_] | None = None
        """Pixels seen to change (not with the light) since the plate began."""
        self._away: NDArray[np.bool_] | None = None
        """Pixels away from the player at the last :meth:`learn` (the light's gain)."""
        self.seen_alike: NDArray[np.bool_] | None = None
        """This frame's pixels another camera shows as the same room (None: no answer)."""
        self._fg: tuple[NDArray[np.bool_] | None] | None = None
        """This frame's :meth:`foreground`, once asked (None: not yet)."""
        self._zone: tuple[NDArray[np.bool_] | None] | None = None
        """:meth:`moved_zone` since the changed pixels last grew (None: not asked)."""

    @property
    def known(self) -> NDArray[np.bool_] | None:
        """Pixels learned often enough to be trusted (None before any frame)."""
        if self._count is None:
            return None
        return self._count >= self.known_frames

    def saw_a_player_move(self) -> bool:
        """Whether the pixels seen to change since the plate began hold a patch of at
        least 3 x 3 plate pixels: a player who moved. A camera's noise changes single
        pixels and pairs, scattered (an empty room's second changes hundreds of them),
        never a whole patch; a limb changes patches."""
        return self.moved_zone() is not None

    def moved_zone(self) -> NDArray[np.bool_] | None:
        """Where a player who moved may be: the convex hull of the changed 3 x 3 patches
        (:meth:`saw_a_player_move`) and everything under it (a still trunk and legs
        under arms that wave). Still room the player never crossed, beside or above
        it, lies outside. None until a player moved. Computed once each time the
        changed pixels grow (read-only)."""
        if self._zone is None:
            self._zone = (self._moved_zone(),)
        return self._zone[0]

    def _moved_zone(self) -> NDArray[np.bool_] | None:
        if self._moved is None:
            return None
        patches = cv2.morphologyEx(self._moved.astype(np.uint8), cv2.MORPH_OPEN,
                                   np.ones((3, 3), np.uint8),
                                   borderType=cv2.BORDER_CONSTANT, borderValue=0)
        points = cv2.findNonZero(patches)
        if points is None:
            return None
        zone = np.zeros(patches.shape, np.uint8)
        cv2.fillConvexPoly(zone, cv2.convexHull(points), 1)
        out = np.logical_or.accumulate(zone > 0, axis=0)
        out.flags.writeable = False
        return out

    def start(self, small: NDArray[np.uint8] | NDArray[np.float32],
              seen_alike: NDArray[np.bool_] | None = None) -> None:
        """A new frame at the plate's resolution (RGB); the plate follows the light.
        ``seen_alike``: pixels another camera shows as the same room, room this
        frame where the plate does not know it."""
        self.seen_alike, self._fg = seen_alike, None
        f = np.asarray(small, np.float32)
        if self._mean is None or self._mean.shape != f.shape:
            h, w = f.shape[:2]
            self._mean = f.copy()
            self._count = np.zeros((h, w), np.uint8)
            self._run = np.zeros((h, w), np.uint8)
            self._prev = f
            self._moved = np.zeros((h, w), bool)
            self._zone = None
            self._away = None
        self._small = f
        assert self._count is not None
        away = self._away
        ratio = _light_ratios(f, self._mean, self._count, self.known_frames,  # every 3rd
                              np.zeros((1, 1), bool) if away is None else away,
                              away is not None, 3)
        if len(ratio) > 100:
            # the median ratio: robust to a player standing where no pose says yet
            gain = np.clip(column_median(ratio), 0.05, 20.0).astype(np.float32)
            if np.any(np.abs(gain - 1.0) > 0.01):
                self._mean *= gain

    def foreground(self) -> NDArray[np.bool_] | None:
        """This frame's pixels that may be the player: unlike the plate where it knows
        the room, else not seen alike by another camera. None while neither tells
        (no mask). Computed once a frame (read-only)."""
        if self._fg is None:
            fg = self._foreground()
            if fg is not None:
                fg.flags.writeable = False
            self._fg = (fg,)
        return self._fg[0]

    def _foreground(self) -> NDArray[np.bool_] | None:
        if self._small is None or self._mean is None:
            return None
        known = self.known
        assert known is not None
        if not known.any():
            return None if self.seen_alike is None else ~self.seen_alike
        level = float(np.sum(cv2.mean(self._mean)[:3]))
        threshold = self.threshold * min(1.0, max(0.3, level / self.contrast_level))
        alike = self.seen_alike
        assert self._count is not None
        room = _room(self._small, self._mean, self._count, self.known_frames,
                     np.float32(threshold), np.zeros((1, 1), np.bool_) if alike is None
                     else np.ascontiguousarray(alike), alike is not None)
        return ~(cv2.morphologyEx(room, cv2.MORPH_OPEN, np.ones((3, 3), np.uint8)) > 0)

    def learn(self, person: NDArray[np.bool_] | None, everywhere: bool = False,
              ambiguous: NDArray[np.bool_] | None = None) -> None:
        """Learn this frame's still pixels outside ``person`` (plate resolution; None:
        no pose, nothing is learned unless ``everywhere``). ``ambiguous`` pixels (maybe
        a still player) are learned only once the plate has seen them change."""
        f, prev = self._small, self._prev
        if f is None or prev is None or self._mean is None:
            return
        self._fg = None
        assert self._count is not None and self._run is not None and self._moved is not None
        still, self._run, known, moving = _stillness(
            np.ascontiguousarray(f, np.float32), np.ascontiguousarray(prev, np.float32),
            self._run, self._count, np.float32(self.still), self.known_frames)
        self._prev = f
        if moving / known < 0.5 if known else True:
            # a pixel that moves is forgotten (most of the room at once: the light)
            moved = ~still
            self._count[moved] = 0
            self._moved |= moved
            self._zone = None
        if person is None and not everywhere:
            self._away = None
            return
        away = np.ones(still.shape, bool) if person is None else ~person
        self._away = away
        learn = away & (self._run >= self.still_frames)
        if ambiguous is not None:
            learn &= self._moved | ~ambiguous
        if not learn.any():
            return
        if person is None:  # an empty-room frame (``everywhere``)
            self.empty_room = learn if self.empty_room is None else self.empty_room | learn
        _learn(self._mean, self._count, np.ascontiguousarray(f, np.float32), learn,
               np.float32(self.rate))
