"""Cloth simulation pinned to the skeleton: XPBD garments on a body of capsules.

    from bodyplay.cloth import Cloth, ClothOptions, robe

    cloth = Cloth(robe(), ClothOptions())
    for joints in poses:               # (17, 3) metres, NaN or None when lost
        result = cloth.step(1 / 60, joints)
    cloth.positions, cloth.faces       # the mesh to draw

See docs/cloth.md for the model, its options and its figures.
"""

from bodyplay.cloth.body import CAPSULE_NAMES, FRAME_NAMES, BodyCapsules, body_capsules, body_frames
from bodyplay.cloth.cloth import Cloth, ClothStep
from bodyplay.cloth.garments import (
    GARMENTS,
    Garment,
    cape,
    garment,
    garment_from_trimesh,
    robe,
    skirt,
)
from bodyplay.cloth.options import ClothOptions

__all__ = [
    "CAPSULE_NAMES",
    "FRAME_NAMES",
    "GARMENTS",
    "BodyCapsules",
    "Cloth",
    "ClothOptions",
    "ClothStep",
    "Garment",
    "body_capsules",
    "body_frames",
    "cape",
    "garment",
    "garment_from_trimesh",
    "robe",
    "skirt",
]
