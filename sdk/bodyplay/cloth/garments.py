"""Garments: a cloth mesh in the skeleton's rest pose and the particles pinned to the body.

The builders make three garments from a few parameters, each a few thousand particles:

* :func:`robe`: a sleeveless robe to below the knees, hanging from the neckline and
  the shoulders (pinned to the ``torso`` frame), with arm holes;
* :func:`cape`: a flared sheet behind the back, its top edge pinned across the
  shoulders;
* :func:`skirt`: a flared skirt to the knees, its waistband pinned to the ``hips`` frame.

Any other mesh works too (:func:`garment_from_trimesh`): give its vertices in the
rest pose of a :class:`~bodyplay.body.Skeleton` and say which vertices are pinned.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.joints import JOINT_INDEX, NUM_JOINTS
from bodyplay.body.shapes import BodyShape
from bodyplay.body.skeleton import Skeleton
from bodyplay.cloth.body import FRAME_NAMES, body_frames
from bodyplay.errors import ConfigError

__all__ = ["GARMENTS", "Garment", "cape", "garment", "garment_from_trimesh", "robe", "skirt"]


@dataclass(frozen=True, eq=False)
class Garment:
    """A cloth mesh ready to simulate.

    ``vertices`` (N, 3) are world metres with the body in ``rest_joints`` (17, 3),
    ``faces`` (F, 3) index them; ``pins`` (P,) are the pinned vertices and
    ``pin_frames`` (P,) the FRAME_NAMES index each follows; ``color`` is an RGB
    triple 0..1 for renderers. Validated on creation (ConfigError).
    """

    name: str
    vertices: NDArray[np.float64]
    faces: NDArray[np.int64]
    pins: NDArray[np.int64]
    pin_frames: NDArray[np.int64]
    rest_joints: NDArray[np.float64]
    color: tuple[float, float, float] = (0.7, 0.2, 0.2)

    def __post_init__(self) -> None:
        v = np.ascontiguousarray(self.vertices, dtype=np.float64)
        f = np.ascontiguousarray(self.faces, dtype=np.int64)
        p = np.ascontiguousarray(self.pins, dtype=np.int64).reshape(-1)
        pf = np.ascontiguousarray(self.pin_frames, dtype=np.int64).reshape(-1)
        j = np.ascontiguousarray(self.rest_joints, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 3 or len(v) < 3 or not np.all(np.isfinite(v)):
            raise ConfigError(f"garment {self.name!r}: vertices must be finite (N >= 3, 3), "
                              f"got shape {v.shape}")
        if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
            raise ConfigError(f"garment {self.name!r}: faces must have shape (F, 3), got {f.shape}")
        if f.min() < 0 or f.max() >= len(v):
            raise ConfigError(f"garment {self.name!r}: faces index vertices outside "
                              f"0..{len(v) - 1}")
        if len(p) != len(pf):
            raise ConfigError(f"garment {self.name!r}: pins and pin_frames differ in length")
        if len(p) and (p.min() < 0 or p.max() >= len(v) or len(np.unique(p)) != len(p)):
            raise ConfigError(f"garment {self.name!r}: pins must be distinct vertex indices")
        if len(pf) and (pf.min() < 0 or pf.max() >= len(FRAME_NAMES)):
            raise ConfigError(f"garment {self.name!r}: pin_frames must index {FRAME_NAMES}")
        if j.shape != (NUM_JOINTS, 3) or not np.all(np.isfinite(j)):
            raise ConfigError(f"garment {self.name!r}: rest_joints must be finite "
                              f"({NUM_JOINTS}, 3), got {j.shape}")
        for name, arr in (("vertices", v), ("faces", f), ("pins", p), ("pin_frames", pf),
                          ("rest_joints", j)):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    @property
    def num_particles(self) -> int:
        """Number of particles (mesh vertices)."""
        return int(len(self.vertices))

    def pin_offsets(self) -> NDArray[np.float64]:
        """(P, 3) each pinned vertex in its frame's coordinates (rest pose)."""
        origins, rots = body_frames(self.rest_joints)
        d = self.vertices[self.pins] - origins[self.pin_frames]
        return np.einsum("pji,pj->pi", rots[self.pin_frames], d)


def _rest_joints(shape: str | BodyShape) -> NDArray[np.float64]:
    skel = Skeleton.from_shape(shape)
    return skel.joint_positions(skel.rest_pose())


def _profile_rows(control: list[tuple[float, float, float]], rows: int
                  ) -> NDArray[np.float64]:
    """(rows, 3) (y, half-width, half-depth) spaced evenly along the profile's length."""
    c = np.asarray(control, dtype=np.float64)
    seg = np.hypot(np.diff(c[:, 0]), np.diff(0.5 * (c[:, 1] + c[:, 2])))
    s = np.concatenate([[0.0], np.cumsum(seg)])
    t = np.linspace(0.0, s[-1], rows)
    return np.stack([np.interp(t, s, c[:, k]) for k in range(3)], axis=1)


