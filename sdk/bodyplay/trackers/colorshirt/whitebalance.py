"""White balance for the shirt: the 3x3 matrix ``W`` and the reference illuminations.

``W`` maps camera RGB to the model's, ``W I ~ mu``, by least squares from per-color
means (paper §5.1) of scribbles, a classification or a rendered pose; without
scribbles :func:`auto_white_balance` searches illuminant gains first.
:class:`ReferenceIlluminations` is the paper's set of previously seen ``W``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.shirt import NUM_COLORS
from bodyplay.errors import ConfigError
from bodyplay.trackers.colorshirt.colors import Classification, ColorModel

__all__ = ["fit_white_balance", "color_means", "white_balance_from_ids",
           "white_balance_from_scribbles", "auto_white_balance", "classification_score",
           "ReferenceIlluminations"]


def fit_white_balance(
    observed: ArrayLike,
    target: ArrayLike,
    weights: ArrayLike | None = None,
    prior: ArrayLike | None = None,
    ridge: float = 1e3,
    off_diagonal: float = 1.0,
) -> NDArray[np.float64]:
    """Least-squares ``W = argmin sum_k w_k ||W o_k - mu_k||^2 + sum_ij r_ij (W - P)_ij^2``
    for (K, 3) mean colors (0..255); the ridge pulls towards ``prior`` (identity when
    None), ``off_diagonal`` times harder on the channel-mixing entries (which drift
    when the visible colors are all alike). Rows are solved independently."""
    o = np.asarray(observed, dtype=np.float64).reshape(-1, 3)
    m = np.asarray(target, dtype=np.float64).reshape(-1, 3)
    if o.shape != m.shape:
        raise ConfigError(f"observed {o.shape} and target {m.shape} colors differ in shape")
    w = np.ones(o.shape[0]) if weights is None else np.asarray(weights, dtype=np.float64)
    P = np.eye(3) if prior is None else np.asarray(prior, dtype=np.float64)
    A = (o * w[:, None]).T @ o
    W = np.empty((3, 3))
    for i in range(3):
        r = np.full(3, ridge * off_diagonal)
        r[i] = ridge
        W[i] = np.linalg.solve(A + np.diag(r), (o * w[:, None]).T @ m[:, i] + r * P[i])
    return W


def color_means(
    image: NDArray[np.uint8], ids: NDArray[np.uint8], min_pixels: int = 15
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Mean raw RGB of each color in a color id map, and pixel counts (0 if too few)."""
    on = np.flatnonzero(ids)  # unclassified pixels only count towards id 0
    lab = ids.reshape(-1)[on].astype(np.int64)
    px = image.reshape(-1, 3)[on].astype(np.float64)
    counts = np.bincount(lab, minlength=NUM_COLORS + 1)[1 : NUM_COLORS + 1]
    sums = np.stack(
        [np.bincount(lab, weights=px[:, c], minlength=NUM_COLORS + 1) for c in range(3)], axis=1
    )[1 : NUM_COLORS + 1]
    means = sums / np.maximum(counts, 1)[:, None]
    counts = np.where(counts >= min_pixels, counts, 0)
    return means, counts


def white_balance_from_ids(
    image: NDArray[np.uint8],
    ids: NDArray[np.uint8],
    model: ColorModel,
    prior: ArrayLike | None = None,
    min_pixels: int = 15,
    min_colors: int = 3,
    ridge_fraction: float = 0.0,
) -> NDArray[np.float64] | None:
    """Refit ``W`` from an id map: each color of at least ``min_pixels`` pixels gives
    its mean, weighted by the root of its count (None under ``min_colors`` colors);
    ``ridge_fraction`` > 0 pulls towards ``prior`` with that share of the data's weight.
    """
    means, counts = color_means(image, ids, min_pixels)
    sel = counts > 0
    if int(sel.sum()) < min_colors:
        return None
    w = np.sqrt(counts[sel])
    ridge = 1e3
    off = 1.0
    if ridge_fraction > 0:
        ridge = ridge_fraction * float(np.sum(w[:, None] * means[sel] ** 2)) / 3.0
        off = 10.0
    return fit_white_balance(means[sel], model.means[sel], weights=w, prior=prior, ridge=ridge,
                             off_diagonal=off)


def white_balance_from_scribbles(
    image: NDArray[np.uint8], scribbles: NDArray[np.integer], model: ColorModel
) -> NDArray[np.float64]:
    """The paper's initialization: ``W`` from coarse scribbles on the visible patches.

    ``scribbles`` is (H, W) with the color index 0..9 under each scribbled pixel and
    -1 elsewhere. Raises ConfigError when fewer than three colors were scribbled.
    """
    s = np.asarray(scribbles)
    if s.shape != image.shape[:2]:
        raise ConfigError(f"scribble mask {s.shape} does not match image {image.shape[:2]}")
    ids = np.where(s >= 0, s + 1, 0).astype(np.uint8)
    W = white_balance_from_ids(image, ids, model, min_pixels=5)
    if W is None:
        raise ConfigError("scribble on at least three differently colored patches")
    return W


