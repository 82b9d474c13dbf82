"""One camera's state between frames (:class:`CameraState`) and share of a frame
(:class:`CameraView`): its white balance and classification, the classification's
clean-up and the normalized database query.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import cv2
import numba
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.shirt import NUM_COLORS, NUM_PATCHES, PATCHES, SHIRT_COLORS
from bodyplay.trackers.colorshirt.database import PoseDatabase
from bodyplay.trackers.colorshirt.floor import FloorWatch
from bodyplay.trackers.colorshirt.locate import BackgroundMask
from bodyplay.trackers.colorshirt.plate import RoomPlate
from bodyplay.trackers.colorshirt.prediction import CropWindow
from bodyplay.trackers.colorshirt.whitebalance import (
    ReferenceIlluminations,
    auto_white_balance,
    classification_score,
)

if TYPE_CHECKING:
    from bodyplay.trackers.colorshirt.colors import ColorModel
    from bodyplay.trackers.colorshirt.options import ColorShirtOptions

__all__ = ["CameraState", "CameraView", "WHITE_ID", "WHITE_PATCHES", "classify_camera",
           "clean_ids", "make_query", "nonzero_box", "prior_penalty_slope"]

_MAX_NOISE_GROWTH = 2.5
"""The noise-aware classification is kept unless it finds this many times the pixels
of the plain one (background creeping in)."""

WHITE_ID = 1 + next(c.index for c in SHIRT_COLORS if c.name == "white")
"""The class id of the shirt's white (ids are color index + 1; 0 is unclassified)."""

WHITE_PATCHES = np.isin(np.arange(NUM_PATCHES + 1),
                        [p.id for p in PATCHES if p.color == WHITE_ID - 1])
"""Per patch id (0 = background): whether the patch is white."""

_SLEEVE_IDS = np.array(sorted(
    1 + c.index for c in SHIRT_COLORS
    if all(p.bone.endswith(("_shoulder", "_elbow")) for p in PATCHES if p.color == c.index)))
"""Class ids of the colors found only on the sleeves (green, cyan, blue, purple)."""


@dataclass
class CameraState:
    """What the tracker remembers per camera between frames."""

    background: BackgroundMask
    W: NDArray[np.float64] | None = None
    references: ReferenceIlluminations = field(default_factory=ReferenceIlluminations)
    last_box: tuple[int, int, int, int] | None = None
    torso_box: tuple[int, int, int, int] | None = None
    """Image box of the torso in the last pose reported (kept foreground)."""
    last_fraction: float | None = None
    floor: FloorWatch = field(default_factory=FloorWatch)
    """The background plate and the feet on the floor."""
    gate: tuple[int, int, int, int] | None = None
    """Image box of the last reported pose's shirt, at time ``gate_t``."""
    gate_t: float = float("nan")
    room: RoomPlate = field(default_factory=RoomPlate)
    """The room learned from what the player uncovers."""
    located: bool = False
    """Whether the histogram search found a shirt in this camera this frame."""
    image: NDArray[np.uint8] | None = None
    """This frame's image, undistorted."""
    reduced: NDArray[np.uint8] | None = None
    """This frame's image at the background model's and the plates' resolution."""

    def __post_init__(self) -> None:
        self.floor.room = self.room  # the feet's source until an empty room was seen


@dataclass(eq=False)
class CameraView:
    """One camera's share of a frame: crop, classification and database match."""

    index: int
    window: CropWindow
    crop: NDArray[np.uint8]
    mask: NDArray[np.bool_] | None
    W: NDArray[np.float64]
    ids: NDArray[np.uint8]
    shirt_scale: float
    query_scale: float = 1.0
    query_offset: NDArray[np.float64] = field(default_factory=lambda: np.zeros(2))
    distance: float = 1.0
    neighbours: object | None = None
    state: CameraState | None = None
    """A start candidate's camera state (its white balance) until it is chosen."""


@numba.njit(cache=True, nogil=True)
def _blob_reach(labels: NDArray[Any], sel: NDArray[np.bool_], gap: NDArray[Any],
                n: int) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64],
                                 NDArray[np.int64]]:  # pragma: no cover - compiled
    """Per label 0..n-1, over its ``sel`` pixels: the least ``gap``, the lowest row and
    the leftmost and rightmost columns (inf, -1, width, -1 for a label without any)."""
    h, w = labels.shape
    nearest = np.full(n, np.inf)
    bottom = np.full(n, -1, np.int64)
    left = np.full(n, w, np.int64)
    right = np.full(n, -1, np.int64)
    for y in range(h):
        for x in range(w):
            if not sel[y, x]:
                continue
            b = labels[y, x]
            g = np.float64(gap[y, x])
            if g < nearest[b]:
                nearest[b] = g
            if y > bottom[b]:
                bottom[b] = y
            if x < left[b]:
                left[b] = x
            if x > right[b]:
                right[b] = x
    return nearest, bottom, left, right


