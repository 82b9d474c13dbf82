"""Options of the synthetic camera: one frozen, validated record of every parameter.

:class:`SyntheticCameraOptions` holds everything that decides the pixels (rig,
lighting, noise, background, body, occlusions, seed, file format) so that
``meta.json`` can store it with :meth:`SyntheticCameraOptions.to_dict` and a run
can be repeated exactly from :meth:`SyntheticCameraOptions.from_dict`. Build one
with :func:`make_synthetic_camera_options`, which checks every value and says
what is wrong.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import asdict, dataclass, fields
from typing import Any

from bodyplay.body.shapes import body_shape
from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types
from bodyplay.synth.backgrounds import resolve_background
from bodyplay.synth.lighting import lighting_preset
from bodyplay.synth.occluder import Occlusion, parse_occlusion
from bodyplay.synth.rig import make_rig_options
from bodyplay.synth.sensor import noise_level

__all__ = ["SyntheticCameraOptions", "make_synthetic_camera_options", "parse_size", "FORMATS"]

FORMATS: tuple[str, ...] = ("mp4", "png")
"""File formats a capture folder can be written in."""


@dataclass(frozen=True)
class SyntheticCameraOptions:
    """Every parameter of a synthetic capture (see :func:`make_synthetic_camera_options`).

    ``size`` is (width, height); ``distance``/``baseline`` None let the rig choose
    (2.5..4 m, 1..2 m); ``k1`` radial lens distortion; ``max_subframes`` bounds the
    renders averaged per frame for motion blur (1 disables blur); ``msaa`` GL
    multisampling (0, 2, 4 or 8).
    """

    cameras: int = 1
    fps: float = 30.0
    size: tuple[int, int] = (640, 480)
    background: str = "brick"
    lighting: str = "steady"
    noise: str = "low"
    body: str = "m"
    occlusions: tuple[Occlusion, ...] = ()
    seed: int = 0
    format: str = "mp4"
    hfov_deg: float = 60.0
    distance: float | None = None
    baseline: float | None = None
    k1: float = 0.0
    max_subframes: int = 4
    msaa: int = 0

    @property
    def width(self) -> int:
        """Image width in pixels."""
        return self.size[0]

    @property
    def height(self) -> int:
        """Image height in pixels."""
        return self.size[1]

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dict (occlusions as ``"START:SECONDS"`` strings)."""
        d = asdict(self)
        d["size"] = list(self.size)
        d["occlusions"] = [str(o) for o in self.occlusions]
        return d

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> SyntheticCameraOptions:
        """Rebuild validated options from :meth:`to_dict` output (e.g. meta.json)."""
        known = {f.name for f in fields(cls)}
        unknown = set(data) - known
        if unknown:
            raise ConfigError(f"unknown synthetic camera options: {', '.join(sorted(unknown))}")
        kw = dict(data)
        if "size" in kw:
            kw["size"] = tuple(kw["size"])
        return make_synthetic_camera_options(**kw)

    def __post_init__(self) -> None:
        check_option_types(self)


def parse_size(text: str) -> tuple[int, int]:
    """Parse ``WIDTHxHEIGHT`` (e.g. ``640x480``)."""
    parts = text.lower().replace(" ", "").split("x")
    if len(parts) != 2 or not all(p.isdigit() for p in parts):
        raise ConfigError(f"size {text!r} must be WIDTHxHEIGHT, e.g. 640x480")
    w, h = int(parts[0]), int(parts[1])
    if not (16 <= w <= 4096 and 16 <= h <= 4096):
        raise ConfigError(f"size {text!r}: width and height must be within 16..4096")
    if w % 2 or h % 2:
        raise ConfigError(f"size {text!r}: width and height must be even (video encoders)")
    return w, h


def make_synthetic_camera_options(
    cameras: int = 1,
    fps: float = 30.0,
    size: tuple[int, int] | str = (640, 480),
    background: str = "brick",
    lighting: str = "steady",
    noise: str = "low",
    body: str = "m",
    occlusions: Iterable[Occlusion | str] = (),
    seed: int = 0,
    format: str = "mp4",
    hfov_deg: float = 60.0,
    distance: float | None = None,
    baseline: float | None = None,
    k1: float = 0.0,
    max_subframes: int = 4,
    msaa: int = 0,
) -> SyntheticCameraOptions:
    """Validated :class:`SyntheticCameraOptions`; every error names the bad value and the fix."""
    if isinstance(size, str):
        size = parse_size(size)
    else:
        size = parse_size(f"{int(size[0])}x{int(size[1])}")
    if not (math.isfinite(fps) and 1.0 <= fps <= 240.0):
        raise ConfigError(f"fps {fps} must be within 1..240")
    make_rig_options(cameras, size[0], size[1], hfov_deg, distance, baseline, k1, seed)
    lighting_preset(lighting)
    noise_level(noise)
    body_shape(body)
    background = resolve_background(background)
    occ = tuple(o if isinstance(o, Occlusion) else parse_occlusion(o) for o in occlusions)
    if format not in FORMATS:
        raise ConfigError(f"unknown format {format!r}; choose one of {', '.join(FORMATS)}")
    if not 1 <= int(max_subframes) <= 32:
        raise ConfigError(f"max_subframes {max_subframes} must be within 1..32")
    if msaa not in (0, 2, 4, 8):
        raise ConfigError(f"msaa {msaa} must be 0, 2, 4 or 8")
    if int(seed) != seed or seed < 0:
        raise ConfigError(f"seed {seed} must be a non-negative integer")
    return SyntheticCameraOptions(
        cameras=int(cameras),
        fps=float(fps),
        size=size,
        background=background,
        lighting=lighting,
        noise=noise,
        body=body,
        occlusions=occ,
        seed=int(seed),
        format=format,
        hfov_deg=float(hfov_deg),
        distance=None if distance is None else float(distance),
        baseline=None if baseline is None else float(baseline),
        k1=float(k1),
        max_subframes=int(max_subframes),
        msaa=int(msaa),
    )