def _tube(profile: NDArray[np.float64], columns: int, center: tuple[float, float],
          keep_face: NDArray[np.bool_] | None = None
          ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """A closed-around, open-ended tube of elliptic rings; faces of ``keep_face`` only."""
    rows = len(profile)
    th = 2.0 * np.pi * np.arange(columns) / columns
    x = center[0] + profile[:, 1:2] * np.cos(th)[None]
    z = center[1] + profile[:, 2:3] * np.sin(th)[None]
    y = np.repeat(profile[:, 0:1], columns, axis=1)
    verts = np.stack([x, y, z], axis=2).reshape(-1, 3)
    r, c = np.meshgrid(np.arange(rows - 1), np.arange(columns), indexing="ij")
    i00 = r * columns + c
    i01 = r * columns + (c + 1) % columns
    i10 = i00 + columns
    i11 = i01 + columns
    quads = np.stack([i00, i01, i10, i11], axis=-1)
    # alternate the diagonal in a checkerboard so the cloth has no preferred shear
    flip = ((r + c) % 2).astype(bool)
    if keep_face is not None:
        quads, flip = quads[keep_face], flip[keep_face]
    quads, flip = quads.reshape(-1, 4), flip.reshape(-1)
    faces = np.concatenate([
        np.where(flip[:, None], quads[:, [0, 2, 3]], quads[:, [0, 2, 1]]),
        np.where(flip[:, None], quads[:, [0, 3, 1]], quads[:, [1, 2, 3]]),
    ])
    return verts, faces


def _compact(verts: NDArray[np.float64], faces: NDArray[np.int64], pinned: NDArray[np.bool_]
             ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]]:
    used = np.zeros(len(verts), dtype=bool)
    used[faces.reshape(-1)] = True
    new = np.cumsum(used) - 1
    return verts[used], new[faces], np.flatnonzero(pinned[used])


def _scale(resolution: float) -> float:
    if not (isinstance(resolution, int | float) and 0.2 <= float(resolution) <= 4.0):
        raise ConfigError(f"garment resolution must be in 0.2..4 (1 = about 2,500 particles), "
                          f"got {resolution!r}")
    return float(resolution)


def robe(shape: str | BodyShape = "m", resolution: float = 1.0,
         color: tuple[float, float, float] = (0.55, 0.16, 0.20)) -> Garment:
    """A sleeveless robe to below the knees for a body preset (about 2,600 particles).

    ``resolution`` scales the particle spacing (particles grow with its square).
    The neckline and shoulder rows are pinned to the torso frame; arm holes let the
    arms through.
    """
    k = _scale(resolution)
    j = _rest_joints(shape)
    ys = float(j[JOINT_INDEX["l_shoulder"], 1])
    yp = float(j[JOINT_INDEX["pelvis"], 1])
    yk = float(j[JOINT_INDEX["l_knee"], 1])
    w = abs(float(j[JOINT_INDEX["l_shoulder"], 0])) / 0.185  # breadth of the body
    control = [(ys + 0.080, 0.10 * w, 0.085), (ys + 0.075, 0.20 * w, 0.13),
               (ys + 0.050, 0.255 * w, 0.15), (ys - 0.05, 0.245 * w, 0.16),
               (ys - 0.20, 0.205 * w, 0.16), (yp + 0.05, 0.215 * w, 0.165),
               (yp - 0.10, 0.245 * w, 0.18), (yk - 0.12, 0.33 * w, 0.26)]
    columns, rows = int(round(48 * k)), int(round(56 * k))
    prof = _profile_rows(control, rows)
    th = 2.0 * np.pi * (np.arange(columns) + 0.5) / columns
    ymid = 0.5 * (prof[:-1, 0] + prof[1:, 0])
    hole_rows = (ymid < ys + 0.06) & (ymid > ys - 0.19)
    keep = ~(hole_rows[:, None] & (np.abs(np.cos(th))[None] > 0.8))
    zc = float(0.5 * (j[JOINT_INDEX["neck"], 2] + j[JOINT_INDEX["pelvis"], 2]))
    verts, faces = _tube(prof, columns, (0.0, zc), keep)
    pinned = np.zeros(len(verts), dtype=bool)
    pinned[: 2 * columns] = True
    v, f, pins = _compact(verts, faces, pinned)
    return Garment("robe", v, f, pins, np.zeros(len(pins), dtype=np.int64), j, color)


