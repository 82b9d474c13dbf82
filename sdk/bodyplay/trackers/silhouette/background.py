"""Background subtraction on intensity-normalized colour with per-pixel Gaussians.

The paper (section 2.2): colour values normalized by their intensity, one Gaussian
per pixel, foreground where the Mahalanobis distance exceeds a threshold, an
adaptive model for slow changes. Here each pixel holds the mean and variance of
three channels, the chromaticities r = R/(R+G+B), g = G/(R+G+B) and the intensity
(weighted down, so that shadows and light changes matter less than hue).

The player is usually in view from the first frame, so there is no empty room to
learn from. The model is a running one:

* every pixel starts *unknown*, its mean the first frame's value;
* a pixel that has stayed still for ``learn_after`` frames and is not where the
  player is (the tracker passes its estimated body, dilated, as ``protect``;
  before the first estimate, the neighbourhood of anything that moved) is learned:
  its mean becomes the current value and it becomes *known* -- this is how the
  pixels the player uncovers get learned, and how the first frame's copy of the
  player (a "ghost") is forgotten;
* an unknown pixel that differed from its model and shows the model's value again,
  away from the player, is known (something passed in front of it);
* known background pixels adapt with rate ``rate`` (slow light changes); a known
  pixel that differs from its model is something in front of the background (the
  player standing still, most often) and is learned only after ``relearn_after``
  still frames (a moved chair, a light switched on), once the estimate has stayed
  off it for ``learn_away`` frames in a row (the estimate lags a step: a foot held
  still under it was learned the frame the step moved it away).

Each frame gives three sets: foreground (differs from its model), known background
and unknown (still, never confirmed). The distance of :mod:`.distance` treats
unknown pixels as "don't care". An empty-room start simply makes every pixel
known after ``learn_after`` frames.

The first frame is segmented too (``bootstrap``): GrabCut (OpenCV) against the
image's edges gives a coarse, generous guess of the player (:func:`first_guess`).
What lies outside it, a few pixels away (``guess_margin``), is the background and
known from the first frame. Inside it the pixels stay unknown until they are
resolved: every ``resolve_every`` frames, GrabCut runs again on the crop around
the unknown pixels, seeded with what the model now knows -- the known background
that shows no change is background, what differs from the known background is
the player (the limbs that moved out of the guess), the unknown pixels are
"probably" either (the previous answer). Its answer labels the unknown pixels:

* still ones it calls the player are foreground (a torso that has not moved since
  the first frame) and are not learned;
* still ones it calls background are background (not "don't care": a larger
  template would otherwise cover them for free);
* differing ones it calls background are the first frame's copy of the player
  that has moved away (a ghost) and are not foreground until something moves
  there.

Once the tracker passes its estimate (``protect``), the still unknown pixels more
than ``resolve_outside`` pixels beyond it are seeded as sure background: furniture
beside the player in the colours of the clothes, which the first guess took along,
then teaches GrabCut what is not the player (before, only ``guess_expiry`` frames
off the estimate released it).

Without a guess (``bootstrap`` off, or nothing found) or before the first
resolution, unknown pixels are "don't care" to the distance and the guess only
helps to find the floor point.

Without a guess nothing held the player's still parts from being learned before
the tracker's first pose but the neighbourhood of what moved this frame: a player
who moves only the arms lost the still legs and torso to the background by the
12th frame. ``hold_below`` keeps, until the first pose, every unknown pixel under
and beside what has moved since the start (each column from its highest moved
pixel down to the image's bottom, widened: :attr:`BackgroundModel.held`) from
being learned, for at most ``hold_guess`` frames, like the guess; they stay "don't
care", and the tracker finds how far the player stands from the shape of what
moves (:mod:`.shapestart`). Once it knows, it makes the first guess again inside
the box a person standing there can fill (:meth:`BackgroundModel.guess_in`,
:func:`box_guess`: GrabCut on the first frame with the rest of the image as sure
background, or the box itself when GrabCut finds no figure in it either), and
that guess is resolved like a first guess.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba
import numpy as np
from numpy.typing import NDArray

from bodyplay.errors import CaptureError
from bodyplay.trackers.silhouette.options import BackgroundOptions

__all__ = ["BackgroundModel", "Silhouette", "normalized_color"]


@numba.njit(cache=True, nogil=True)
def _normalized(image, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    h, w = image.shape[:2]
    off = np.float32(30.0)
    one = np.float32(1.0)
    third = np.float32(1.0 / 765.0)
    for i in range(h):
        for j in range(w):
            r = np.float32(image[i, j, 0])
            g = np.float32(image[i, j, 1])
            s = r + g + np.float32(image[i, j, 2])
            inv = one / (s + off)
            out[i, j, 0] = r * inv
            out[i, j, 1] = g * inv
            out[i, j, 2] = s * third


def normalized_color(image: NDArray[np.uint8]) -> NDArray[np.float32]:
    """(H, W, 3) RGB -> (H, W, 3) chromaticities r, g and intensity in 0..1: r = R / (R +
    G + B + 30), g likewise (the offset keeps dark pixels' chromaticity from
    exploding), intensity (R + G + B) / 765; float32 throughout, one pass (numba)."""
    img = np.ascontiguousarray(image, np.uint8)
    out = np.empty(img.shape, np.float32)
    _normalized(img, out)
    return out


@dataclass(frozen=True, eq=False)
class Silhouette:
    """One frame's segmentation at the model's working resolution.

    ``foreground``: uint8 0/1 after clean-up; ``unknown``: uint8 0/1 pixels never
    confirmed as background that show nothing new; ``scale``: working size over
    the camera image size; ``region``: the foreground plus the first frame's guess
    of the player not learned yet (where the body may be: used to find the floor
    point).
    """

    foreground: NDArray[np.uint8]
    unknown: NDArray[np.uint8]
    scale: float
    region: NDArray[np.uint8] | None = None

    @property
    def area(self) -> float:
        """Share of the image that is foreground."""
        return float(self.foreground.mean())


@numba.njit(cache=True, nogil=True)
def _classify(x, mean, var, prev, still, wi, thr2, move2, differs, moved):  # type: ignore[no-untyped-def]  # pragma: no cover
    h, w = still.shape
    for i in range(h):
        for j in range(w):
            d2 = 0.0
            m2 = 0.0
            for c in range(3):
                wc = wi if c == 2 else 1.0
                e = x[i, j, c] - mean[i, j, c]
                d2 += wc * e * e / var[i, j, c]
                f = x[i, j, c] - prev[i, j, c]
                m2 += wc * f * f
            differs[i, j] = 1 if d2 > thr2 else 0
            if m2 > move2:
                moved[i, j] = 1
                still[i, j] = 0
            else:
                still[i, j] += 1


@numba.njit(cache=True, nogil=True)
def _learn(x, mean, var, still, known, differs, was_diff, protect, learn_after,  # type: ignore[no-untyped-def]  # pragma: no cover
           relearn_after, rate, var0, away, learn_away):
    h, w = still.shape
    for i in range(h):
        for j in range(w):
            if differs[i, j]:
                was_diff[i, j] = True
            if protect[i, j]:
                away[i, j] = 0
                continue
            if away[i, j] < 1_000_000:
                away[i, j] += 1
            if not known[i, j] and not differs[i, j] and was_diff[i, j]:
                known[i, j] = True  # back to its value after something passed: background
            if (still[i, j] >= learn_after and not known[i, j]) or (
                    differs[i, j] and still[i, j] >= relearn_after
                    and away[i, j] >= learn_away):  # away from the player, not just now
                for c in range(3):
                    mean[i, j, c] = x[i, j, c]
                    var[i, j, c] = var0
                known[i, j] = True
            elif known[i, j] and not differs[i, j]:
                for c in range(3):
                    e = x[i, j, c] - mean[i, j, c]
                    mean[i, j, c] += rate * e
                    var[i, j, c] = max((1 - rate) * var[i, j, c] + rate * e * e, var0)


def _small(image: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """The first guess's working copy: short side 120 pixels."""
    h, w = image.shape[:2]
    s = min(1.0, 120.0 / min(h, w))
    return np.asarray(cv2.resize(image, (max(8, int(w * s)), max(8, int(h * s))),
                                 interpolation=cv2.INTER_AREA), np.uint8)


