"""The color shirt: 20 patches in 10 colors, each color twice (color-shirt paper).

The layout is chosen so that a camera facing the person sees each color at most
once: the front set (four torso-front quarters, the front halves of both sleeves'
upper and lower parts, and the two shoulder caps) uses all ten colors, and the back
set (four torso-back quarters, back halves of the sleeves, and the two flanks)
uses them again, arranged so that a color's two patches are on opposite sides of
the body. Torso front/back and every upper and lower arm are thus told apart.

Patch ids are 1..20 (0 is background in every id map). "Front" is +Z in the rest
pose, "left" is the person's left (+X).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["ShirtColor", "Patch", "SHIRT_COLORS", "PATCHES", "NUM_PATCHES", "NUM_COLORS",
           "patch_colors_rgb", "patch_color_index"]


@dataclass(frozen=True)
class ShirtColor:
    """One of the ten fabric colors, as sRGB 0..255 under white light."""

    index: int
    name: str
    rgb: tuple[int, int, int]


@dataclass(frozen=True)
class Patch:
    """One of the 20 patches: its id (1..20), name, color index and the bone it covers."""

    id: int
    name: str
    color: int
    bone: str


SHIRT_COLORS: tuple[ShirtColor, ...] = (
    ShirtColor(0, "red", (215, 30, 35)),
    ShirtColor(1, "orange", (245, 135, 20)),
    ShirtColor(2, "yellow", (240, 220, 35)),
    ShirtColor(3, "lime", (140, 215, 50)),
    ShirtColor(4, "green", (20, 130, 60)),
    ShirtColor(5, "cyan", (30, 190, 215)),
    ShirtColor(6, "blue", (30, 60, 195)),
    ShirtColor(7, "purple", (105, 40, 150)),
    ShirtColor(8, "magenta", (215, 45, 165)),
    ShirtColor(9, "white", (235, 235, 230)),
)
"""The ten colors; the default color model is fitted to renders of these."""

NUM_COLORS = len(SHIRT_COLORS)

PATCHES: tuple[Patch, ...] = (
    Patch(1, "torso_front_upper_left", 0, "thorax"),
    Patch(2, "torso_front_upper_right", 1, "thorax"),
    Patch(3, "torso_front_lower_left", 2, "lumbar"),
    Patch(4, "torso_front_lower_right", 3, "lumbar"),
    Patch(5, "l_upper_arm_front", 4, "l_shoulder"),
    Patch(6, "r_upper_arm_front", 5, "r_shoulder"),
    Patch(7, "l_forearm_front", 6, "l_elbow"),
    Patch(8, "r_forearm_front", 7, "r_elbow"),
    Patch(9, "l_shoulder_cap", 8, "l_clavicle"),
    Patch(10, "r_shoulder_cap", 9, "r_clavicle"),
    Patch(11, "torso_back_lower_right", 0, "lumbar"),
    Patch(12, "torso_back_lower_left", 1, "lumbar"),
    Patch(13, "torso_back_upper_right", 2, "thorax"),
    Patch(14, "torso_back_upper_left", 3, "thorax"),
    Patch(15, "r_forearm_back", 4, "r_elbow"),
    Patch(16, "l_forearm_back", 5, "l_elbow"),
    Patch(17, "r_upper_arm_back", 6, "r_shoulder"),
    Patch(18, "l_upper_arm_back", 7, "l_shoulder"),
    Patch(19, "r_flank", 8, "thorax"),
    Patch(20, "l_flank", 9, "thorax"),
)
"""The 20 patches; ``bone`` is the skeleton node whose segment the patch covers."""

NUM_PATCHES = len(PATCHES)


def patch_color_index() -> NDArray[np.int64]:
    """(21,) color index of each patch id (entry 0, the background, is -1)."""
    out = np.full(NUM_PATCHES + 1, -1, dtype=np.int64)
    for p in PATCHES:
        out[p.id] = p.color
    return out


def patch_colors_rgb() -> NDArray[np.uint8]:
    """(21, 3) sRGB color of each patch id (entry 0 black), for drawing id maps."""
    out = np.zeros((NUM_PATCHES + 1, 3), dtype=np.uint8)
    for p in PATCHES:
        out[p.id] = SHIRT_COLORS[p.color].rgb
    return out
