"""The shirt's color model: ten Gaussians in RGB and Mahalanobis pixel classification.

A white-balanced pixel ``W I`` is the nearest of the ten colors in Mahalanobis
distance when under ``T``. A *color id map* is ``uint8``: 0 unclassified, ``k + 1``
shirt color ``k`` (:data:`bodyplay.body.shirt.SHIRT_COLORS`), as the database's.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import cached_property
from importlib import resources
from pathlib import Path

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.shirt import NUM_COLORS, SHIRT_COLORS
from bodyplay.errors import ConfigError

__all__ = ["ColorModel", "Classification", "default_color_model", "srgb_color_model",
           "DEFAULT_MODEL_RESOURCE"]

DEFAULT_MODEL_RESOURCE = "color_model.json"
"""File name of the shipped default model inside ``bodyplay/assets/colorshirt``."""

_RIDGE = 4.0  # added to every covariance diagonal (RGB units squared): keeps it invertible


@numba.njit(cache=True, nogil=True)
def _balanced_row(image: NDArray[np.uint8], y: int, W: NDArray[np.float32],
                  p0: NDArray[np.float32], p1: NDArray[np.float32],
                  p2: NDArray[np.float32]) -> None:  # pragma: no cover - compiled
    """Row ``y`` of ``image`` white-balanced by ``W``, into ``p0``, ``p1``, ``p2``."""
    for x in range(image.shape[1]):
        r = np.float32(image[y, x, 0])
        g = np.float32(image[y, x, 1])
        b = np.float32(image[y, x, 2])
        p0[x] = W[0, 0] * r + W[0, 1] * g + W[0, 2] * b
        p1[x] = W[1, 0] * r + W[1, 1] * g + W[1, 2] * b
        p2[x] = W[2, 0] * r + W[2, 1] * g + W[2, 2] * b


@numba.njit(cache=True, nogil=True)
def _mahalanobis_row(p0: NDArray[np.float32], p1: NDArray[np.float32],
                     p2: NDArray[np.float32], means: NDArray[np.float32],
                     linv: NDArray[np.float32], c: int,
                     out: NDArray[np.float32]) -> None:  # pragma: no cover - compiled
    """Mahalanobis distance of a balanced row to color ``c`` (``linv`` is lower
    triangular: ``z = L^-1 d``, the distance is ``||z||``)."""
    m0, m1, m2 = means[c, 0], means[c, 1], means[c, 2]
    l00, l10, l11 = linv[c, 0, 0], linv[c, 1, 0], linv[c, 1, 1]
    l20, l21, l22 = linv[c, 2, 0], linv[c, 2, 1], linv[c, 2, 2]
    for x in range(out.shape[0]):
        d0 = p0[x] - m0
        d1 = p1[x] - m1
        d2 = p2[x] - m2
        z0 = l00 * d0
        z1 = l10 * d0 + l11 * d1
        z2 = l20 * d0 + l21 * d1 + l22 * d2
        out[x] = np.sqrt(z0 * z0 + z1 * z1 + z2 * z2)


# The kernel works a row at a time, color by color over the row's pixels (loops the
# compiler vectorizes); every pixel gets the same operations in the same order as
# one pixel at a time would, so the same values.
@numba.njit(cache=True, nogil=True)
def _classify_kernel(  # pragma: no cover - compiled
    image: NDArray[np.uint8],
    W: NDArray[np.float32],
    means: NDArray[np.float32],
    linv: NDArray[np.float32],
    threshold: float,
    mask: NDArray[np.bool_],
    use_mask: bool,
    dists: NDArray[np.float32],
    patch: NDArray[np.uint8],
    color: NDArray[np.int64],
    strength: np.float32,
    far: np.float32,
) -> tuple[NDArray[np.uint8], NDArray[np.uint8]]:
    """Color ids of the balanced pixels nearest a color (Mahalanobis) under
    ``threshold``, each color paying ``strength`` times its least distance to one of
    its patches (``dists[j]`` of patch ``patch[j]`` of color ``color[j]``; ``far`` for
    a color with none, nothing when ``far`` is 0), and per classified pixel that patch."""
    h, w = image.shape[0], image.shape[1]
    k = means.shape[0]
    ids = np.zeros((h, w), np.uint8)
    owner = np.zeros((h, w), np.uint8)
    best = np.empty((k, w), np.float32)
    near = np.zeros((k, w), np.uint8)
    seen = np.zeros(k, np.bool_)  # whether the color has a patch (the same on every pixel)
    p0, p1, p2 = np.empty(w, np.float32), np.empty(w, np.float32), np.empty(w, np.float32)
    dist = np.empty(w, np.float32)
    bd = np.empty(w, np.float32)
    bk = np.empty(w, np.int64)
    for y in range(h):
        seen[:] = False
        for j in range(dists.shape[0]):
            c = color[j]
            pj = patch[j]
            if not seen[c]:  # the color's first patch
                seen[c] = True
                for x in range(w):
                    best[c, x] = dists[j, y, x]
                    near[c, x] = pj
                continue
            for x in range(w):  # a later one where it is strictly nearer
                d = dists[j, y, x]
                b = best[c, x]
                nearer = d < b
                best[c, x] = d if nearer else b
                near[c, x] = pj if nearer else near[c, x]
        _balanced_row(image, y, W, p0, p1, p2)
        bd[:] = np.inf
        bk[:] = -1
        for c in range(k):
            _mahalanobis_row(p0, p1, p2, means, linv, c, dist)
            if seen[c]:
                for x in range(w):
                    dist[x] += strength * best[c, x]
            elif far != 0:
                for x in range(w):
                    dist[x] += far
            for x in range(w):
                v = dist[x]
                lower = v < bd[x]
                bd[x] = v if lower else bd[x]
                bk[x] = c if lower else bk[x]
        for x in range(w):
            if use_mask and not mask[y, x]:
                continue
            if bd[x] < threshold:
                c = bk[x]
                ids[y, x] = c + 1
                owner[y, x] = near[c, x] if seen[c] else 0
    return ids, owner


def _checked(image: NDArray[np.uint8], white_balance: ArrayLike | None,
             mask: NDArray[np.bool_] | None
             ) -> tuple[NDArray[np.uint8], NDArray[np.float32], NDArray[np.bool_]]:
    """A classification's image, ``W`` (float32, identity when None) and mask (a 1x1
    placeholder when None), checked."""
    img = np.ascontiguousarray(image)
    if img.ndim != 3 or img.shape[2] != 3 or img.dtype != np.uint8:
        raise ConfigError(f"expected an (H, W, 3) uint8 RGB image, got {img.shape} {img.dtype}")
    W = np.eye(3, dtype=np.float32) if white_balance is None else np.asarray(
        white_balance, dtype=np.float32
    )
    if W.shape != (3, 3):
        raise ConfigError(f"white balance must be 3x3, got {W.shape}")
    if mask is None:
        return img, W, np.ones((1, 1), np.bool_)
    m = np.ascontiguousarray(mask, dtype=np.bool_)
    if m.shape != img.shape[:2]:
        raise ConfigError(f"mask shape {m.shape} does not match image {img.shape[:2]}")
    return img, W, m


@dataclass(frozen=True, eq=False)
class Classification:
    """A classified image: color id map (0 = none, k+1 = color k)."""

    ids: NDArray[np.uint8]

    def fraction_classified(self, mask: NDArray[np.bool_] | None = None) -> float:
        """Fraction of (foreground) pixels that received a color: the paper's 40% test."""
        if mask is None:
            return float(np.count_nonzero(self.ids)) / max(self.ids.size, 1)
        n = int(np.count_nonzero(mask))
        return float(np.count_nonzero(self.ids[mask])) / max(n, 1)