def first_guess(image: NDArray[np.uint8], size: tuple[int, int]) -> NDArray[np.bool_]:
    """Where the player probably is in the first frame, before anything has moved:
    GrabCut (OpenCV) with everything but the image's sides and top as the unknown
    region (a player stands on the floor, away from the edges), run on a small copy;
    returned at ``size`` (width, height)."""
    small = _small(image)
    sh, sw = small.shape[:2]
    mx, my, mb = int(0.08 * sw), int(0.04 * sh), int(0.02 * sh)
    mask = np.zeros((sh, sw), np.uint8)
    guess = _grabcut(small, mask, (mx, my, sw - 2 * mx, sh - my - mb), cv2.GC_INIT_WITH_RECT)
    if guess is None or guess.mean() > 0.5:  # no figure against a ground: no guess
        return np.zeros(size[::-1], bool)
    return np.asarray(cv2.resize(guess, size, interpolation=cv2.INTER_NEAREST), bool)


def _grabcut(small: NDArray[np.uint8], mask: NDArray[np.uint8], rect: tuple[int, int, int, int],
             mode: int) -> NDArray[np.uint8] | None:
    """OpenCV's GrabCut (3 iterations) on the RGB ``small`` from ``mask`` / ``rect``;
    the figure (1) and ground (0), or None when OpenCV gives up."""
    bgd = np.zeros((1, 65), np.float64)
    fgd = np.zeros((1, 65), np.float64)
    cv2.setRNGSeed(0)  # GrabCut's clustering draws from OpenCV's RNG: same frame, same guess
    try:
        cv2.grabCut(cv2.cvtColor(small, cv2.COLOR_RGB2BGR), mask, rect, bgd, fgd, 3, mode)
    except cv2.error:
        return None
    return ((mask == cv2.GC_FGD) | (mask == cv2.GC_PR_FGD)).astype(np.uint8)


