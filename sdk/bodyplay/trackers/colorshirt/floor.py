"""Where the feet meet the floor: a depth cue for one camera (beyond the paper).

The feet stand on the floor (world ``y = 0``), so the ray through the person's
lowest pixel meets the floor at the person's distance (:func:`floor_reading`). The
feet need a mask that keeps still legs, which MOG2 absorbs: :class:`BackgroundPlate`
learns the empty room and then follows it only away from the person, with one gain
per channel for the light. Without empty-room frames the feet come from the room plate
(:class:`.plate.RoomPlate`), where it knows the floor under them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.locate import reduce_box, reduce_image
from bodyplay.trackers.colorshirt.plate import RoomPlate

if TYPE_CHECKING:
    from bodyplay.trackers.colorshirt.options import ColorShirtOptions
    from bodyplay.trackers.colorshirt.views import CameraState, CameraView

__all__ = ["BackgroundPlate", "FeetPoint", "FloorReading", "FloorWatch", "feet_points",
           "floor_depth", "floor_reading", "person_region"]

Box = tuple[int, int, int, int]

_JOIN = np.ones((5, 5), np.uint8)
"""The blob is labelled on the mask dilated by this, so that a foot the plate's
threshold splits stays one; its lowest points are read on the undilated mask."""


class BackgroundPlate:
    """The empty room as seen by one camera, at reduced resolution (a running mean).

    While nobody is in view (:meth:`learn`) every pixel follows the frames (ready
    after ``min_frames``); while a person is tracked (:meth:`update_around`) only
    pixels outside the person's region follow, slowly. ``threshold``: summed
    absolute R, G, B difference that counts as foreground in a room at least as
    bright as ``contrast_level`` (dimmer rooms shrink it in proportion, to 30%).
    """

    def __init__(self, downscale: int = 2, min_frames: int = 8, rate: float = 0.02,
                 threshold: float = 40.0, contrast_level: float = 330.0) -> None:
        self.downscale = max(1, int(downscale))
        self.min_frames = int(min_frames)
        self.rate = float(rate)
        self.threshold = float(threshold)
        self.contrast_level = float(contrast_level)
        self._mean: NDArray[np.float32] | None = None
        self._frames = 0

    @property
    def ready(self) -> bool:
        """Whether enough empty-room frames were seen to trust the plate."""
        return self._frames >= self.min_frames

    def small(self, image: NDArray[np.uint8], reduced: bool = False) -> NDArray[np.float32]:
        """``image`` at the plate's resolution, as float32 (``reduced``: it already is)."""
        return (image if reduced else reduce_image(image, self.downscale)).astype(np.float32)

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
        """A tracked frame: the whole plate follows the light's change (one gain per
        channel, measured outside ``person``, plate pixels, so that the room behind
        the person keeps step), then pixels outside ``person`` follow the frame slowly.
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
        """Foreground mask of ``small`` within ``person`` (False elsewhere), the plate
        scaled by the light's change outside ``person``; None before it is ready."""
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
    pixels. The feet are the two lowest runs of columns whose lowest blob pixel lies
    in the blob's lowest tenth. With ``known`` (a room plate's learned pixels) a foot
    counts only where its lowest pixels and the pixels below them are known room.
    None when the shirt's box holds little foreground, the blob reaches the image's
    lower edge, or nothing of it lies below the shirt.
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
    :meth:`shirt_at`; :meth:`feet` finds the feet only when asked.
    """

    def __init__(self, plate: BackgroundPlate | None = None) -> None:
        self.plate = plate or BackgroundPlate()
        self.seen_shirt = False
        """Whether the shirt was confirmed (the plate then stops learning it)."""
        self._small: NDArray[np.float32] | None = None
        self._shirt: Box | None = None
        self._feet: tuple[FeetPoint, ...] | None = None
        self._fg: NDArray[np.bool_] | None = None
        self._fg_done = False
        self.room: RoomPlate | None = None
        """The feet's source while the plate has seen no empty room."""

    def start(self, image: NDArray[np.uint8], reduced: bool = False) -> None:
        """A new frame (undistorted RGB, full resolution, or already at the plate's
        resolution when ``reduced``)."""
        self._small = self.plate.small(image, reduced)
        self._shirt = None
        self._feet = None
        self._fg = None
        self._fg_done = False

    def no_shirt(self) -> None:
        """A frame before any pose was reported: the plate learns it."""
        if self._small is not None and not self.seen_shirt:
            self.plate.learn(self._small)

    def shirt_at(self, shirt: Box, confirmed: bool = True) -> None:
        """The shirt's box (full-resolution px) in this frame; the plate moves on
        around it once a pose was reported (``confirmed``)."""
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
        return reduce_box(person_region(self._shirt, w * d, h * d), d, w, h)

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
        (width, height) of the working crop; None before the plate is ready."""
        if self._small is None or not self.plate.ready:
            return None
        h, w = self._small.shape[:2]
        x0, y0, x1, y1 = reduce_box(box, self.plate.downscale, w, h)
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


@dataclass(frozen=True)
class FloorReading:
    """What the feet told in one frame: the root's ``depth`` along the lone camera's
    axis (m; None: no reading) and the ``stagger``, how far apart in depth the two
    feet stand (m; None unless both were found: then one image cannot say which
    foot bears the weight)."""

    stagger: float | None = None
    depth: float | None = None


def floor_reading(cameras: Sequence[Camera], states: Sequence[CameraState],
                  views: Sequence[CameraView], options: ColorShirtOptions,
                  root_height: float) -> FloorReading:
    """The root's depth that a lone camera reads from the feet: their floor points'
    mean raised by ``root_height`` (m), its depth plus ``options.floor_offset``."""
    if len(views) != 1 or not options.floor_cue:
        return FloorReading()
    cam = cameras[views[0].index]
    points, depths = [], []
    for f in states[views[0].index].floor.feet():
        z = floor_depth(cam, f)
        if z is not None:
            depths.append(z)
            ray = np.linalg.solve(cam.K, np.array([f.u, f.v, 1.0]))
            points.append(cam.R.T @ (ray * z) + cam.center)
    if not depths:
        return FloorReading()
    root = np.mean(points, axis=0) + np.array([0.0, root_height, 0.0])
    depth = float(cam.world_to_camera(root)[2]) + options.floor_offset
    return FloorReading(max(depths) - min(depths) if len(depths) > 1 else None, depth)
