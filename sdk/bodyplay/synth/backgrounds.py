"""Background pictures behind the synthetic actor: shipped photos, any image file, or a plain wall.

The shipped photos (CC0 / public domain, see ``assets/backgrounds/NOTICE``) are
chosen by name (``brick``, ``coffee`` ...); any other value is read as an image
path. ``plain`` gives a uniform grey wall and ``#rrggbb`` a wall of that color,
useful when a test needs to tell the actor from the background. Images are
scaled to cover the frame and cropped; a second camera gets a slightly shifted
crop, since it sees the wall from elsewhere (the wall is a backdrop, not geometry).
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.errors import ConfigError

__all__ = ["background_names", "resolve_background", "load_background"]

_SOLID = {"plain": (128, 128, 128), "black": (0, 0, 0), "white": (235, 235, 235)}


def _assets() -> Path:
    return Path(str(resources.files("bodyplay") / "assets" / "backgrounds"))


def background_names() -> tuple[str, ...]:
    """Names of the shipped photos plus the solid walls (``plain``, ``black``, ``white``)."""
    photos = sorted(p.stem for p in _assets().glob("*.jpg"))
    return tuple(photos) + tuple(_SOLID)


def resolve_background(spec: str) -> str:
    """Check a background spec (name, ``#rrggbb`` or image path) and return its canonical form.

    Paths are made absolute so that meta.json can repeat the run from anywhere.
    """
    if spec in _SOLID or spec in background_names():
        return spec
    if spec.startswith("#"):
        _hex_rgb(spec)
        return spec.lower()
    p = Path(spec).expanduser()
    if p.is_file():
        return str(p.resolve())
    raise ConfigError(
        f"unknown background {spec!r}: not a shipped name ({', '.join(background_names())}), "
        "not a #rrggbb color and not an image file"
    )


def _hex_rgb(spec: str) -> tuple[int, int, int]:
    h = spec[1:]
    if len(h) != 6 or any(c not in "0123456789abcdefABCDEF" for c in h):
        raise ConfigError(f"background color {spec!r} must be #rrggbb")
    return int(h[0:2], 16), int(h[2:4], 16), int(h[4:6], 16)


def load_background(spec: str, width: int, height: int, camera_index: int = 0) -> NDArray[np.uint8]:
    """(height, width, 3) uint8 sRGB background for one camera.

    The image is scaled (area interpolation when shrinking) to cover the frame with
    5% to spare and cropped; camera ``i`` shifts the crop by ``i`` times that spare.
    """
    spec = resolve_background(spec)
    if spec in _SOLID or spec.startswith("#"):
        rgb = _SOLID[spec] if spec in _SOLID else _hex_rgb(spec)
        return np.broadcast_to(np.array(rgb, np.uint8), (height, width, 3)).copy()
    path = _assets() / f"{spec}.jpg" if "/" not in spec and "\\" not in spec else Path(spec)
    bgr = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if bgr is None:
        raise ConfigError(f"background {path}: cannot read it as an image (png, jpg, bmp ...)")
    h, w = bgr.shape[:2]
    scale = 1.05 * max(width / w, height / h)
    nw, nh = max(width, round(w * scale)), max(height, round(h * scale))
    interp = cv2.INTER_AREA if scale < 1 else cv2.INTER_LINEAR
    big = cv2.resize(bgr, (nw, nh), interpolation=interp)
    spare_x, spare_y = nw - width, nh - height
    x0 = min(spare_x, spare_x // 2 + camera_index * max(1, spare_x // 2)) if spare_x else 0
    y0 = spare_y // 2
    crop = big[y0 : y0 + height, x0 : x0 + width, ::-1]
    return np.ascontiguousarray(crop)
