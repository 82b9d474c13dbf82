"""Occluders: an opaque panel that passes between a camera and the actor for a while.

Real captures lose the body behind furniture, a passer-by or a raised object; the
trackers must coast through it (the silhouette paper's dynamic model inflates the
variance of occluded parts). An :class:`Occlusion` is a time window; during it the
synthetic camera adds a cardboard-coloured panel, 0.55 m wide and 0.7 m tall, standing
30% of the way from the actor's chest to the first camera, so that camera loses the
torso and arms while a second camera of a pair still sees most of the body.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np
import trimesh
from numpy.typing import NDArray

from bodyplay.capture.camera import look_at
from bodyplay.errors import ConfigError

__all__ = ["Occlusion", "parse_occlusion", "PanelMesh", "occluder_panel"]

_PANEL_RGB = (0.55, 0.42, 0.28)  # brown cardboard, sRGB 0..1


@dataclass(frozen=True)
class Occlusion:
    """An occluder in front of camera 0 from ``start`` for ``seconds`` (clip time, seconds)."""

    start: float
    seconds: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.start) and self.start >= 0):
            raise ConfigError(f"occlusion start {self.start} must be a time >= 0 seconds")
        if not (math.isfinite(self.seconds) and self.seconds > 0):
            raise ConfigError(f"occlusion length {self.seconds} must be > 0 seconds")

    def active(self, t: float) -> bool:
        """Whether the occluder is in place at time ``t``."""
        return self.start <= t < self.start + self.seconds

    def __str__(self) -> str:
        return f"{self.start:g}:{self.seconds:g}"


def parse_occlusion(text: str) -> Occlusion:
    """Parse ``START:SECONDS`` (e.g. ``1.5:0.8``) into an :class:`Occlusion`."""
    m = re.fullmatch(r"\s*([0-9.eE+-]+)\s*:\s*([0-9.eE+-]+)\s*", text)
    if not m:
        raise ConfigError(f"occlusion {text!r} must be START:SECONDS, e.g. 1.5:0.8")
    try:
        return Occlusion(float(m.group(1)), float(m.group(2)))
    except ValueError:
        raise ConfigError(f"occlusion {text!r} must be START:SECONDS, e.g. 1.5:0.8") from None


@dataclass(frozen=True, eq=False)
class PanelMesh:
    """A rigid mesh in world coordinates: vertices, faces, sRGB colors 0..1, normals."""

    vertices: NDArray[np.float32]
    faces: NDArray[np.int32]
    colors: NDArray[np.float32]
    normals: NDArray[np.float32]


def occluder_panel(
    camera_center: NDArray[np.float64],
    target: NDArray[np.float64],
    fraction: float = 0.3,
    width: float = 0.55,
    height: float = 0.7,
) -> PanelMesh:
    """A box panel facing the camera, ``fraction`` of the way from ``target`` to the camera.

    Faces are split per side (flat normals) so the panel shades like a box.
    """
    center = target + fraction * (camera_center - target)
    box = trimesh.creation.box(extents=[width, height, 0.04])
    R, _ = look_at(camera_center, target)
    # Box axes: x along the camera's right, y up (camera's -y), z along the view.
    M = np.eye(4)
    M[:3, :3] = np.stack([R[0], -R[1], R[2]], axis=1)
    M[:3, 3] = center
    box.apply_transform(M)
    tri = box.vertices[box.faces]  # (F, 3, 3): unshared vertices for flat shading
    verts = tri.reshape(-1, 3).astype(np.float32)
    faces = np.arange(len(verts), dtype=np.int32).reshape(-1, 3)
    normals = np.repeat(np.asarray(box.face_normals, dtype=np.float32), 3, axis=0)
    colors = np.broadcast_to(np.array(_PANEL_RGB, np.float32), verts.shape).copy()
    return PanelMesh(verts, faces, colors, normals)
