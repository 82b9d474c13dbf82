"""What a game draws in one frame: :class:`Scene`, a draw list with no OpenGL in it.

A game's ``draw(ctx, scene)`` fills the scene with primitives (spheres, boxes,
capsules, a floor, free meshes such as cloth), blob shadows, the player's avatar
and HUD text; the kit's renderer (:mod:`bodyplay.app.renderer`) draws it with
moderngl. Keeping the description free of GL lets game logic be tested headless
without a context and lets the same scene go to a window or to a video.

World coordinates are those of every bodyplay pose: metres, Y up, floor at Y = 0.
Colors are linear RGB floats in 0..1. HUD positions are pixels from the top-left.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.joints import BONES, JOINT_INDEX, NUM_JOINTS
from bodyplay.capture.camera import Camera, look_at
from bodyplay.errors import ConfigError

__all__ = ["Scene", "TextItem", "MeshItem", "InsetItem", "AVATAR_COLOR", "LOST_COLOR"]

Color = tuple[float, float, float]

AVATAR_COLOR: Color = (0.95, 0.55, 0.15)
"""Default avatar color (tracked joints)."""
LOST_COLOR: Color = (0.55, 0.55, 0.58)
"""Color of the bones the tracker reports ``lost`` (drawn thinner, where last seen)."""
_INFERRED_TINT = 0.45  # inferred joints: this far from the color towards white

# Rest offsets from the pelvis (m) for joints never seen (an upper-body tracker's legs):
# drawn as lost, standing straight under the hips.
_REST_FROM_PELVIS: dict[str, tuple[float, float, float]] = {
    "l_hip": (0.09, 0.0, 0.0), "r_hip": (-0.09, 0.0, 0.0),
    "l_knee": (0.1, -0.45, 0.02), "r_knee": (-0.1, -0.45, 0.02),
    "l_ankle": (0.1, -0.88, 0.0), "r_ankle": (-0.1, -0.88, 0.0),
    "spine": (0.0, 0.16, 0.0), "chest": (0.0, 0.33, 0.0), "neck": (0.0, 0.49, 0.0),
    "head": (0.0, 0.62, 0.0),
}
_BONES_LIST = [(JOINT_INDEX[a], JOINT_INDEX[b]) for a, b in BONES]


def _color(c: ArrayLike, what: str = "color") -> Color:
    """Three floats clipped to 0..1 (plain Python: scenes add thousands a second)."""
    try:
        r, g, b = (float(x) for x in c)  # type: ignore[union-attr, arg-type]
    except (TypeError, ValueError):
        raise ConfigError(f"{what} must be three RGB floats in 0..1, got {c!r}") from None
    if not (math.isfinite(r) and math.isfinite(g) and math.isfinite(b)):
        raise ConfigError(f"{what} must be three finite RGB floats, got {c!r}")
    return (min(max(r, 0.0), 1.0), min(max(g, 0.0), 1.0), min(max(b, 0.0), 1.0))


def _point(p: ArrayLike, what: str) -> tuple[float, float, float]:
    """A 3-D point as three floats (NaN allowed: lost things are skipped by callers)."""
    try:
        x, y, z = (float(v) for v in p)  # type: ignore[union-attr, arg-type]
    except (TypeError, ValueError):
        raise ConfigError(f"{what} must be a 3-D point (x, y, z) in metres, got {p!r}") from None
    return x, y, z


def _finite(p: tuple[float, float, float]) -> bool:
    return math.isfinite(p[0]) and math.isfinite(p[1]) and math.isfinite(p[2])


@dataclass(frozen=True, eq=False)
class TextItem:
    """One HUD line: ``text`` at pixel ``pos`` (anchor point), ``size`` (1 = ~22 px
    high), ``color``, ``anchor`` (``left``, ``center``, ``right``), dark ``outline``."""

    text: str
    pos: tuple[float, float]
    size: float = 1.0
    color: Color = (1.0, 1.0, 1.0)
    anchor: Literal["left", "center", "right"] = "left"
    outline: bool = True


@dataclass(frozen=True, eq=False)
class MeshItem:
    """A free triangle mesh: ``vertices`` (V, 3), ``faces`` (F, 3), ``colors`` (3,) or
    (V, 3); ``two_sided`` lights both faces (cloth), else back faces are culled."""

    vertices: NDArray[np.float32]
    faces: NDArray[np.int32]
    colors: NDArray[np.float32]
    two_sided: bool = True


@dataclass(frozen=True, eq=False)
class InsetItem:
    """An RGB picture shown over the scene in the pixel rectangle ``rect`` (x, y, w, h)
    with a ``border`` color (e.g. the camera image the tracker sees)."""

    image: NDArray[np.uint8]
    rect: tuple[int, int, int, int]
    border: Color | None = (1.0, 1.0, 1.0)


@dataclass
class Scene:
    """The draw list of one frame; the runner makes a fresh one for every frame.

    ``camera`` is a calibrated :class:`~bodyplay.capture.camera.Camera` (set it with
    :meth:`look`); ``mirror`` flips the picture left-right (a player facing the
    screen sees themselves as in a mirror); ``sky`` is the clear color.
    Instances are stored as flat arrays so that hundreds of primitives cost one
    draw call per kind.
    """

    width: int = 640
    height: int = 480
    camera: Camera | None = None
    mirror: bool = False
    sky: Color = (0.55, 0.7, 0.9)
    spheres: list[tuple[float, ...]] = field(default_factory=list)
    boxes: list[tuple[float, ...]] = field(default_factory=list)
    capsules: list[tuple[float, ...]] = field(default_factory=list)
    lines: list[tuple[float, ...]] = field(default_factory=list)
    shadows: list[tuple[float, ...]] = field(default_factory=list)
    meshes: list[MeshItem] = field(default_factory=list)
    texts: list[TextItem] = field(default_factory=list)
    insets: list[InsetItem] = field(default_factory=list)
    floor_spec: tuple[Color, Color, float, float] | None = None

    # ---- camera ----------------------------------------------------------------------
    def extend(self, other: Scene) -> None:
        """Add everything ``other`` holds (its camera and floor too, when this scene has
        none): build a game's static scenery once and add it every frame."""
        self.spheres.extend(other.spheres)
        self.boxes.extend(other.boxes)
        self.capsules.extend(other.capsules)
        self.lines.extend(other.lines)
        self.shadows.extend(other.shadows)
        self.meshes.extend(other.meshes)
        self.texts.extend(other.texts)
        self.insets.extend(other.insets)
        if self.floor_spec is None:
            self.floor_spec = other.floor_spec
        if self.camera is None:
            self.camera = other.camera
            self.mirror = other.mirror
            self.sky = other.sky

    def look(
        self,
        eye: ArrayLike,
        target: ArrayLike,
        hfov_deg: float = 60.0,
    ) -> Camera:
        """Place the view camera at ``eye`` looking at ``target`` with a horizontal
        field of view; returns (and sets) the camera."""
        if not 5.0 <= hfov_deg <= 150.0:
            raise ConfigError(f"hfov_deg must be in 5..150 degrees, got {hfov_deg}")
        R, t = look_at(_point(eye, "eye"), _point(target, "target"))
        self.camera = Camera.from_fov("view", self.width, self.height, hfov_deg, R, t)
        return self.camera

    # ---- primitives ------------------------------------------------------------------
    def sphere(
        self, center: ArrayLike, radius: float, color: ArrayLike = (0.9, 0.9, 0.9),
        *, shadow: bool = False,
    ) -> None:
        """A sphere of ``radius`` m at ``center``; ``shadow`` adds a blob shadow under it."""
        c = _point(center, "sphere center")
        if not _finite(c) or not radius > 0:
            return  # a lost or degenerate object is simply not drawn
        self.spheres.append((*c, float(radius), *_color(color)))
        if shadow:
            self.shadow(c, radius * 1.2)

    def box(
        self, center: ArrayLike, size: ArrayLike, color: ArrayLike = (0.8, 0.8, 0.8),
        *, yaw: float = 0.0,
    ) -> None:
        """An axis-aligned box (``size`` = full extents x, y, z m), turned by ``yaw``
        radians about the vertical axis."""
        c = _point(center, "box center")
        s = _point(size, "box size")
        if not (_finite(c) and min(s) > 0):
            return
        self.boxes.append((*c, *s, float(yaw), *_color(color)))

    def capsule(
        self, a: ArrayLike, b: ArrayLike, radius: float, color: ArrayLike = (0.8, 0.8, 0.8)
    ) -> None:
        """A capsule (cylinder with round ends) of ``radius`` m from ``a`` to ``b``."""
        pa, pb = _point(a, "capsule end a"), _point(b, "capsule end b")
        if not (_finite(pa) and _finite(pb)) or not radius > 0:
            return
        self.capsules.append((*pa, *pb, float(radius), *_color(color)))

    def line(self, a: ArrayLike, b: ArrayLike, color: ArrayLike = (1, 1, 1)) -> None:
        """A one-pixel unlit line from ``a`` to ``b`` (nets, guides; far cheaper than
        a capsule: use :meth:`capsule` for rods that must look round)."""
        pa, pb = _point(a, "line end a"), _point(b, "line end b")
        if not (_finite(pa) and _finite(pb)):
            return
        self.lines.append((*pa, *pb, *_color(color)))

    def floor(
        self,
        color: ArrayLike = (0.33, 0.55, 0.3),
        color2: ArrayLike | None = (0.3, 0.5, 0.27),
        size: float = 30.0,
        tile: float = 1.0,
    ) -> None:
        """The floor (Y = 0), ``size`` m square around the origin, checkered in tiles
        of ``tile`` m with ``color2`` (None: plain)."""
        c1 = _color(color, "floor color")
        c2 = c1 if color2 is None else _color(color2, "floor color2")
        if not (size > 0 and tile > 0):
            raise ConfigError("floor size and tile must be positive metres")
        self.floor_spec = (c1, c2, float(size), float(tile))

    def shadow(self, center: ArrayLike, radius: float, strength: float = 0.45) -> None:
        """A soft dark disc on the floor under ``center`` (its x, z); it fades as
        the object rises (``strength`` at the floor, 0..1)."""
        c = _point(center, "shadow center")
        if not _finite(c) or not radius > 0:
            return
        height = max(c[1], 0.0)
        fade = float(strength) / (1.0 + 0.6 * height)
        self.shadows.append((c[0], c[2], float(radius) * (1.0 + 0.15 * height), fade))

    def mesh(
        self,
        vertices: ArrayLike,
        faces: ArrayLike,
        color: ArrayLike = (0.8, 0.2, 0.2),
        *,
        two_sided: bool = True,
    ) -> None:
        """A triangle mesh in world metres (cloth, a goal net, a level's geometry);
        ``color`` is one RGB or (V, 3) per vertex; ``two_sided`` shades both faces."""
        v = np.ascontiguousarray(vertices, dtype=np.float32)
        f = np.ascontiguousarray(faces, dtype=np.int32)
        if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3:
            raise ConfigError(f"mesh needs vertices (V, 3) and faces (F, 3), got {v.shape} "
                              f"and {f.shape}")
        if f.size and (f.min() < 0 or f.max() >= len(v)):
            raise ConfigError(f"mesh faces index vertices outside 0..{len(v) - 1}")
        c = np.asarray(color, dtype=np.float32)
        if c.shape == (3,):
            c = np.broadcast_to(c, v.shape)
        if c.shape != v.shape:
            raise ConfigError(f"mesh color must be (3,) or {v.shape}, got {c.shape}")
        self.meshes.append(MeshItem(v, f, np.ascontiguousarray(c), bool(two_sided)))

    # ---- the player ------------------------------------------------------------------
    def avatar(
        self,
        joints: ArrayLike,
        state: Sequence[str] | None = None,
        color: ArrayLike = AVATAR_COLOR,
        *,
        lost_color: ArrayLike = LOST_COLOR,
        radius: float = 0.045,
        shadow: bool = True,
        last_seen: ArrayLike | None = None,
    ) -> None:
        """The player as a capsule figure from (17, 3) ``joints``.

        Bones between ``tracked`` joints get ``color``, ``inferred`` ones a paler
        tint; a bone touching a ``lost`` joint is drawn thin in ``lost_color`` where
        the joint was ``last_seen`` ((17, 3), NaN where never seen), or, for joints
        never seen (an upper-body tracker's legs), standing straight under the
        pelvis. A lost player with nothing to show draws nothing.
        """
        j = np.array(joints, dtype=np.float64, copy=True)
        if j.shape != (NUM_JOINTS, 3):
            raise ConfigError(f"avatar joints must have shape ({NUM_JOINTS}, 3), got {j.shape}")
        finite = np.asarray(np.isfinite(j).all(axis=1), dtype=bool)
        st = list(state) if state is not None else [
            "tracked" if ok else "lost" for ok in finite.tolist()
        ]
        if len(st) != NUM_JOINTS:
            raise ConfigError(f"avatar state needs {NUM_JOINTS} entries, got {len(st)}")
        lost = np.array([s == "lost" for s in st]) | ~finite
        if last_seen is not None:
            ls = np.asarray(last_seen, dtype=np.float64)
            fill = lost & np.isfinite(ls).all(axis=1)
            j[fill] = ls[fill]
        pelvis = j[JOINT_INDEX["pelvis"]]
        has_pelvis = bool(np.isfinite(pelvis).all())
        if has_pelvis:
            missing = np.asarray(~np.isfinite(j).all(axis=1), dtype=bool)
            for name, off in _REST_FROM_PELVIS.items():
                i = JOINT_INDEX[name]
                if missing[i]:
                    j[i] = pelvis + np.asarray(off)
        col = _color(color)
        pale = _color([c + _INFERRED_TINT * (1.0 - c) for c in col])
        lcol = _color(lost_color, "lost_color")
        inferred = [s == "inferred" for s in st]
        lost_l = lost.tolist()
        pts = j.tolist()
        for a, b in _BONES_LIST:
            if lost_l[a] or lost_l[b]:
                self.capsule(pts[a], pts[b], radius * 0.55, lcol)
            else:
                c = pale if (inferred[a] or inferred[b]) else col
                self.capsule(pts[a], pts[b], radius, c)
        head = JOINT_INDEX["head"]
        if lost_l[head]:
            self.sphere(pts[head], 0.09, lcol)
        else:
            self.sphere(pts[head], 0.11, pale if inferred[head] else col)
        for name in ("l_wrist", "r_wrist"):
            i = JOINT_INDEX[name]
            if not lost_l[i]:
                self.sphere(pts[i], radius * 1.5, pale if inferred[i] else col)
        if shadow and has_pelvis:
            self.shadow((pelvis[0], 0.0, pelvis[2]), 0.35, 0.5)

    # ---- HUD -------------------------------------------------------------------------
    def text(
        self,
        line: str,
        pos: tuple[float, float] = (12.0, 28.0),
        size: float = 1.0,
        color: ArrayLike = (1.0, 1.0, 1.0),
        *,
        anchor: Literal["left", "center", "right"] = "left",
        outline: bool = True,
    ) -> None:
        """A HUD line at pixel ``pos`` (its baseline anchor) in the picture."""
        if anchor not in ("left", "center", "right"):
            raise ConfigError(f"text anchor must be left, center or right, got {anchor!r}")
        if not (math.isfinite(size) and 0.1 <= size <= 10.0):
            raise ConfigError(f"text size must be in 0.1..10, got {size}")
        self.texts.append(TextItem(str(line), (float(pos[0]), float(pos[1])), float(size),
                                   _color(color), anchor, bool(outline)))

    def inset(
        self, image: ArrayLike, rect: tuple[int, int, int, int],
        border: ArrayLike | None = (1.0, 1.0, 1.0),
    ) -> None:
        """Show an RGB uint8 ``image`` scaled into the pixel rectangle (x, y, w, h)."""
        img = np.asarray(image)
        if img.dtype != np.uint8 or img.ndim != 3 or img.shape[2] != 3:
            raise ConfigError(f"inset image must be (H, W, 3) uint8 RGB, got {img.dtype} "
                              f"{img.shape}")
        x, y, w, h = (int(v) for v in rect)
        if w < 2 or h < 2:
            raise ConfigError(f"inset rect must be at least 2x2 pixels, got {rect}")
        self.insets.append(InsetItem(img, (x, y, w, h),
                                     None if border is None else _color(border, "border")))

    @property
    def empty(self) -> bool:
        """Whether nothing 3-D was added."""
        return not (self.spheres or self.boxes or self.capsules or self.lines or self.meshes
                    or self.floor_spec or self.shadows)
