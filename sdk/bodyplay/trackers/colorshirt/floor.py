"""Where the feet meet the floor: a depth cue for one camera, from a background plate.

One camera cannot tell a small person near from a tall one far: the shirt alone
fixes only the ratio of size to distance. The feet can: they stand on the floor
(world ``y = 0``), so the ray through the lowest pixel of the person meets the
floor at the person's distance. Beyond the paper.

Finding the feet needs a foreground mask that keeps legs that do not move, which
an adaptive subtractor (MOG2) does not: it absorbs a still person within frames.
:class:`BackgroundPlate` therefore learns the empty room (as a game does when it
asks the player to step out of view for a moment) and afterwards updates only
away from the person, correcting the plate for global changes of light by a gain
per channel measured there. :func:`feet_points` takes the lowest foreground pixels
of each foot of the blob below the shirt; :func:`floor_depth` turns them into a depth along the
camera's axis.

Without empty-room frames (the player in view from the first frame) the feet are
read from the room plate (:class:`.plate.RoomPlate`), which learns the room from
what the player uncovers: a foot counts only where the plate knows the floor
under it, so a player who walks onto floor seen before tells the depth, and one
who stands still where the room was never seen gives no reading (the tracker
then falls back on the shirt's size, as without any plate).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.plate import RoomPlate

__all__ = [
    "BackgroundPlate", "FeetPoint", "FloorWatch", "feet_points", "floor_depth", "person_region",
]

Box = tuple[int, int, int, int]

_JOIN = np.ones((5, 5), np.uint8)
"""The blob is labelled on the mask dilated by this (plate pixels), so that the
parts of a foot that the plate's threshold splits still count as the body's: a
dark foot's instep matches a gray floor, the toes below it were an island of
their own, and the foot's lowest pixel came out at the instep, 10-20 px too
high (20-30 cm too far). The lowest points are read on the undilated mask."""


class BackgroundPlate:
    """The empty room as seen by one camera, at reduced resolution (OpenCV running mean).

    While nobody is in view (:meth:`learn`), every pixel follows the frames; once
    ``min_frames`` such frames were seen the plate is :attr:`ready`. While a person
    is tracked (:meth:`update_around`), only pixels outside the person's region
    follow, slowly, so that a player who stands still never fades into the plate.
    """

    def __init__(self, downscale: int = 2, min_frames: int = 8, rate: float = 0.02,
                 threshold: float = 40.0, contrast_level: float = 330.0) -> None:
        self.downscale = max(1, int(downscale))
        self.min_frames = int(min_frames)
        self.rate = float(rate)
        self.threshold = float(threshold)
        """Summed absolute difference over R, G, B (0..765) that counts as foreground
        in a scene at least as bright as ``contrast_level``."""
        self.contrast_level = float(contrast_level)
        """Summed R + G + B mean of the room (a mid-gray room: 330) below which the
        threshold shrinks in proportion, down to 30% of itself: in dim light every
        difference shrinks with the light, and a fixed threshold left the shaded side
        of the head out of the foreground (in the ``dim`` preset the head cue's disk
        was 60-75% full and its centre 4-6 px off in one camera; scaled, 86-95%
        full and 2-3 px off)."""
        self.reset()

    def reset(self) -> None:
        """Forget the plate."""
        self._mean: NDArray[np.float32] | None = None
        self._frames = 0

    @property
    def ready(self) -> bool:
        """Whether enough empty-room frames were seen to trust the plate."""
        return self._frames >= self.min_frames

    def small(self, image: NDArray[np.uint8], reduced: bool = False) -> NDArray[np.float32]:
        """``image`` at the plate's resolution, as float32 (``reduced``: it already is)."""
        h, w = image.shape[:2]
        if self.downscale > 1 and not reduced:
            image = np.asarray(cv2.resize(image, (w // self.downscale, h // self.downscale),
                                          interpolation=cv2.INTER_AREA), np.uint8)
        return image.astype(np.float32)

    def learn(self, small: NDArray[np.float32]) -> None:
        """A frame with nobody in view: the plate follows it (a running mean)."""
        if self._mean is None or self._mean.shape != small.shape:
            self._mean = small.copy()
            self._frames = 1
            return
        self._frames += 1
        alpha = max(1.0 / self._frames, 0.1)
        cv2.accumulateWeighted(small, self._mean, alpha)

    def update_around(self, small: NDArray[np.float32], person: Box) -> None:
        """A tracked frame: the whole plate follows the light's global change (one
        gain per channel, measured outside ``person``), then pixels outside
        ``person`` (plate pixels) follow the frame slowly.

        Scaling the whole plate keeps the part behind the person in step with the
        part around it: when only the surroundings followed a lamp switched off,
        the gain measured there drifted back to 1 within a few dozen frames while
        the plate behind the person still showed the room in the old light, and
        the whole region turned foreground.
        """
        if self._mean is None:
            return
        gain, _ = self._light_change(small, person)
        if np.any(np.abs(gain - 1.0) > 1e-3):
            self._mean *= gain
        keep = np.ones(small.shape[:2], np.uint8)
        x0, y0, x1, y1 = person
        keep[max(y0, 0): max(y1, 0), max(x0, 0): max(x1, 0)] = 0
        cv2.accumulateWeighted(small, self._mean, self.rate, mask=keep)

    def _light_change(self, small: NDArray[np.float32],
                      person: Box) -> tuple[NDArray[np.float32], float]:
        """The gain per channel from plate to ``small`` outside ``person``, and the
        frame's summed R + G + B level there."""
        assert self._mean is not None
        # measured on every 4th pixel of every 4th row: plenty for a mean
        step = 4
        outside = np.ones((-(-small.shape[0] // step), -(-small.shape[1] // step)), np.uint8)
        x0, y0, x1, y1 = person
        outside[max(y0, 0) // step: -(-max(y1, 0) // step),
                max(x0, 0) // step: -(-max(x1, 0) // step)] = 0
        plate = self._mean
        if int(np.count_nonzero(outside)) > 50:
            f = np.array(cv2.mean(small[::step, ::step], mask=outside)[:3])
            p = np.array(cv2.mean(plate[::step, ::step], mask=outside)[:3])
            gain = np.clip(f / np.maximum(p, 1.0), 0.05, 20.0).astype(np.float32)
            return gain, float(f.sum())
        return np.ones(3, np.float32), float(np.sum(cv2.mean(plate[::step, ::step])[:3]))

    def foreground(self, small: NDArray[np.float32], person: Box) -> NDArray[np.bool_] | None:
        """Foreground mask of ``small`` within ``person`` (False elsewhere).

        The plate is first scaled by the light's change, and the threshold by the
        room's brightness (:attr:`contrast_level`).

        The change is one gain per channel: the ratio of the frame's mean to the
        plate's over the pixels outside ``person``. None before the plate is ready.
        """
        if not self.ready or self._mean is None:
            return None
        gain, level = self._light_change(small, person)
        x0, y0, x1, y1 = person
        plate = self._mean
        threshold = self.threshold * min(1.0, max(0.3, level / self.contrast_level))
        # only the person's region is compared (the rest is plate by assumption)
        ys = slice(max(y0, 0), max(y1, 0))
        xs = slice(max(x0, 0), max(x1, 0))
        diff = cv2.transform(cv2.absdiff(small[ys, xs], plate[ys, xs] * gain),
                             np.ones((1, 3), np.float32))
        fg = np.zeros(small.shape[:2], np.uint8)
        fg[ys, xs] = cv2.morphologyEx((diff > threshold).astype(np.uint8), cv2.MORPH_OPEN,
                                      np.ones((3, 3), np.uint8))
        return fg > 0


@dataclass(frozen=True)
class FeetPoint:
    """The lowest point of the person in an image (full-resolution pixels)."""

    u: float
    v: float


def person_region(shirt: Box, width: int, height: int) -> Box:
    """Where the person may be, from the shirt's box: around it and down to the floor."""
    x0, y0, x1, y1 = shirt
    w, h = x1 - x0, y1 - y0
    return (max(0, x0 - w), max(0, y0 - h), min(width, x1 + w), height)


def feet_points(fg: NDArray[np.bool_], shirt: Box, downscale: int,
                known: NDArray[np.bool_] | None = None) -> tuple[FeetPoint, ...]:
    """The lowest point of each foot of the blob the shirt belongs to (none, one or two).

    ``fg`` is a plate-resolution mask, ``shirt`` the shirt's box in full-resolution
    pixels. The feet are the runs of columns whose lowest blob pixel lies in the
    blob's lowest tenth; the two lowest runs count (a foot hidden behind the other
    leaves one). With ``known`` (the pixels a :class:`.plate.RoomPlate` has learned,
    whose ``fg`` counts unknown pixels as the player's), a foot counts only where
    its lowest pixels are known (the room there was seen, so the foot is *seen* to
    differ from it) and the pixel below each is known room: the foot's edge is
    observed, not the edge of what the plate has not learned yet (the silhouette
    grown around a still player, which read the feet 30-60 cm too near). Nothing
    is returned when the shirt's box holds little foreground
    (the plate does not fit the scene), when the blob reaches the image's lower edge
    (feet out of view) or when nothing of it lies below the shirt (no legs).
    """
    s = downscale
    h, w = fg.shape
    x0, y0, x1, y1 = (int(c // s) for c in shirt)
    x0, x1 = max(x0, 0), min(x1, w)
    y0, y1 = max(y0, 0), min(y1, h)
    if x1 - x0 < 2 or y1 - y0 < 2 or fg[y0:y1, x0:x1].mean() < 0.3:
        return ()
    bw = x1 - x0
    rx0, rx1 = max(0, x0 - bw), min(w, x1 + bw)
    band = np.ascontiguousarray(fg[y0:, rx0:rx1]).astype(np.uint8)
    _, labels = cv2.connectedComponents(cv2.dilate(band, _JOIN), connectivity=8)
    inside = labels[: y1 - y0, x0 - rx0: x1 - rx0]
    ids = np.unique(inside[(inside > 0) & (band[: y1 - y0, x0 - rx0: x1 - rx0] > 0)])
    if not len(ids):
        return ()
    body = np.isin(labels, ids) & (band > 0)
    rows = np.nonzero(body.sum(axis=1) >= 2)[0]
    if not len(rows):
        return ()
    bottom = int(rows.max())
    if y0 + bottom >= h - 2 or bottom < (y1 - y0):
        return ()  # feet below the image, or no legs below the shirt
    # lowest blob pixel of every column (-1: empty column)
    any_px = body.any(axis=0)
    lowest = np.where(any_px, body.shape[0] - 1 - np.argmax(body[::-1], axis=0), -1)
    foot_cols = lowest >= bottom - max(2, int(0.1 * bottom))
    runs: list[tuple[int, int]] = []
    for x in np.nonzero(foot_cols)[0]:
        if runs and x - runs[-1][1] <= 2:
            runs[-1] = (runs[-1][0], int(x))
        else:
            runs.append((int(x), int(x)))
    runs.sort(key=lambda r: -int(lowest[r[0]: r[1] + 1].max()))
    out = []
    for a, b in runs[:2]:
        v = int(lowest[a: b + 1].max())
        if known is not None:
            xs = np.arange(a, b + 1)
            ys = y0 + lowest[xs]
            below = np.minimum(ys + 1, h - 1)
            seen = known[ys, rx0 + xs] & known[below, rx0 + xs] & ~fg[below, rx0 + xs]
            if (ys + 1 >= h).any() or seen.mean() < 0.5:
                continue
        out.append(FeetPoint((rx0 + 0.5 * (a + b) + 0.5) * s, (y0 + v + 1.0) * s))
    return tuple(out)


def floor_depth(camera: Camera, feet: FeetPoint) -> float | None:
    """Depth along ``camera``'s axis where the ray through ``feet`` meets the floor y = 0.

    None when the ray does not go down to the floor in front of the camera.
    """
    ray_cam = np.linalg.solve(camera.K, np.array([feet.u, feet.v, 1.0]))
    ray_world = camera.R.T @ ray_cam
    center = camera.center
    if ray_world[1] >= -1e-6 or center[1] <= 0.0:
        return None
    s = -center[1] / ray_world[1]  # ray_cam has z = 1, so s is the depth
    return float(s) if s > 0.3 else None


class FloorWatch:
    """One camera's floor cue across frames: its plate, and each frame's feet on demand.

    Per frame: :meth:`start` with the image, then :meth:`no_shirt` or
    :meth:`shirt_at`; :meth:`feet` finds the feet only when asked (the tracker asks
    when one camera alone sees the shirt), so a second camera costs only the plate.
    """

    def __init__(self, plate: BackgroundPlate | None = None) -> None:
        self.plate = plate or BackgroundPlate()
        self.seen_shirt = False
        """Whether the shirt was found since the last reset (the plate then stops
        learning the whole frame)."""
        self._small: NDArray[np.float32] | None = None
        self._shirt: Box | None = None
        self._feet: tuple[FeetPoint, ...] | None = None
        self._fg: NDArray[np.bool_] | None = None
        self._fg_done = False
        self.room: RoomPlate | None = None
        """The room learned from what the player uncovers: the feet's source while
        the plate has seen no empty room."""

    def start(self, image: NDArray[np.uint8], reduced: bool = False) -> None:
        """A new frame (undistorted RGB, full resolution, or already at the plate's
        resolution when ``reduced``)."""
        self._small = self.plate.small(image, reduced)
        self._shirt = None
        self._feet = None
        self._fg = None
        self._fg_done = False

    def no_shirt(self) -> None:
        """A frame before any pose was reported (whether or not a shirt-like region
        was found in it): until the first shirt is confirmed, the plate learns it."""
        if self._small is not None and not self.seen_shirt:
            self.plate.learn(self._small)

    def shirt_at(self, shirt: Box, confirmed: bool = True) -> None:
        """The shirt's box (full-resolution px) in this frame; the plate moves on around it.

        ``confirmed``: whether the tracker has reported a pose yet. Until it has,
        a shirt-like region may be clutter of the room (clothes or a poster in
        shirt colors), and the plate goes on learning the whole frame (the
        tracker calls :meth:`no_shirt` on every such frame).
        """
        self._shirt = shirt
        if not confirmed and not self.seen_shirt:
            return  # the plate learned the frame (:meth:`no_shirt`)
        self.seen_shirt = True
        if self._small is not None:
            self.plate.update_around(self._small, self._region_small())

    def _region_small(self) -> Box:
        assert self._small is not None and self._shirt is not None
        d = self.plate.downscale
        h, w = self._small.shape[:2]
        x0, y0, x1, y1 = person_region(self._shirt, w * d, h * d)
        return (x0 // d, y0 // d, -(-x1 // d), -(-y1 // d))

    def foreground(self) -> NDArray[np.bool_] | None:
        """This frame's foreground around the person (plate resolution), computed once
        per frame on demand; None without a plate or a shirt."""
        if not self._fg_done:
            self._fg_done = True
            if self._small is not None and self._shirt is not None:
                self._fg = self.plate.foreground(self._small, self._region_small())
        return self._fg

    def crop_foreground(self, box: Box, size: tuple[int, int]) -> NDArray[np.bool_] | None:
        """The plate's foreground inside ``box`` (full-resolution px), resized to ``size``
        (width, height) of the working crop; None before the plate is ready.

        Unlike MOG2's mask, the plate never learns the player: a player who stands
        still stays foreground, so the mask can be trusted right next to the shirt.
        """
        if self._small is None or not self.plate.ready:
            return None
        d = self.plate.downscale
        h, w = self._small.shape[:2]
        x0, y0, x1, y1 = (max(box[0] // d, 0), max(box[1] // d, 0),
                          min(-(-box[2] // d), w), min(-(-box[3] // d), h))
        if x1 - x0 < 2 or y1 - y0 < 2:
            return None
        fg = self.plate.foreground(self._small, (x0, y0, x1, y1))
        if fg is None:
            return None
        # one plate pixel back around the outline, which the plate's opening trims
        sub = cv2.dilate(fg[y0:y1, x0:x1].astype(np.uint8), np.ones((3, 3), np.uint8))
        return np.asarray(cv2.resize(sub, size, interpolation=cv2.INTER_NEAREST), bool)

    def feet(self) -> tuple[FeetPoint, ...]:
        """This frame's feet (see :func:`feet_points`); empty without a plate or shirt."""
        if self._feet is None:
            self._feet = ()
            fg = self.foreground()
            known = None
            if fg is None and self.room is not None and self._shirt is not None:
                fg, known = self.room.foreground(), self.room.known
            if fg is not None and self._shirt is not None:
                self._feet = feet_points(fg, self._shirt, self.plate.downscale, known)
        return self._feet

    @property
    def last_feet(self) -> tuple[FeetPoint, ...]:
        """The feet found this frame, without searching for them (for overlays)."""
        return self._feet or ()