@dataclass(frozen=True, eq=False)
class ColorModel:
    """Ten Gaussians ``N(mu_k, Sigma_k)`` in RGB 0..255, one per shirt color.

    Build one with :meth:`fit` (labeled pixels), :func:`srgb_color_model` (the
    nominal fabric colors) or :func:`default_color_model` (the shipped fit).
    """

    means: NDArray[np.float64]
    covariances: NDArray[np.float64]
    measurement_noise: float = 0.0
    """Std (RGB units) of the camera's own measurement error (noise, quantization,
    compression) as the training images had it; see :meth:`effective_inverse`."""

    def __post_init__(self) -> None:
        if not (np.isfinite(self.measurement_noise) and self.measurement_noise >= 0):
            raise ConfigError("measurement_noise must be a finite value >= 0")
        m = np.asarray(self.means, dtype=np.float64)
        c = np.asarray(self.covariances, dtype=np.float64)
        if m.shape != (NUM_COLORS, 3) or c.shape != (NUM_COLORS, 3, 3):
            raise ConfigError(
                f"a color model needs ({NUM_COLORS}, 3) means and ({NUM_COLORS}, 3, 3) "
                f"covariances, got {m.shape} and {c.shape}"
            )
        if not (np.all(np.isfinite(m)) and np.all(np.isfinite(c))):
            raise ConfigError("color model contains NaN or infinite values")
        try:
            np.linalg.cholesky(c)
        except np.linalg.LinAlgError:
            raise ConfigError("color model covariances must be positive definite") from None
        object.__setattr__(self, "means", m)
        object.__setattr__(self, "covariances", c)

    # ---- construction ------------------------------------------------------------
    @classmethod
    def fit(cls, pixels: ArrayLike, labels: ArrayLike, min_pixels: int = 20) -> ColorModel:
        """Fit the ten Gaussians to RGB ``pixels`` (N, 3) with color ``labels`` (N,).

        Labels are color indices 0..9; negative labels are ignored. Every color needs
        at least ``min_pixels`` samples; a small ridge keeps covariances invertible.
        """
        px = np.asarray(pixels, dtype=np.float64).reshape(-1, 3)
        lab = np.asarray(labels).reshape(-1)
        if lab.shape[0] != px.shape[0]:
            raise ConfigError(f"{px.shape[0]} pixels but {lab.shape[0]} labels")
        means = np.zeros((NUM_COLORS, 3))
        covs = np.zeros((NUM_COLORS, 3, 3))
        for k in range(NUM_COLORS):
            sel = px[lab == k]
            if sel.shape[0] < min_pixels:
                raise ConfigError(
                    f"color {SHIRT_COLORS[k].name!r} has {sel.shape[0]} labeled pixels, "
                    f"need at least {min_pixels}; label more of that patch"
                )
            means[k] = sel.mean(axis=0)
            covs[k] = np.cov(sel, rowvar=False) + _RIDGE * np.eye(3)
        return cls(means, covs)

    # ---- derived -----------------------------------------------------------------
    @cached_property
    def _linv(self) -> NDArray[np.float32]:
        L = np.linalg.cholesky(self.covariances)
        return np.linalg.inv(L).astype(np.float32)

    def effective_inverse(self, white_balance: NDArray[np.float32]) -> NDArray[np.float32]:
        """Inverse Cholesky factors of the covariances seen through ``white_balance``:
        a balanced pixel ``W (x + e)`` spreads by ``W S W^T``, not ``S =
        measurement_noise^2 I``; the positive part of the difference is added."""
        if self.measurement_noise <= 0:
            return self._linv
        W = np.asarray(white_balance, dtype=np.float64)
        key = W.tobytes()
        last = self.__dict__.get("_last_inverse")
        if last is not None and last[0] == key:  # the same W as the last call (a frame's
            return last[1]                       # classifications share it)
        extra = self.measurement_noise**2 * (W @ W.T - np.eye(3))
        w, v = np.linalg.eigh(extra)
        extra = (v * np.maximum(w, 0.0)) @ v.T
        out = self._linv
        if np.any(extra):
            L = np.linalg.cholesky(self.covariances + extra[None])
            out = np.linalg.inv(L).astype(np.float32)
        self.__dict__["_last_inverse"] = (key, out)
        return out

    @cached_property
    def _means32(self) -> NDArray[np.float32]:
        return self.means.astype(np.float32)

    def classify(
        self,
        image: NDArray[np.uint8],
        white_balance: ArrayLike | None = None,
        threshold: float = 3.0,
        mask: NDArray[np.bool_] | None = None,
    ) -> Classification:
        """Classify an RGB image into a color id map.

        ``white_balance`` is the 3x3 ``W`` applied to each pixel first (identity when
        None); ``mask`` restricts classification to foreground pixels (the paper's
        background-subtraction mask).
        """
        img, W, m = _checked(image, white_balance, mask)
        ids, _ = _classify_kernel(
            img, W, self._means32, self.effective_inverse(W), float(threshold), m,
            mask is not None, np.zeros((0, 1, 1), np.float32), np.zeros(0, np.uint8),
            np.zeros(0, np.int64), np.float32(0.0), np.float32(0.0))
        return Classification(ids)

    def classify_near(
        self,
        image: NDArray[np.uint8],
        white_balance: ArrayLike,
        threshold: float,
        mask: NDArray[np.bool_] | None,
        distances: NDArray[np.float32],
        patch: NDArray[np.uint8],
        color: NDArray[np.int64],
        strength: float,
        far: float = 1.0e4,
    ) -> tuple[NDArray[np.uint8], NDArray[np.uint8]]:
        """:meth:`classify` with the pose prior's penalty made on the fly: color ``k``
        pays ``strength`` times the least of its patches' distance maps (``distances``
        (M, H, W) of patches ``patch`` of colors ``color``), or ``far`` without one.
        Returns the id map and, per classified pixel, its color's nearest patch."""
        img, W, m = _checked(image, white_balance, mask)
        d = np.ascontiguousarray(distances, dtype=np.float32)
        if d.ndim != 3 or d.shape[1:] != img.shape[:2] or not len(patch) == len(color) == len(d):
            raise ConfigError(f"distances must be (M, H, W) of the image with M patches and "
                              f"colors, got {d.shape}, {len(patch)}, {len(color)}")
        return _classify_kernel(
            img, W, self._means32, self.effective_inverse(W), float(threshold), m,
            mask is not None, d, np.ascontiguousarray(patch, np.uint8),
            np.ascontiguousarray(color, np.int64), np.float32(strength), np.float32(far))

    # ---- persistence ---------------------------------------------------------------
    def to_dict(self) -> dict[str, object]:
        """JSON-ready form: color names, means and covariances."""
        return {
            "colors": [c.name for c in SHIRT_COLORS],
            "means": np.round(self.means, 4).tolist(),
            "covariances": np.round(self.covariances, 4).tolist(),
        }

    @classmethod
    def from_dict(cls, data: dict[str, object], where: str = "color model") -> ColorModel:
        """Read :meth:`to_dict` output, naming the source in errors."""
        try:
            return cls(np.asarray(data["means"], float), np.asarray(data["covariances"], float))
        except KeyError as exc:
            raise ConfigError(f"{where}: missing key {exc.args[0]!r}") from None

    def save(self, path: str | Path) -> Path:
        """Write the model as JSON."""
        p = Path(path)
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(json.dumps(self.to_dict(), indent=1))
        return p

    @classmethod
    def load(cls, path: str | Path) -> ColorModel:
        """Read a model written by :meth:`save`."""
        p = Path(path)
        if not p.exists():
            raise ConfigError(f"{p}: no such color model; run `bodyplay colors fit` to make one")
        try:
            data = json.loads(p.read_text())
        except json.JSONDecodeError as exc:
            raise ConfigError(f"{p}: not valid JSON ({exc.msg})") from None
        return cls.from_dict(data, where=str(p))


def srgb_color_model(noise: float = 12.0, shading: float = 0.18) -> ColorModel:
    """A model from the nominal sRGB fabric colors.

    Each covariance is isotropic sensor noise (``noise`` std, RGB units) plus an
    elongation along the mean color (``shading`` relative std), since shading mostly
    scales a patch's color.
    """
    means = np.array([c.rgb for c in SHIRT_COLORS], dtype=np.float64)
    covs = np.empty((NUM_COLORS, 3, 3))
    for k, mu in enumerate(means):
        covs[k] = noise**2 * np.eye(3) + shading**2 * np.outer(mu, mu)
    return ColorModel(means, covs)


def default_color_model() -> ColorModel:
    """The shipped model (fitted to id-map-labeled synthetic renders), else the sRGB one."""
    res = resources.files("bodyplay").joinpath("assets", "colorshirt", DEFAULT_MODEL_RESOURCE)
    if res.is_file():
        return ColorModel.from_dict(json.loads(res.read_text()), where=str(res))
    return srgb_color_model()
