"""``bodyplay shirt --out shirt.png``: a printable reference of the color-shirt pattern.

Draws the flat layout a tailor (or a fabric-paint session) needs to make the shirt of
the color-shirt tracker: torso front and back, both sleeves opened along their
under-seam, every patch colored with its id and color name, and a legend with the
sRGB values of the ten colors. See docs/shirt.md.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.shirt import PATCHES, SHIRT_COLORS
from bodyplay.errors import ConfigError

__all__ = ["register", "run", "draw_shirt_reference"]

_FONT = cv2.FONT_HERSHEY_SIMPLEX
_PATCH = {p.name: p for p in PATCHES}


def _bgr(rgb: tuple[int, int, int]) -> tuple[int, int, int]:
    return (int(rgb[2]), int(rgb[1]), int(rgb[0]))


def _ink(rgb: tuple[int, int, int]) -> tuple[int, int, int]:
    lum = 0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2]
    return (0, 0, 0) if lum > 140 else (255, 255, 255)


def _text(img: NDArray[np.uint8], lines: list[str], center: tuple[int, int],
          color: tuple[int, int, int], scale: float = 0.6) -> None:
    h = int(26 * scale / 0.6)
    y0 = center[1] - (len(lines) - 1) * h // 2
    for i, line in enumerate(lines):
        (w, _), _ = cv2.getTextSize(line, _FONT, scale, 2)
        cv2.putText(img, line, (center[0] - w // 2, y0 + i * h + 8), _FONT, scale, color, 2,
                    cv2.LINE_AA)


def _patch(img: NDArray[np.uint8], name: str, poly: list[tuple[int, int]]) -> None:
    p = _PATCH[name]
    col = SHIRT_COLORS[p.color]
    pts = np.array(poly, np.int32)
    cv2.fillPoly(img, [pts], _bgr(col.rgb), cv2.LINE_AA)
    cv2.polylines(img, [pts], True, (40, 40, 40), 2, cv2.LINE_AA)
    c = pts.mean(0).astype(int)
    _text(img, [str(p.id), col.name], (int(c[0]), int(c[1])), _ink(col.rgb))


def _torso(img: NDArray[np.uint8], x0: int, y0: int, back: bool) -> None:
    """Torso panel 360 x 440 px; front seen from the front, back seen from behind."""
    w, h = 360, 440
    xm, ym = x0 + w // 2, y0 + h // 2
    # image-left is the person's right on the front, the person's left on the back
    near, far = ("left", "right") if back else ("right", "left")
    kind = "back" if back else "front"
    for side, (xa, xb) in ((near, (x0, xm)), (far, (xm, x0 + w))):
        _patch(img, f"torso_{kind}_upper_{side}", [(xa, y0), (xb, y0), (xb, ym), (xa, ym)])
        _patch(img, f"torso_{kind}_lower_{side}", [(xa, ym), (xb, ym), (xb, y0 + h),
                                                  (xa, y0 + h)])
    if back:  # flanks: the back-facing sides under the arms
        fy0, fy1 = y0 + 60, y0 + h - 130
        _patch(img, "l_flank", [(x0, fy0), (x0 + 70, fy0 + 20), (x0 + 70, fy1), (x0, fy1)])
        _patch(img, "r_flank", [(x0 + w, fy0), (x0 + w - 70, fy0 + 20), (x0 + w - 70, fy1),
                                (x0 + w, fy1)])
    else:  # shoulder caps: top-front of each shoulder
        _patch(img, "r_shoulder_cap", [(x0, y0), (x0 + 95, y0), (x0 + 80, y0 + 75),
                                       (x0, y0 + 75)])
        _patch(img, "l_shoulder_cap", [(x0 + w, y0), (x0 + w - 95, y0), (x0 + w - 80, y0 + 75),
                                       (x0 + w, y0 + 75)])
    # neckline
    cv2.ellipse(img, (xm, y0), (55, 35), 0, 0, 180, (255, 255, 255), -1, cv2.LINE_AA)
    cv2.ellipse(img, (xm, y0), (55, 35), 0, 0, 180, (40, 40, 40), 2, cv2.LINE_AA)
    _text(img, ["TORSO BACK (seen from behind)" if back else "TORSO FRONT (seen from front)"],
          (xm, y0 + h + 30), (0, 0, 0), 0.6)


def _sleeve(img: NDArray[np.uint8], x0: int, y0: int, side: str) -> None:
    """A sleeve opened along its under-seam: front half above, back half below."""
    w, h = 560, 180
    xe = x0 + w // 2
    # shoulder end towards the torso: right sleeve drawn with the shoulder on the right
    sh_left = side == "l"
    xs, xw = (x0, x0 + w) if sh_left else (x0 + w, x0)
    for half, (ya, yb) in (("front", (y0, y0 + h // 2)), ("back", (y0 + h // 2, y0 + h))):
        _patch(img, f"{side}_upper_arm_{half}", [(xs, ya), (xe, ya), (xe, yb), (xs, yb)])
        _patch(img, f"{side}_forearm_{half}", [(xe, ya), (xw, ya), (xw, yb), (xe, yb)])
    who = "LEFT" if side == "l" else "RIGHT"
    _text(img, [f"{who} SLEEVE: shoulder {'<-' if sh_left else '->'}  wrist "
                f"{'->' if sh_left else '<-'}   (top: front half, bottom: back half)"],
          (x0 + w // 2, y0 + h + 28), (0, 0, 0), 0.55)


def draw_shirt_reference(width: int = 1700, height: int = 1200) -> NDArray[np.uint8]:
    """The printable pattern as a (height, width, 3) BGR image."""
    if width < 1300 or height < 1000:
        raise ConfigError("the shirt reference needs at least 1300 x 1000 pixels")
    img = np.full((height, width, 3), 255, np.uint8)
    cv2.putText(img, "bodyplay color shirt: 20 patches, 10 colors (each twice)", (40, 55),
                _FONT, 1.1, (0, 0, 0), 2, cv2.LINE_AA)
    cv2.putText(img, "front = chest side; 'left' = the wearer's left. Print at any scale; "
                "see docs/shirt.md.", (40, 90), _FONT, 0.6, (60, 60, 60), 1, cv2.LINE_AA)
    _torso(img, 60, 140, back=False)
    _torso(img, 480, 140, back=True)
    _sleeve(img, 60, 680, "r")
    _sleeve(img, 60, 940, "l")
    # legend
    lx, ly = 960, 160
    cv2.putText(img, "colors (sRGB 0-255)   patches", (lx, ly - 20), _FONT, 0.7, (0, 0, 0), 2,
                cv2.LINE_AA)
    for c in SHIRT_COLORS:
        y = ly + 56 * c.index
        cv2.rectangle(img, (lx, y), (lx + 70, y + 44), _bgr(c.rgb), -1)
        cv2.rectangle(img, (lx, y), (lx + 70, y + 44), (40, 40, 40), 2)
        ids = [p for p in PATCHES if p.color == c.index]
        label = f"{c.name:8s} {c.rgb[0]:3d},{c.rgb[1]:3d},{c.rgb[2]:3d}"
        cv2.putText(img, label, (lx + 85, y + 20), _FONT, 0.6, (0, 0, 0), 2, cv2.LINE_AA)
        cv2.putText(img, "  ".join(f"{p.id}:{p.name}" for p in ids), (lx + 85, y + 40), _FONT,
                    0.42, (50, 50, 50), 1, cv2.LINE_AA)
    return img


def run(args: argparse.Namespace) -> int:
    """Write the reference image to ``args.out``."""
    out = Path(args.out)
    if out.suffix.lower() not in (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff"):
        raise ConfigError(f"{out}: use an image file name ending in .png (or .jpg)")
    if not out.parent.exists():
        raise ConfigError(f"{out.parent}: folder does not exist; create it or choose another")
    if not cv2.imwrite(str(out), draw_shirt_reference()):
        raise ConfigError(f"{out}: could not write the image (permissions? disk full?)")
    print(f"wrote {out}")
    return 0


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add ``bodyplay shirt``."""
    p = subparsers.add_parser("shirt", help="draw the printable color-shirt pattern (PNG)",
                              description=__doc__)
    p.add_argument("--out", default="shirt.png", help="output image (default shirt.png)")
    p.set_defaults(func=run)