def nonzero_box(mask: NDArray[Any]) -> tuple[int, int, int, int] | None:
    """``(x0, y0, x1, y1)``, the first and last column and row of a 2-D array's nonzero
    entries (None: none); the bounds of ``np.nonzero``'s, without listing them."""
    rows = np.flatnonzero(mask.any(axis=1))
    if not len(rows):
        return None
    cols = np.flatnonzero(mask.any(axis=0))
    return int(cols[0]), int(rows[0]), int(cols[-1]), int(rows[-1])


def clean_ids(ids: NDArray[np.uint8], blob_fraction: float,
              attach_fraction: float = 0.1,
              sleeve_attach: float = 0.0) -> NDArray[np.uint8]:
    """Keep the shirt-like blobs of a classification.

    Blobs are the colored (non-white) pixels, opened and grown a little. The
    largest blob of two shirt colors is the shirt; another two-colour blob is kept
    when not far smaller (``blob_fraction`` of its area) or within
    ``attach_fraction`` of the shirt's extent of it (an arm cut off by a white
    shoulder cap), a one-colour one only in a sleeve colour; a sleeve-coloured blob
    joined to the shirt through white is kept too, and one of two sleeve colours
    over the shirt within ``sleeve_attach`` of its raised upper arms (forearms over
    the head). White is kept only next to the kept blobs.
    """
    white = cv2.morphologyEx((ids == WHITE_ID).astype(np.uint8), cv2.MORPH_OPEN,
                             np.ones((2, 2), np.uint8))
    core = cv2.morphologyEx(((ids > 0) & (ids != WHITE_ID)).astype(np.uint8), cv2.MORPH_OPEN,
                            np.ones((3, 3), np.uint8))
    grown = cv2.dilate(core, np.ones((5, 5), np.uint8))
    n, labels = cv2.connectedComponents(grown, connectivity=8)
    sel = core > 0
    hist = np.bincount(labels[sel] * (NUM_COLORS + 1) + ids[sel],
                       minlength=n * (NUM_COLORS + 1)).reshape(n, NUM_COLORS + 1)
    area = hist.sum(axis=1)
    n_colors = (hist[:, 1:] >= np.maximum(3, 0.03 * area)[:, None]).sum(axis=1)
    valid = n_colors >= 2
    valid[0] = False
    if not valid.any():
        return np.zeros_like(ids)
    main = int(np.argmax(np.where(valid, area, 0)))
    body = sel & (labels == main)
    box = nonzero_box(body)
    assert box is not None
    bx0, by0, bx1, by1 = box
    extent = max(bx1 - bx0, by1 - by0)
    keep = valid & (area >= blob_fraction * area[main])
    sleeve = hist[:, _SLEEVE_IDS].sum(axis=1) >= 0.9 * np.maximum(area, 1)
    reach = int(attach_fraction * extent)
    sleeve_reach = int(sleeve_attach * extent)
    # the rules below only add blobs that are valid or in sleeve colours and not kept
    # yet: without any (mostly the shirt alone) they are skipped
    undecided = (valid | sleeve) & ~keep
    if max(reach, sleeve_reach) > 0 and undecided[1:].any():
        # each blob's least chessboard distance (the square neighbourhood) to the shirt
        gap = cv2.distanceTransform((labels != main).astype(np.uint8), cv2.DIST_C, 3)
        nearest, bottom, left, right = _blob_reach(labels, sel, gap, n)
        if reach > 0:
            keep |= (nearest <= reach) & (valid | sleeve)
        if sleeve_reach > 0:
            # over the head: above the shirt's top and within its columns
            over = (bottom < by0) & (left >= bx0) & (right <= bx1)
            # two forearms: two sleeve colors, each more than a few pixels
            two_sleeves = (hist[:, _SLEEVE_IDS] >= np.maximum(3, 0.03 * area)[:, None]).sum(
                axis=1) >= 2
            candidate = (nearest <= sleeve_reach) & valid & two_sleeves & sleeve & over & ~keep
            if candidate.any():  # within reach of the raised upper arms, not the torso
                on_sleeve = np.isin(ids, _SLEEVE_IDS)
                torso_rows = np.nonzero((body & ~on_sleeve).any(axis=1))[0]
                arm = body & on_sleeve
                if len(torso_rows):
                    arm[torso_rows[0]:] = False
                if arm.any():
                    arm_gap = cv2.distanceTransform((~arm).astype(np.uint8), cv2.DIST_C, 3)
                    from_arm = _blob_reach(labels, sel, arm_gap, n)[0]
                    keep |= candidate & (from_arm <= sleeve_reach)
    if (valid & sleeve & ~keep).any():
        # an arm in two sleeve colors joined to the shirt through white (its shoulder cap)
        bridge = cv2.bitwise_or(grown, cv2.dilate(white, np.ones((3, 3), np.uint8)))
        _, bridged = cv2.connectedComponents(bridge, connectivity=8)
        shirt = np.bincount(bridged[labels == main]).argmax()
        joined = np.bincount(labels[(bridged == shirt) & sel], minlength=n) > 0
        keep |= joined & valid & sleeve
    kept = core * keep[labels].astype(np.uint8)
    r = max(2, int(0.05 * extent))
    near = cv2.dilate(kept, np.ones((2 * r + 1, 2 * r + 1), np.uint8))
    keep_px = np.asarray(kept, np.uint8) | (np.asarray(white, np.uint8)
                                            & np.asarray(near, np.uint8))
    return (ids * keep_px).astype(np.uint8)