def cape(shape: str | BodyShape = "m", resolution: float = 1.0,
         color: tuple[float, float, float] = (0.15, 0.22, 0.55)) -> Garment:
    """A cape from the shoulders to the calves, flaring behind the back (2,400 particles).

    Its top edge is pinned across the back of the shoulders (torso frame).
    """
    k = _scale(resolution)
    j = _rest_joints(shape)
    ys = float(j[JOINT_INDEX["l_shoulder"], 1])
    zb = float(j[JOINT_INDEX["neck"], 2])
    w = abs(float(j[JOINT_INDEX["l_shoulder"], 0])) / 0.185
    columns, rows = int(round(40 * k)), int(round(60 * k))
    s = np.linspace(0.0, 1.0, rows)[:, None]  # 0 at the top edge
    u = np.linspace(-0.5, 0.5, columns)[None]
    width = (0.44 + 0.5 * s) * w
    x = u * width
    y = (ys + 0.07) - s * (ys + 0.07 - 0.35 * ys / 1.42)
    # the top edge wraps a little round the shoulders, the rest hangs behind the back
    z = zb - 0.075 - 0.12 * np.sqrt(s) + 0.05 * (1.0 - s) ** 4 * (2.0 * u) ** 2
    z = np.broadcast_to(z, (rows, columns))
    verts = np.stack([x, np.broadcast_to(y, x.shape), z], axis=2).reshape(-1, 3)
    r, c = np.meshgrid(np.arange(rows - 1), np.arange(columns - 1), indexing="ij")
    i00 = (r * columns + c).reshape(-1)
    i01, i10 = i00 + 1, i00 + columns
    i11 = i10 + 1
    flip = ((r + c) % 2).astype(bool).reshape(-1)[:, None]
    faces = np.concatenate([
        np.where(flip, np.stack([i00, i10, i11], 1), np.stack([i00, i10, i01], 1)),
        np.where(flip, np.stack([i00, i11, i01], 1), np.stack([i01, i10, i11], 1)),
    ])
    pins = np.arange(columns)
    return Garment("cape", verts, faces, pins, np.zeros(columns, dtype=np.int64), j, color)


def skirt(shape: str | BodyShape = "m", resolution: float = 1.0,
          color: tuple[float, float, float] = (0.12, 0.45, 0.30)) -> Garment:
    """A flared skirt from the waist to the knees (about 2,400 particles).

    The waistband (two rows) is pinned to the hips frame.
    """
    k = _scale(resolution)
    j = _rest_joints(shape)
    yp = float(j[JOINT_INDEX["pelvis"], 1])
    yk = float(j[JOINT_INDEX["l_knee"], 1])
    w = abs(float(j[JOINT_INDEX["l_hip"], 0])) / 0.09
    control = [(yp + 0.12, 0.185 * w, 0.13), (yp + 0.0, 0.215 * w, 0.15),
               (yk - 0.02, 0.34 * w, 0.30)]
    columns, rows = int(round(80 * k)), int(round(30 * k))
    prof = _profile_rows(control, rows)
    verts, faces = _tube(prof, columns, (0.0, float(j[JOINT_INDEX["pelvis"], 2])))
    pins = np.arange(2 * columns)
    return Garment("skirt", verts, faces, pins, np.ones(len(pins), dtype=np.int64), j, color)


GARMENTS = {"robe": robe, "cape": cape, "skirt": skirt}
"""The garment builders by name."""


def garment(name: str, shape: str | BodyShape = "m", resolution: float = 1.0) -> Garment:
    """Build a garment by name (``robe``, ``cape`` or ``skirt``) for a body preset."""
    try:
        build = GARMENTS[name]
    except (KeyError, TypeError):
        raise ConfigError(f"unknown garment {name!r}; choose one of {', '.join(GARMENTS)}"
                          ) from None
    return build(shape, resolution)


def garment_from_trimesh(mesh: trimesh.Trimesh, pins: ArrayLike, frame: str = "torso",
                         shape: str | BodyShape = "m", name: str = "garment",
                         color: tuple[float, float, float] = (0.6, 0.6, 0.6)) -> Garment:
    """A garment from any trimesh laid on the rest pose of ``shape``'s skeleton.

    ``pins``: the vertex indices pinned to ``frame`` (``torso`` or ``hips``).
    """
    if frame not in FRAME_NAMES:
        raise ConfigError(f"unknown frame {frame!r}; choose one of {', '.join(FRAME_NAMES)}")
    p = np.asarray(pins, dtype=np.int64).reshape(-1)
    return Garment(name, np.asarray(mesh.vertices), np.asarray(mesh.faces), p,
                   np.full(len(p), FRAME_NAMES.index(frame), dtype=np.int64),
                   _rest_joints(shape), color)
