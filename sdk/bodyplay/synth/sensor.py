"""The webcam sensor: exposure, shot and read noise, ADC, gamma, lossy compression.

What a cheap webcam does to light, in order: the shutter integrates the scene over
the exposure time (motion blur: the caller averages sub-frame renders, see
:func:`average_linear`), the pixels count photo-electrons (Poisson shot noise,
approximated by a Gaussian of variance equal to the signal) plus read noise, the
analog gain amplifies both (dim scenes: high gain, noisy pictures), a 12-bit ADC
quantizes, the image processor applies the sRGB tone curve with its white balance
*fixed* (no correction of colored light), and the USB link carries MJPEG, i.e. a
JPEG round trip. The per-pixel chain (noise, ADC, tone curve) is one fused numba
pass with lookup tables for the tone curve and the Gaussian (16 random bits per
pixel and channel).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np
from numba import njit
from numpy.typing import NDArray

from bodyplay.errors import ConfigError

__all__ = [
    "NoiseLevel",
    "NOISE_LEVELS",
    "noise_level",
    "Sensor",
    "srgb_to_linear",
    "linear_to_srgb",
    "average_linear",
    "gaussian_noise",
    "jpeg_roundtrip",
]

_ADC_LEVELS = 4096  # 12-bit ADC


def srgb_to_linear(srgb: NDArray[np.floating]) -> NDArray[np.float64]:
    """sRGB-encoded values in 0..1 to linear light (IEC 61966-2-1)."""
    s = np.asarray(srgb, dtype=np.float64)
    return np.where(s <= 0.04045, s / 12.92, ((s + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(lin: NDArray[np.floating]) -> NDArray[np.float64]:
    """Linear light in 0..1 to sRGB-encoded values in 0..1."""
    x = np.clip(np.asarray(lin, dtype=np.float64), 0.0, 1.0)
    return np.where(x <= 0.0031308, x * 12.92, 1.055 * x ** (1.0 / 2.4) - 0.055)


def _normal_table() -> NDArray[np.float32]:
    """Inverse normal CDF at the centres of 65536 equal-probability bins."""
    from scipy.special import ndtri

    p = (np.arange(65536, dtype=np.float64) + 0.5) / 65536.0
    return np.asarray(ndtri(p), dtype=np.float32)


_NORMAL_TABLE = _normal_table()
_DECODE_LUT = srgb_to_linear(np.arange(256) / 255.0).astype(np.float32)
_ENCODE_LUT = np.clip(
    np.round(linear_to_srgb(np.arange(_ADC_LEVELS) / (_ADC_LEVELS - 1)) * 255.0), 0, 255
).astype(np.uint8)


def average_linear(images: list[NDArray[np.uint8]], srgb_encoded: bool) -> NDArray[np.float32]:
    """Average uint8 renders in linear light: the shutter integrating sub-frames.

    ``srgb_encoded`` says whether the renders are sRGB-encoded (decoded with a
    lookup table) or already linear (scaled by 1/255).
    """
    if not images:
        raise ConfigError("average_linear needs at least one image")
    acc: NDArray[np.float32] | None = None
    for img in images:
        lin = _DECODE_LUT[img] if srgb_encoded else img.astype(np.float32) * np.float32(1 / 255)
        acc = lin if acc is None else np.add(acc, lin, out=acc)
    assert acc is not None
    if len(images) > 1:
        acc *= np.float32(1.0 / len(images))
    return acc


@dataclass(frozen=True)
class NoiseLevel:
    """Sensor and link quality: full-well capacity and read noise (electrons), JPEG quality.

    ``jpeg_quality`` None means no compression (a lossless link); ``full_well`` 0
    means a noise-free sensor.
    """

    name: str
    full_well: float
    read_noise: float
    jpeg_quality: int | None


NOISE_LEVELS: dict[str, NoiseLevel] = {
    n.name: n
    for n in (
        NoiseLevel("none", 0.0, 0.0, None),
        NoiseLevel("low", 9000.0, 2.0, 95),
        NoiseLevel("medium", 4000.0, 4.0, 88),
        NoiseLevel("high", 1500.0, 8.0, 75),
    )
}
"""Named sensor qualities: none (ideal), low (good webcam), medium (cheap one), high (bad)."""


def noise_level(name: str | NoiseLevel) -> NoiseLevel:
    """Look up a noise level by name, with an error listing the valid names."""
    if isinstance(name, NoiseLevel):
        return name
    try:
        return NOISE_LEVELS[name]
    except KeyError:
        raise ConfigError(
            f"unknown noise level {name!r}; choose one of {', '.join(NOISE_LEVELS)}"
        ) from None


class Sensor:
    """Turns linear irradiance images into 8-bit sRGB frames as a webcam delivers them.

    ``gain`` is the analog gain of the lighting preset (noise grows with it);
    the random generator is the caller's, so a seeded camera is reproducible.
    """

    def __init__(self, level: NoiseLevel, gain: float = 1.0) -> None:
        if gain <= 0:
            raise ConfigError(f"sensor gain must be positive, got {gain}")
        self.level = level
        self.gain = float(gain)
        if level.full_well > 0:
            # variance of a linear value L: L * gain / FW + (read * gain / FW)^2
            self._a = np.float32(self.gain / level.full_well)
            self._b = np.float32((level.read_noise * self.gain / level.full_well) ** 2)
        else:
            self._a = np.float32(0.0)
            self._b = np.float32(0.0)

    @property
    def noisy(self) -> bool:
        """Whether this sensor adds noise."""
        return bool(self._a > 0 or self._b > 0)

    def develop(self, linear: NDArray[np.float32], rng: np.random.Generator) -> NDArray[np.uint8]:
        """(H, W, 3) linear float32 in 0..1 (left unchanged) -> (H, W, 3) uint8 sRGB."""
        lin = np.ascontiguousarray(linear, dtype=np.float32)
        out = np.empty(lin.shape, np.uint8)
        if self.noisy:
            bits = np.frombuffer(rng.bytes(2 * lin.size), dtype=np.uint16)
        else:
            bits = np.zeros(0, np.uint16)
        _develop_pixels(lin.reshape(-1), bits, self._a, self._b, _NORMAL_TABLE, _ENCODE_LUT,
                        out.reshape(-1))
        if self.level.jpeg_quality is not None:
            out = jpeg_roundtrip(out, self.level.jpeg_quality)
        return out


@njit(cache=True, nogil=True)
def _develop_pixels(lin, bits, a, b, normal, encode, out):  # type: ignore[no-untyped-def]
    """One pass per value: shot + read noise (if ``bits``), 12-bit ADC, sRGB tone curve.

    out[i] = encode[adc(L + sqrt(max(L, 0) * a + b) * normal[bits[i]])] with
    L = lin[i]; float32 arithmetic as the vectorized form it replaces.
    """
    top = np.float32(_ADC_LEVELS - 1)
    noisy = bits.size > 0
    for i in range(lin.size):
        x = lin[i]
        if noisy:
            x = max(x, np.float32(0.0))
            sigma = np.float32(math.sqrt(x * a + b))
            x = x + sigma * normal[bits[i]]
        x = x * top + np.float32(0.5)
        x = min(max(x, np.float32(0.0)), top)
        out[i] = encode[int(x)]


def gaussian_noise(rng: np.random.Generator, shape: tuple[int, ...]) -> NDArray[np.float32]:
    """Standard normal float32 samples by inverse-CDF lookup of 16 random bits each.

    Four times faster than ``Generator.standard_normal`` here; the tails are cut
    at 4.3 sigma, far beyond what 8-bit pixels resolve.
    """
    n = int(np.prod(shape))
    bits = np.frombuffer(rng.bytes(2 * n), dtype=np.uint16)
    return np.take(_NORMAL_TABLE, bits).reshape(shape)


def jpeg_roundtrip(rgb: NDArray[np.uint8], quality: int) -> NDArray[np.uint8]:
    """Encode and decode as JPEG (what an MJPEG webcam link does to every frame)."""
    if not 1 <= quality <= 100:
        raise ConfigError(f"JPEG quality must be 1..100, got {quality}")
    ok, buf = cv2.imencode(".jpg", rgb[:, :, ::-1], [cv2.IMWRITE_JPEG_QUALITY, int(quality)])
    if not ok:
        raise ConfigError("JPEG encoding failed")
    bgr = cv2.imdecode(buf, cv2.IMREAD_COLOR)
    if bgr is None:
        raise ConfigError("JPEG decoding failed")
    return np.ascontiguousarray(np.asarray(bgr, dtype=np.uint8)[:, :, ::-1])