def box_guess(small: NDArray[np.uint8], box: NDArray[np.bool_],
              background: NDArray[np.bool_] | None = None) -> NDArray[np.bool_]:
    """The first guess again, inside ``box`` only: GrabCut (OpenCV) on ``small`` (the
    first frame's 120-pixel copy) with everything outside ``box`` (working
    resolution, where a standing person at the tracker's floor point can be) as sure
    background and ``background`` (pixels learned as the room since) as probable
    background; returned at ``box``'s size, empty when GrabCut finds no figure
    (more than half the box)."""
    sh, sw = small.shape[:2]
    size = box.shape[::-1]
    inside = cv2.resize(box.astype(np.uint8), (sw, sh), interpolation=cv2.INTER_NEAREST) > 0
    mask = np.full((sh, sw), cv2.GC_BGD, np.uint8)
    mask[inside] = cv2.GC_PR_FGD
    if background is not None:
        bg = cv2.resize(background.astype(np.uint8), (sw, sh), interpolation=cv2.INTER_AREA)
        mask[inside & (bg > 0)] = cv2.GC_PR_BGD
    if not inside.any() or inside.all():
        return np.zeros(box.shape, bool)
    guess = _grabcut(small, mask, (0, 0, 1, 1), cv2.GC_INIT_WITH_MASK)
    if guess is None or guess.sum() > 0.5 * inside.sum():
        return np.zeros(box.shape, bool)
    return np.asarray(cv2.resize(guess, size, interpolation=cv2.INTER_NEAREST), bool)