def make_query(view: CameraView, database: PoseDatabase, lo: NDArray[np.float64],
               hi: NDArray[np.float64], facing: NDArray[np.float64] | None = None,
               min_cos: float = 0.0) -> None:
    """Normalize the classified crop like the database (bounding box, margin, 40x40) and
    find its neighbours (facing as :meth:`PoseDatabase.query`)."""
    n = database.options.map_size
    extent = max(float(np.max(hi - lo)), 4.0)
    s = n * (1.0 - 2.0 * database.options.margin) / extent
    # crop pixel centres: bounding box of pixel areas [x - 0.5, x + 0.5]
    centre = 0.5 * (lo + hi) - 0.5
    off = (n - 1) / 2.0 - centre * s
    M = np.array([[s, 0.0, off[0]], [0.0, s, off[1]]])
    query = np.asarray(cv2.warpAffine(view.ids, M, (n, n), flags=cv2.INTER_NEAREST,
                                      borderValue=0), np.uint8)
    view.query_scale, view.query_offset = s, off
    nb = database.query(query, facing=facing, min_cos=min_cos)
    view.neighbours = nb
    view.distance = float(nb.distance[0])


def classify_camera(st: CameraState, crop: NDArray[np.uint8], mask: NDArray[np.bool_] | None,
                    fg: NDArray[np.bool_], model: ColorModel, noise_model: ColorModel,
                    o: ColorShirtOptions) -> tuple[NDArray[np.float64], NDArray[np.uint8]]:
    """Step 1 for one camera: choose ``W`` (automatic, kept, or a stored reference
    illumination after a light change) and classify the crop; ``st`` remembers ``W``.
    ``fg`` is the paper's "supposedly foreground" (the located window, masked).
    """
    box = nonzero_box(fg)  # the automatic search looks at the located window, mostly shirt
    sub = np.s_[:, :] if box is None else np.s_[box[1]: box[3] + 1, box[0]: box[2] + 1]
    sub_mask = None if mask is None else mask[sub]
    if st.W is None:
        st.W = auto_white_balance(crop[sub], model, sub_mask, o.threshold,
                                  candidates=list(st.references.matrices))
        if o.adaptive_white_balance:
            st.references.add(st.W)
    assert st.W is not None
    cls = model.classify(crop, st.W, o.threshold, mask)
    W = st.W
    frac = cls.fraction_classified(fg)
    # the paper's test (under 40% classified), plus a sudden halving of the
    # classified share: a light switched on or off
    sudden = st.last_fraction is not None and frac < 0.5 * st.last_fraction
    if o.adaptive_white_balance and (frac < o.retry_fraction or sudden):
        best = st.references.best(crop, model, mask, o.threshold)
        if best is not None and np.count_nonzero(best[1].ids) > np.count_nonzero(cls.ids):
            W, cls = best
        frac2 = cls.fraction_classified(fg)
        if frac2 < 0.5 * o.retry_fraction or (
            st.last_fraction is not None and frac2 < 0.5 * st.last_fraction
        ):
            auto = auto_white_balance(crop[sub], model, sub_mask, o.threshold,
                                      candidates=list(st.references.matrices))
            cls2 = model.classify(crop, auto, o.threshold, mask)
            if classification_score(cls2.ids) > classification_score(cls.ids):
                W, cls = auto, cls2
        st.W = W
    st.last_fraction = cls.fraction_classified(fg)
    if noise_model is not model:  # W was chosen with the plain model
        wide = noise_model.classify(crop, W, o.threshold, mask)
        if np.count_nonzero(wide.ids) <= _MAX_NOISE_GROWTH * np.count_nonzero(cls.ids):
            cls = wide
    return W, cls.ids


def prior_penalty_slope(strength: float, shirt_scale: float, W: NDArray[np.float64],
                        gain_power: float) -> float:
    """``C`` of the pose-assisted reclassification's penalty ``C d`` (per crop pixel):
    the paper's ``strength / s`` (``s`` the shirt's size in the crop) times
    ``g ** gain_power``, ``g = max(1, |det W| ** (1/3))`` the white balance's gain
    (an amplified image says less, so the pose says more).
    """
    gain = max(1.0, abs(float(np.linalg.det(W))) ** (1.0 / 3.0))
    return strength / max(shirt_scale, 1.0) * gain**gain_power
