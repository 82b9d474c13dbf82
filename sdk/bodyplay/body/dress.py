"""Dressing a body mesh: which surface is skin, shirt (and which patch), trousers, shoes.

The same rules dress the generic tracker mesh and the MakeHuman actor, so that the
shirt pattern of :mod:`bodyplay.body.shirt` lies on both bodies in the same places.
Rules work on points (vertices or face centroids) in the skeleton's rest T-pose
(facing +Z, Y up, arms along +-X) together with the dominant skin-weight node:

* arms: beyond the shoulder centre in |x|; hands (beyond the wrist) are skin, the
  sleeves run to the wrists; front (+Z) and back halves about the bone axis;
* shoulder caps: the top-front of the region within ``0.10 * scale`` of each
  shoulder centre (seen from the front, not from behind);
* flanks: the back-facing sides of the torso under the arms (seen from behind);
* torso quarters: front/back about the torso's centre line, left/right at x = 0,
  upper/lower at mid height between the hem and the shoulders;
* skin on the neck and head (optionally hair on the generic head), shoes on the feet,
  trousers below the hem (a little above the hip centres) and on the legs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.shirt import PATCHES, patch_colors_rgb
from bodyplay.body.skeleton import NODE_NAMES
from bodyplay.body.skinning import MATERIAL_RGB, Material

__all__ = ["TorsoProfile", "torso_profile", "dress_points", "vertex_colors"]

_N = {name: i for i, name in enumerate(NODE_NAMES)}
_PID = {p.name: p.id for p in PATCHES}
_TORSO_NODES = (_N["pelvis"], _N["lumbar"], _N["thorax"], _N["l_clavicle"], _N["r_clavicle"])
_HEAD_NODES = (_N["neck"], _N["head"], _N["head_top"])
_FOOT_NODES = (_N["l_ankle"], _N["l_toe"], _N["r_ankle"], _N["r_toe"])
_KNEE_NODES = (_N["l_knee"], _N["r_knee"])


@dataclass(frozen=True)
class TorsoProfile:
    """Torso cross-sections by height: centre z and half extents (x, z), in metres."""

    y: NDArray[np.float64]
    center_z: NDArray[np.float64]
    half_x: NDArray[np.float64]
    half_z: NDArray[np.float64]

    def at(self, y: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
        """Interpolated (center_z, half_x, half_z) at heights ``y``."""
        return (
            np.interp(y, self.y, self.center_z),
            np.interp(y, self.y, self.half_x),
            np.interp(y, self.y, self.half_z),
        )


def _scale(joints: NDArray[np.float64]) -> float:
    """Body length scale relative to the 1.75 m reference (head top at 1.74 m)."""
    return float(joints[_N["head_top"], 1] / 1.74)


def _hem(joints: NDArray[np.float64]) -> float:
    return float(joints[_N["pelvis"], 1] + 0.03 * _scale(joints))


def torso_profile(
    vertices: NDArray[np.floating], dominant: NDArray[np.integer], joints: NDArray[np.float64]
) -> TorsoProfile:
    """Measure the torso's cross-sections from the rest-pose vertices of a mesh."""
    u = _scale(joints)
    x_sh = 0.5 * (abs(joints[_N["l_shoulder"], 0]) + abs(joints[_N["r_shoulder"], 0]))
    y_sh = 0.5 * (joints[_N["l_shoulder"], 1] + joints[_N["r_shoulder"], 1])
    v = np.asarray(vertices, dtype=np.float64)
    torso = np.isin(dominant, _TORSO_NODES) & (np.abs(v[:, 0]) < x_sh - 0.02 * u)
    lo = joints[_N["pelvis"], 1] - 0.1 * u
    edges = np.arange(lo, y_sh + 0.08 * u, 0.02 * u)
    ys, zc, hx, hz = [], [], [], []
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        sel = v[torso & (v[:, 1] >= a) & (v[:, 1] < b)]
        if len(sel) < 8:
            continue
        ys.append(0.5 * (a + b))
        zc.append(0.5 * (sel[:, 2].max() + sel[:, 2].min()))
        hx.append(max(np.abs(sel[:, 0]).max(), 0.05 * u))
        hz.append(max(0.5 * (sel[:, 2].max() - sel[:, 2].min()), 0.04 * u))
    if not ys:  # no torso vertices: a nominal torso
        ys, zc, hx, hz = [lo, y_sh], [0.0, 0.0], [0.16 * u] * 2, [0.1 * u] * 2
    return TorsoProfile(np.array(ys), np.array(zc), np.array(hx), np.array(hz))