def _below(stirred: NDArray[np.bool_], reach: int) -> NDArray[np.bool_]:
    """The pixels under and beside what has moved: in each column, from its highest
    moved pixel down to the image's bottom, widened by ``reach`` pixels either side
    (a player who moves only the arms stands on still legs under them)."""
    cols = stirred.any(axis=0)
    out = np.zeros(stirred.shape, bool)
    if not cols.any():
        return out
    top = np.where(cols, stirred.argmax(axis=0), stirred.shape[0])
    # the highest moved row of the columns within reach (a sliding minimum)
    pad = np.pad(top, reach, mode="constant", constant_values=stirred.shape[0])
    near = np.lib.stride_tricks.sliding_window_view(pad, 2 * reach + 1).min(axis=1)
    out[:] = np.arange(stirred.shape[0])[:, None] >= near[None, :]
    return out


class BackgroundModel:
    """The running per-pixel Gaussian background model (see the module docstring).

    ``reguessed``: whether :meth:`guess_in` has been asked since the start (it is
    made once per start)."""

    def __init__(self, options: BackgroundOptions | None = None) -> None:
        self.options = options or BackgroundOptions()
        self.reset()

    def reset(self) -> None:
        """Forget everything learned."""
        self._mean: NDArray[np.float32] | None = None
        self._var: NDArray[np.float32] | None = None
        self._prev: NDArray[np.float32] | None = None
        self._still: NDArray[np.int32] | None = None
        self.known: NDArray[np.bool_] | None = None
        self.occupied: NDArray[np.bool_] = np.zeros((0, 0), bool)
        self.player: NDArray[np.bool_] | None = None
        self._ghost: NDArray[np.bool_] = np.zeros((0, 0), bool)
        self._away: NDArray[np.int32] = np.zeros((0, 0), np.int32)
        self._off: NDArray[np.int32] = np.zeros((0, 0), np.int32)
        self._resolving = False
        self._frames = 0
        self._stirred: NDArray[np.bool_] = np.zeros((0, 0), bool)
        self.held: NDArray[np.bool_] | None = None
        self.motion = 0.0
        self.moving: NDArray[np.bool_] = np.zeros((0, 0), bool)
        self._x: NDArray[np.float32] | None = None
        self._first: NDArray[np.float32] | None = None
        self._learned_at: NDArray[np.int32] = np.zeros((0, 0), np.int32)
        self._small: NDArray[np.uint8] | None = None
        self.reguessed = False
        self._dropped = False

    @property
    def dropped(self) -> bool:
        """Whether the first frame's guess was dropped (:meth:`drop_guess`) since the
        start."""
        return self._dropped

    @property
    def frames(self) -> int:
        """Frames seen since the start (or the last :meth:`reset`)."""
        return self._frames

    @property
    def guessing(self) -> bool:
        """Whether the first frame's guess of the player is being resolved (there was
        one and it was not dropped)."""
        return self._resolving

    def drop_guess(self) -> None:
        """The tracker found the first frame's guess wrong (it took a treadmill or a
        sofa under the player for the body): stop resolving it; its unknown pixels
        go back to "don't care" and are learned like any unknown pixel."""
        self._resolving = False
        self.player = None
        self._ghost = np.zeros((0, 0), bool)
        self._dropped = True

    def release(self, mask: NDArray[np.bool_], since: int | None = None) -> None:
        """The tracker found that what it followed there is not the player (it stood
        still while the player moved elsewhere, :mod:`.stilltrack`): the pixels of
        ``mask`` (working resolution) that did not move this frame are learned as
        background now, with this frame's values, and stop being the resolved player
        or a ghost. With ``since`` (a frame count, :attr:`frames`), the pixels of the
        first frame's guess learned as background from that frame on, outside
        ``mask``, are unknown again (the wrong estimate made them sure background in
        the resolution: the player's still body, beside it) and resolved anew."""
        if self._x is None or self.known is None or self._mean is None or self._var is None:
            return
        if mask.shape != self.known.shape:
            raise CaptureError(f"release mask is {mask.shape[::-1]}, the model works at "
                               f"{self.known.shape[::-1]}")
        m = mask & ~self.moving
        self._mean[m] = self._x[m]
        self._var[m] = self.options.min_std ** 2
        self.known |= m
        if self.player is not None:
            self.player &= ~m
        if self._ghost.shape == m.shape:
            self._ghost &= ~m
        self.occupied = self.occupied & ~m
        if since is None or not self._resolving or self._first is None:
            return
        back = (self._learned_at >= since) & ~mask
        self._mean[back] = self._first[back]
        self._var[back] = self.options.min_std ** 2
        self.known &= ~back
        self._was_diff &= ~back
        self._learned_at[back] = -1
        if self.player is not None:
            self.player |= back  # probably the player, as in the first guess

    def guess_in(self, box: NDArray[np.bool_], grabcut: bool = True) -> bool:
        """The first frame's guess of the player made again, inside ``box`` (working
        resolution: where a person standing at the tracker's floor point can be),
        when the first one gave nothing or was dropped (:func:`box_guess`; with
        ``grabcut`` False, the box itself: a guess that was dropped had taken the
        room for the figure, and GrabCut on the same first frame would take it
        again). Pixels learned since the start inside the new guess are unknown
        again (their first values back), those outside it known; the guess is then
        resolved like a first guess, by what has moved since. Once per start;
        returns whether there is a new guess."""
        if (self.reguessed or self._resolving or self._small is None or self._first is None
                or self.known is None or self._mean is None or self._var is None
                or not self.options.resolve_every):
            return False
        if box.shape != self.known.shape:
            raise CaptureError(f"guess box is {box.shape[::-1]}, the model works at "
                               f"{self.known.shape[::-1]}")
        self.reguessed = True
        guess = box_guess(self._small, box, self.known) if grabcut else box.copy()
        if not guess.any():  # no figure in the box either: the box itself, resolved later
            guess = box.copy()
        if not guess.any():
            return False
        r = self.options.guess_margin
        k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1,) * 2)
        near = cv2.dilate(guess.astype(np.uint8), k) > 0
        back = near & self.known  # learned since the start: the player's still body
        self._mean[back] = self._first[back]
        self._var[back] = self.options.min_std ** 2
        self._was_diff &= ~near
        self.known = ~near
        self.occupied = guess
        self._learned_at[:] = -1
        self._stirred[:] = False
        self.held = None
        self.player = None
        self._ghost = np.zeros((0, 0), bool)
        self._resolving = True
        return True

    def _prepare(self, image: NDArray[np.uint8]) -> NDArray[np.float32]:
        if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
            raise CaptureError(f"background model needs (H, W, 3) uint8 RGB frames, got "
                               f"{image.shape} {image.dtype}")
        h, w = image.shape[:2]
        s = min(1.0, self.options.working_size / min(h, w))
        if s != 1.0:
            image = np.asarray(cv2.resize(image, (max(1, int(round(w * s))),
                                                  max(1, int(round(h * s)))),
                                          interpolation=cv2.INTER_AREA), np.uint8)
        return normalized_color(image)

    def apply(self, image: NDArray[np.uint8],
              protect: NDArray[np.bool_] | None = None) -> Silhouette:
        """Segment one frame and update the model.

        ``protect`` (working resolution, True where the player is believed to be)
        keeps those pixels from being learned; None before the tracker has an
        estimate.
        """
        o = self.options
        x = self._prepare(image)
        self._frames += 1
        if self._mean is None or self._mean.shape != x.shape:
            self._mean = x.copy()
            self._var = np.full(x.shape, o.min_std**2, np.float32)
            self._prev = x.copy()
            self._still = np.zeros(x.shape[:2], np.int32)
            self.known = np.zeros(x.shape[:2], bool)
            self.occupied = (first_guess(image, x.shape[1::-1]) if o.bootstrap
                             else np.zeros(x.shape[:2], bool))
            self._was_diff = np.zeros(x.shape[:2], bool)
            self._stirred = np.zeros(x.shape[:2], bool)
            self.player = None
            self._first = x.copy()
            self._small = _small(image)
            self._learned_at = np.full(x.shape[:2], -1, np.int32)
            # without a first guess there is nothing to resolve: unknown stays "don't care"
            self._resolving = bool(o.resolve_every and self.occupied.any())
            if self._resolving:
                # outside the first frame's guess, what the camera sees is the background
                r = o.guess_margin
                k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1,) * 2)
                self.known = ~(cv2.dilate(self.occupied.astype(np.uint8), k) > 0)
        assert self._var is not None and self._prev is not None and self._still is not None
        assert self.known is not None
        differs = np.zeros(x.shape[:2], np.uint8)
        moved = np.zeros(x.shape[:2], np.uint8)
        _classify(x, self._mean, self._var, self._prev, self._still,
                  np.float32(o.intensity_weight**2), np.float32(o.threshold**2),
                  np.float32((2.5 * o.min_std) ** 2 * 3.0), differs, moved)
        self._prev = x
        # what moved this frame, single noisy pixels dropped
        stir = cv2.morphologyEx(moved, cv2.MORPH_OPEN, np.ones((3, 3), np.uint8)) > 0
        self.motion = float(stir.mean())
        self.moving = stir
        self._x = x
        if (self._resolving and self._frames % o.resolve_every == 0
                and not self.known.all()):
            self._resolve(image, x.shape[1::-1], differs,
                          None if o.resolve_outside is None else protect)
        shown: NDArray[np.uint8] = differs
        if self.player is not None:
            # unknown pixels: the still ones the colours say are the player count, and
            # the differing ones they say are background (the first frame's copy of
            # the player, a ghost) do not, until something moves there
            self._ghost &= ~moved.astype(bool)
            shown = (((differs > 0) & ~(self._ghost & ~self.known))
                     | (self.player & ~self.known)).astype(np.uint8)
        fg = self._clean(shown)
        given = protect is not None
        if protect is None:
            r = max(3, int(0.1 * x.shape[0]))
            protect = cv2.dilate(moved,
                                 cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1,) * 2)
                                 ) > 0
            if self._frames < o.hold_guess:  # the first guess of the player waits a while
                protect |= self.occupied
            if o.hold_below and self._frames < o.hold_guess:  # so does the still body
                self._stirred |= stir
                self.held = _below(self._stirred, r) & ~self.known
                protect |= self.held
            else:
                self.held = None
        else:
            if protect.shape != fg.shape:
                raise CaptureError(f"protect mask is {protect.shape[::-1]}, the model works "
                                   f"at {fg.shape[::-1]}")
            self._stirred[:] = False  # the tracker has the player: start over when lost
            self.held = None
        if self.player is not None:
            if given and o.guess_expiry:
                self._expire(protect)
            protect = protect | (self.player & ~self.known)
        if self._off.shape != protect.shape:
            self._off = np.zeros(protect.shape, np.int32)
        before = self.known & self.occupied
        _learn(x, self._mean, self._var, self._still, self.known, differs, self._was_diff,
               np.ascontiguousarray(protect), o.learn_after, o.relearn_after, np.float32(o.rate),
               np.float32(o.min_std**2), self._off, o.learn_away)
        self._learned_at[self.known & self.occupied & ~before] = self._frames
        unknown = (~self.known & (fg == 0)).astype(np.uint8)
        if self.player is not None:  # resolved: the rest of the unknown is background
            unknown[:] = 0
        region = fg | (self.occupied & ~self.known).astype(np.uint8)
        if self.held is not None:  # where the player has moved (the feet, once) counts too
            region |= (self._stirred & ~self.known).astype(np.uint8)
        return Silhouette(fg, unknown, x.shape[1] / image.shape[1], region)

    def _expire(self, protect: NDArray[np.bool_]) -> None:
        """Still pixels resolved as the player that have stayed away from the
        tracker's estimate (``protect``) for ``guess_expiry`` frames are not the
        player (cabinets behind him that GrabCut took along): they stop being
        protected and are learned as background."""
        assert self.player is not None and self.known is not None
        if self._away.shape != protect.shape:
            self._away = np.zeros(protect.shape, np.int32)
        away = self.player & ~self.known & ~protect
        self._away[away] += 1
        self._away[~away] = 0
        self.player &= self._away < self.options.guess_expiry

    def _resolve(self, image: NDArray[np.uint8], size: tuple[int, int],
                 differs: NDArray[np.uint8],
                 estimate: NDArray[np.bool_] | None = None) -> None:
        """Which unknown pixels are the player: GrabCut (OpenCV) seeded with the known
        background that shows no change (background) and what differs from it (the
        player over a learned background), on the crop around the unknown pixels;
        sets ``player`` (the unknown pixels it calls the player) and the ghosts."""
        assert self.known is not None
        unknown = ~self.known
        fg_known = self.known & (differs > 0)
        if not (differs > 0).any():
            return
        ys, xs = np.nonzero(unknown | fg_known)
        m = 12
        y0, y1 = max(0, ys.min() - m), min(size[1], ys.max() + m + 1)
        x0, x1 = max(0, xs.min() - m), min(size[0], xs.max() + m + 1)
        if image.shape[1] != size[0]:
            image = np.asarray(cv2.resize(image, size, interpolation=cv2.INTER_AREA), np.uint8)
        crop = np.ascontiguousarray(image[y0:y1, x0:x1])
        mask: NDArray[np.uint8] = np.full((y1 - y0, x1 - x0), cv2.GC_BGD, np.uint8)
        un = unknown[y0:y1, x0:x1]
        prev = self.player[y0:y1, x0:x1] if self.player is not None else np.ones_like(un)
        mask[un] = cv2.GC_PR_BGD
        mask[un & prev] = cv2.GC_PR_FGD
        mask[un & (differs[y0:y1, x0:x1] > 0)] = cv2.GC_PR_FGD
        mask[fg_known[y0:y1, x0:x1]] = cv2.GC_FGD
        reach = self.options.resolve_outside
        if estimate is not None and reach is not None and estimate.shape == unknown.shape:
            # where the tracker's estimate (dilated, and ``reach`` pixels more) does not
            # reach, a still unknown pixel is not the player: sure background (the cat's
            # eye or the cabinet beside the player; its colours then teach GrabCut what
            # is not the clothes)
            near = estimate.astype(np.uint8)
            if reach:
                near = np.asarray(cv2.dilate(near, cv2.getStructuringElement(
                    cv2.MORPH_ELLIPSE, (2 * reach + 1,) * 2)), np.uint8)
            mask[un & (near[y0:y1, x0:x1] == 0) & (differs[y0:y1, x0:x1] == 0)] = cv2.GC_BGD
        bgd = np.zeros((1, 65), np.float64)
        fgd = np.zeros((1, 65), np.float64)
        cv2.setRNGSeed(0)
        try:
            cv2.grabCut(cv2.cvtColor(crop, cv2.COLOR_RGB2BGR), mask, (0, 0, 1, 1), bgd, fgd,
                        self.options.resolve_iterations, cv2.GC_INIT_WITH_MASK)
        except cv2.error:
            return
        player = np.zeros(size[::-1], bool)
        player[y0:y1, x0:x1] = (mask == cv2.GC_FGD) | (mask == cv2.GC_PR_FGD)
        self.player = player & unknown
        self._ghost = unknown & (differs > 0) & ~player

    def _clean(self, fg: NDArray[np.uint8]) -> NDArray[np.uint8]:
        o = self.options
        if o.open_px:
            k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * o.open_px + 1,) * 2)
            fg = np.asarray(cv2.morphologyEx(fg, cv2.MORPH_OPEN, k), np.uint8)
        if o.close_px:
            k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * o.close_px + 1,) * 2)
            fg = np.asarray(cv2.morphologyEx(fg, cv2.MORPH_CLOSE, k), np.uint8)
        n, lab, stats, _ = cv2.connectedComponentsWithStats(fg, connectivity=8)
        if n <= 1:
            return fg
        keep = stats[:, cv2.CC_STAT_AREA] >= o.min_area * fg.size
        keep[0] = False
        return keep[lab].astype(np.uint8)