def classification_score(ids: NDArray[np.uint8], n_pixels: int | None = None,
                         cap: float = 0.1) -> float:
    """How shirt-like a classification is: ``sum_k min(fraction_k, cap)`` over colors
    (the cap stops a ``W`` that paints everything one color from scoring well)."""
    n = ids.size if n_pixels is None else n_pixels
    counts = np.bincount(ids.reshape(-1), minlength=NUM_COLORS + 1)[1:]
    return float(np.minimum(counts / max(n, 1), cap).sum())


def _candidate_gains(
    image: NDArray[np.uint8], mask: NDArray[np.bool_] | None, model: ColorModel
) -> list[NDArray[np.float64]]:
    cands: list[NDArray[np.float64]] = []
    px = image.reshape(-1, 3).astype(np.float64)
    if mask is not None:
        px = px[mask.reshape(-1)]
    mean = px.mean(axis=0) if px.size else np.full(3, 128.0)
    model_mean = model.means.mean(axis=0)
    # gray world: scale each channel so the region's mean matches the model's mean color
    cands.append(np.diag(model_mean / np.maximum(mean, 1.0)))
    gray = float(model_mean.mean() / max(mean.mean(), 1.0))
    for scale in (gray * 0.8, gray, gray * 1.25, 1.0):
        for gr in (0.6, 0.8, 1.0, 1.25, 1.6):
            for gb in (0.6, 0.8, 1.0, 1.25, 1.6):
                cands.append(scale * np.diag([gr, 1.0, gb]))
    return cands


def auto_white_balance(
    image: NDArray[np.uint8],
    model: ColorModel,
    mask: NDArray[np.bool_] | None = None,
    threshold: float = 3.0,
    refine_steps: int = 3,
    sample: int = 48,
    candidates: list[NDArray[np.float64]] | None = None,
) -> NDArray[np.float64]:
    """Estimate ``W`` with no scribbles from an image of the (located) shirt region:
    the best-scoring gray-world or illuminant-gain candidate (and ``candidates``) on a
    ``sample``-pixel-wide thumbnail, then the full 3x3 ``W`` refitted from its own
    classification up to ``refine_steps`` times."""
    import cv2

    h, w = image.shape[:2]
    f = min(1.0, sample / max(h, w))
    small = image
    small_mask = mask
    if f < 1.0:
        size = (max(1, round(w * f)), max(1, round(h * f)))
        small = np.asarray(cv2.resize(image, size, interpolation=cv2.INTER_AREA), np.uint8)
        if mask is not None:
            small_mask = cv2.resize(mask.astype(np.uint8), size,
                                    interpolation=cv2.INTER_NEAREST) > 0
    n_small = int(small_mask.sum()) if small_mask is not None else small.shape[0] * small.shape[1]
    # unmasked (a player in view, the room unknown), the window may be a third room:
    # one color counts half as much, so painting the room one color cannot win
    cap = 0.1 if mask is not None else 0.05
    best_W = np.eye(3)
    best_score = -1.0
    for W in [*_candidate_gains(image, mask, model), *(candidates or [])]:
        cls = model.classify(small, W, threshold, small_mask)
        s = classification_score(cls.ids, n_small, cap)
        if s > best_score:
            best_score, best_W = s, W
    n_full = int(mask.sum()) if mask is not None else h * w
    cls = model.classify(image, best_W, threshold, mask)
    score = classification_score(cls.ids, n_full, cap)
    for _ in range(refine_steps):
        W2 = white_balance_from_ids(image, cls.ids, model, prior=best_W, min_colors=4,
                                    ridge_fraction=0.1)
        if W2 is None:
            break
        cls2 = model.classify(image, W2, threshold, mask)
        s2 = classification_score(cls2.ids, n_full, cap)
        if s2 < score - 1e-3:
            break
        best_W, cls, score = W2, cls2, s2
    return best_W


@dataclass
class ReferenceIlluminations:
    """The reference white-balance matrices (paper §5.2): :meth:`add` stores ``W*`` when
    farther than ``min_distance`` (Frobenius) from every stored one; :meth:`best` gives
    the one classifying the most foreground."""

    min_distance: float = 0.5
    max_size: int = 32
    matrices: list[NDArray[np.float64]] = field(default_factory=list)

    def add(self, W: ArrayLike) -> bool:
        """Store ``W`` if it is new enough; True when it was stored."""
        Wm = np.asarray(W, dtype=np.float64)
        if Wm.shape != (3, 3) or not np.all(np.isfinite(Wm)):
            raise ConfigError("a reference illumination must be a finite 3x3 matrix")
        if self.matrices:
            d = min(float(np.linalg.norm(Wm - M)) for M in self.matrices)
            if d <= self.min_distance:
                return False
        self.matrices.append(Wm.copy())
        if len(self.matrices) > self.max_size:
            self.matrices.pop(1)  # keep the first (user / bootstrap) illumination
        return True

    def best(
        self,
        image: NDArray[np.uint8],
        model: ColorModel,
        mask: NDArray[np.bool_] | None,
        threshold: float,
    ) -> tuple[NDArray[np.float64], Classification] | None:
        """The stored ``W`` that classifies the most foreground pixels, with its result."""
        best: tuple[NDArray[np.float64], Classification] | None = None
        best_n = -1
        for W in self.matrices:
            cls = model.classify(image, W, threshold, mask)
            n = int(np.count_nonzero(cls.ids))
            if n > best_n:
                best_n, best = n, (W, cls)
        return best
