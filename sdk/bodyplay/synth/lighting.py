"""Lighting presets for the synthetic camera: colored lights seen by a fixed-white-balance webcam.

A real webcam in a game room has its white balance fixed (or slow to adapt), so a
tungsten lamp makes the picture orange, fluorescent tubes make it greenish, and a
lamp switched off mid-clip changes both the color and the brightness of every
pixel at once (the stress test of the color-shirt paper). The presets here are
data: a set of directional lights with colors from a color temperature, an ambient
term, the exposure time the camera's auto-exposure would settle on and the analog
gain it would apply (which scales sensor noise, see :mod:`bodyplay.synth.sensor`).

Colors are linear RGB relative to the camera's fixed white point (about 5000 K):
a light of that temperature is neutral, warmer ones are orange, cooler ones blue.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from bodyplay.errors import ConfigError

__all__ = [
    "LightSpec",
    "LightingState",
    "LightingPreset",
    "LIGHTING_PRESETS",
    "lighting_preset",
    "kelvin_to_rgb",
]

_CAMERA_WHITE_K = 5000.0


def _planck_rgb(kelvin: float) -> NDArray[np.float64]:
    """Linear sRGB of a black body (Planck spectrum integrated against CIE 1931 fits)."""
    lam = np.arange(380.0, 781.0, 5.0)  # nm
    # Multi-lobe Gaussian fits of the CIE 1931 colour matching functions (Wyman et al. 2013).
    def g(x: NDArray[np.float64], mu: float, s1: float, s2: float) -> NDArray[np.float64]:
        s = np.where(x < mu, s1, s2)
        return np.asarray(np.exp(-0.5 * ((x - mu) / s) ** 2))

    xbar = 1.056 * g(lam, 599.8, 37.9, 31.0) + 0.362 * g(lam, 442.0, 16.0, 26.7) - 0.065 * g(
        lam, 501.1, 20.4, 26.2
    )
    ybar = 0.821 * g(lam, 568.8, 46.9, 40.5) + 0.286 * g(lam, 530.9, 16.3, 31.1)
    zbar = 1.217 * g(lam, 437.0, 11.8, 36.0) + 0.681 * g(lam, 459.0, 26.0, 13.8)
    h, c, k = 6.62607015e-34, 2.99792458e8, 1.380649e-23
    lm = lam * 1e-9
    spd = 1.0 / (lm**5 * (np.exp(h * c / (lm * k * kelvin)) - 1.0))
    xyz = np.array([np.sum(spd * xbar), np.sum(spd * ybar), np.sum(spd * zbar)])
    m = np.array(
        [[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]]
    )
    rgb = np.clip(m @ xyz, 1e-6, None)
    return np.asarray(rgb / rgb[1])


def kelvin_to_rgb(kelvin: float) -> tuple[float, float, float]:
    """Linear RGB (unit luminance) of a black body as seen by a camera white-balanced at 5000 K."""
    if not 1000.0 <= kelvin <= 20000.0:
        raise ConfigError(f"color temperature {kelvin} K is outside 1000..20000 K")
    rgb = _planck_rgb(kelvin) / _planck_rgb(_CAMERA_WHITE_K)
    rgb = rgb / float(rgb @ np.array([0.2126, 0.7152, 0.0722]))  # unit luminance
    return float(rgb[0]), float(rgb[1]), float(rgb[2])


@dataclass(frozen=True)
class LightSpec:
    """A directional light: where light comes *from* (world, unit vector), color, intensity."""

    direction: tuple[float, float, float]
    color: tuple[float, float, float]
    intensity: float

    def radiance(self) -> NDArray[np.float64]:
        """(3,) linear RGB contribution at normal incidence (color times intensity)."""
        return np.asarray(self.color) * self.intensity


@dataclass(frozen=True)
class LightingState:
    """The lights in effect at one instant, in the actor's frame (camera-relative)."""

    lights: tuple[LightSpec, ...]
    ambient: tuple[float, float, float]

    def room_illuminant(self) -> NDArray[np.float64]:
        """(3,) linear RGB that a diffuse wall facing the camera receives (for backgrounds)."""
        total = np.asarray(self.ambient, dtype=np.float64).copy()
        for light in self.lights:
            # A wall behind the actor faces the camera; lights from the front reach it.
            total += light.radiance() * max(0.25, light.direction[2])
        return total


@dataclass(frozen=True)
class _TimedLight:
    light: LightSpec
    off_after: float | None  # fraction of the clip after which the light is off
    flicker: float  # relative amplitude of the mains beat seen at the frame rate