def dress_points(
    points: NDArray[np.floating],
    dominant: NDArray[np.integer],
    joints: NDArray[np.float64],
    profile: TorsoProfile,
    hair: bool = False,
) -> tuple[NDArray[np.uint8], NDArray[np.uint8]]:
    """(material, patch id) of rest-pose points given their dominant skin node.

    ``joints`` are the skeleton's rest node positions (num_nodes, 3). Patch id is 0
    for points not on the shirt.
    """
    p = np.asarray(points, dtype=np.float64)
    dom = np.asarray(dominant)
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    ax = np.abs(x)
    left = x >= 0.0
    u = _scale(joints)
    mat = np.full(len(p), Material.SHIRT, dtype=np.uint8)
    part = np.zeros(len(p), dtype=np.uint8)

    def side(name: str) -> NDArray[np.float64]:
        return np.where(left[:, None], joints[_N["l_" + name]], joints[_N["r_" + name]])

    sh, el, wr = side("shoulder"), side("elbow"), side("wrist")
    y_sh = 0.5 * (joints[_N["l_shoulder"], 1] + joints[_N["r_shoulder"], 1])
    hem = _hem(joints)

    # ---- arms (T-pose: along +-X beyond the shoulder centres) ---------------------
    arm = (ax > np.abs(sh[:, 0])) & (y > y_sh - 0.18 * u) & ~np.isin(dom, _HEAD_NODES)
    hand = arm & (ax > np.abs(wr[:, 0]))
    fore = arm & ~hand & (ax > np.abs(el[:, 0]))
    upper = arm & ~hand & ~fore
    mat[hand] = Material.SKIN

    def axis_z(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
        t = np.clip((ax - np.abs(a[:, 0])) / np.maximum(np.abs(b[:, 0] - a[:, 0]), 1e-6), 0, 1)
        return a[:, 2] + t * (b[:, 2] - a[:, 2])

    # front/back split about the sleeve's measured centre line (bone axis if too few)
    centre = np.where(fore, axis_z(el, wr), axis_z(sh, el))
    step = 0.02 * u
    for m in (left, ~left):
        sel = (fore | upper) & m
        if not sel.any():
            continue
        bins = np.floor(ax[sel] / step).astype(np.int64)
        zs = z[sel]
        lo_z = np.full(bins.max() + 1, np.inf)
        hi_z = np.full(bins.max() + 1, -np.inf)
        np.minimum.at(lo_z, bins, zs)
        np.maximum.at(hi_z, bins, zs)
        n = np.bincount(bins)
        ok = n[bins] >= 6
        with np.errstate(invalid="ignore"):
            mid = 0.5 * (lo_z + hi_z)[bins]
        c = centre[sel]
        centre[sel] = np.where(ok, mid, c)
    fore_front = z >= centre
    up_front = z >= centre
    for s, m in (("l", left), ("r", ~left)):
        part[fore & m & fore_front] = _PID[f"{s}_forearm_front"]
        part[fore & m & ~fore_front] = _PID[f"{s}_forearm_back"]
        part[upper & m & up_front] = _PID[f"{s}_upper_arm_front"]
        part[upper & m & ~up_front] = _PID[f"{s}_upper_arm_back"]

    # ---- head, feet, legs ----------------------------------------------------------
    rest = ~arm
    head = rest & np.isin(dom, _HEAD_NODES)
    mat[head] = Material.SKIN
    if hair:
        hc = joints[_N["head"]]
        top = (y > hc[1] + 0.035 * u) | ((z < hc[2] - 0.02 * u) & (y > hc[1] - 0.05 * u))
        mat[head & top & (dom != _N["neck"])] = Material.HAIR
    feet = rest & ~head & np.isin(dom, _FOOT_NODES)
    mat[feet] = Material.SHOES
    legs = rest & ~head & ~feet & ((y < hem) | np.isin(dom, _KNEE_NODES))
    mat[legs] = Material.TROUSERS

    # ---- torso ---------------------------------------------------------------------
    torso = rest & ~head & ~feet & ~legs
    zc, hx, hz = profile.at(y)
    front = z >= zc
    y_mid = 0.5 * (hem + y_sh)
    upper_half = y >= y_mid
    phi = np.degrees(np.arctan2((z - zc) / hz, ax / hx))
    flank = (
        torso
        & (y > hem + 0.3 * (y_sh - hem))
        & (y < y_sh - 0.07 * u)
        & (phi > -65.0)
        & (phi < -8.0)
        & (ax > 0.5 * hx)
    )
    quarter = torso & ~flank
    for s, m in (("left", left), ("right", ~left)):
        part[quarter & m & front & upper_half] = _PID[f"torso_front_upper_{s}"]
        part[quarter & m & front & ~upper_half] = _PID[f"torso_front_lower_{s}"]
        part[quarter & m & ~front & upper_half] = _PID[f"torso_back_upper_{s}"]
        part[quarter & m & ~front & ~upper_half] = _PID[f"torso_back_lower_{s}"]
    part[flank & left] = _PID["l_flank"]
    part[flank & ~left] = _PID["r_flank"]

    # ---- shoulder caps: top-front of each shoulder, over torso and sleeve ---------
    d = np.linalg.norm(p - sh, axis=1)
    cap = (torso | upper) & (d < 0.10 * u) & (y > sh[:, 1] - 0.01 * u) & (z > sh[:, 2] - 0.01 * u)
    part[cap & left] = _PID["l_shoulder_cap"]
    part[cap & ~left] = _PID["r_shoulder_cap"]
    part[mat != Material.SHIRT] = 0
    return mat, part


def vertex_colors(material: NDArray[np.uint8], part: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """(V, 3) base sRGB per vertex: patch color on the shirt, else the material color."""
    out = np.zeros((len(material), 3), dtype=np.uint8)
    for m, rgb in MATERIAL_RGB.items():
        out[material == m] = rgb
    shirt = part > 0
    out[shirt] = patch_colors_rgb()[part[shirt]]
    return out