@dataclass(frozen=True)
class LightingPreset:
    """A named lighting setup and the camera's auto-exposure response to it.

    ``exposure`` is the exposure time as a fraction of the frame period (motion blur
    length), ``gain`` the analog gain (1 = good light; noise grows with it).
    """

    name: str
    description: str
    timed_lights: tuple[_TimedLight, ...]
    ambient: tuple[float, float, float]
    exposure: float
    gain: float

    def state(self, t: float, duration: float | None) -> LightingState:
        """The lights at time ``t`` of a clip lasting ``duration`` seconds (None: live, no end).

        Directions are given in an actor-facing frame (+Z from the actor towards the
        camera, +Y up, +X the camera's right); :class:`~bodyplay.synth.camera.SyntheticCamera`
        rotates them into the world with the rig.
        """
        lights = []
        for tl in self.timed_lights:
            if tl.off_after is not None:
                switch_t = tl.off_after * duration if duration is not None else 5.0
                if t >= switch_t:
                    continue
            intensity = tl.light.intensity
            if tl.flicker:
                # 100 Hz mains flicker aliased by a 30 fps shutter: a 10 Hz beat.
                intensity *= 1.0 + tl.flicker * math.sin(2.0 * math.pi * 10.0 * t)
            lights.append(LightSpec(tl.light.direction, tl.light.color, intensity))
        return LightingState(tuple(lights), self.ambient)

    def switch_time(self, duration: float | None) -> float | None:
        """When a light switches off (None if it never does)."""
        for tl in self.timed_lights:
            if tl.off_after is not None:
                return tl.off_after * duration if duration is not None else 5.0
        return None


def _unit(x: float, y: float, z: float) -> tuple[float, float, float]:
    n = math.sqrt(x * x + y * y + z * z)
    return (x / n, y / n, z / n)


def _scaled(rgb: tuple[float, float, float], s: float) -> tuple[float, float, float]:
    return (rgb[0] * s, rgb[1] * s, rgb[2] * s)


def _build_presets() -> dict[str, LightingPreset]:
    neutral = kelvin_to_rgb(5000.0)
    warm = kelvin_to_rgb(2800.0)
    daylight = kelvin_to_rgb(7500.0)
    # Cool-white tubes: ~4100 K with the mercury-line green excess, little deep red.
    fluo = kelvin_to_rgb(4100.0)
    fluo = (fluo[0] * 0.86, fluo[1] * 1.0, fluo[2] * 0.92)
    key_left = _unit(-0.6, 0.55, 0.6)
    fill_right = _unit(0.7, 0.25, 0.65)
    overhead = _unit(0.0, 1.0, 0.35)
    presets = (
        LightingPreset(
            "steady",
            "even white light, as in a well-lit room; camera white balance matches it",
            (
                _TimedLight(LightSpec(key_left, neutral, 0.75), None, 0.0),
                _TimedLight(LightSpec(fill_right, neutral, 0.35), None, 0.0),
            ),
            _scaled(neutral, 0.30),
            exposure=0.5,
            gain=1.0,
        ),
        LightingPreset(
            "tungsten",
            "warm incandescent lamps (~2800 K) seen through daylight white balance: orange cast",
            (
                _TimedLight(LightSpec(key_left, warm, 0.85), None, 0.0),
                _TimedLight(LightSpec(fill_right, warm, 0.30), None, 0.0),
            ),
            _scaled(warm, 0.22),
            exposure=0.75,
            gain=1.6,
        ),
        LightingPreset(
            "fluorescent",
            "cool-white overhead tubes: greenish cast, flat light, slight mains flicker",
            (
                _TimedLight(LightSpec(overhead, fluo, 0.70), None, 0.04),
                _TimedLight(LightSpec(fill_right, fluo, 0.25), None, 0.04),
            ),
            _scaled(fluo, 0.40),
            exposure=0.5,
            gain=1.2,
        ),
        LightingPreset(
            "dim",
            "one weak warm lamp: long exposure (motion blur), high gain (noise), dark image",
            (_TimedLight(LightSpec(key_left, kelvin_to_rgb(3000.0), 0.42), None, 0.0),),
            _scaled(kelvin_to_rgb(3000.0), 0.10),
            exposure=1.0,
            gain=5.0,
        ),
        LightingPreset(
            "mixed",
            "a warm lamp on the left, cool daylight fill from a window on the right",
            (
                _TimedLight(LightSpec(key_left, warm, 0.70), None, 0.0),
                _TimedLight(LightSpec(fill_right, daylight, 0.45), None, 0.0),
            ),
            _scaled(neutral, 0.20),
            exposure=0.6,
            gain=1.4,
        ),
        LightingPreset(
            "switch",
            "as mixed, but the warm lamp goes off at mid-clip: sudden change of color and level",
            (
                _TimedLight(LightSpec(key_left, warm, 0.70), 0.5, 0.0),
                _TimedLight(LightSpec(fill_right, daylight, 0.45), None, 0.0),
            ),
            _scaled(daylight, 0.20),
            exposure=0.6,
            gain=1.4,
        ),
    )
    return {p.name: p for p in presets}


LIGHTING_PRESETS: dict[str, LightingPreset] = _build_presets()
"""The shipped presets by name: steady, tungsten, fluorescent, dim, mixed, switch."""


def lighting_preset(name: str | LightingPreset) -> LightingPreset:
    """Look up a lighting preset by name, with an error listing the valid names."""
    if isinstance(name, LightingPreset):
        return name
    try:
        return LIGHTING_PRESETS[name]
    except KeyError:
        raise ConfigError(
            f"unknown lighting preset {name!r}; choose one of {', '.join(LIGHTING_PRESETS)}"
        ) from None
