"""Retargeting motion capture onto the bodyplay skeleton.

Two steps. First the source (a :class:`~bodyplay.motion.bvh.BVHClip`) is mapped onto
the 17 joints of DESIGN.md: a :class:`JointMapping` names the source joints that are
the shoulder, elbow, wrist, hip, knee and ankle centres and the head; ``pelvis`` and
``neck`` are the midpoints of the hips and shoulders, ``spine``/``chest`` lie at one
and two thirds between them, and the head centre is estimated on the line from the
source Head joint to its End Site. The up axis is detected (the trunk's direction),
the source's standing height is measured (units are never assumed), positions are
scaled to the target skeleton's height and the floor is put at Y = 0.

Second, :func:`poses_from_joints` solves pose vectors analytically so that the
skeleton's bones point where the source's do: pelvis and chest orientations from the
hips and shoulders lines and the trunk axis (the chest's turn relative to the pelvis
is split between lumbar and thorax), the neck swings towards the head, elbows and
knees are hinges whose bend plane fixes the twist of the upper arm and thigh, and
the optional hands, toes and head top swing the wrists, ankles and head. The same
solver exports tracked joints (with NaN for lost ones) to BVH.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from bodyplay.body.joints import JOINT_INDEX, JOINT_NAMES, NUM_JOINTS
from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.motion.bvh import BVHClip
from bodyplay.motion.mapping import LIMB_KEYS, JointMapping, mapping_for
from bodyplay.optiontypes import check_option_types

if TYPE_CHECKING:
    from bodyplay.motion.clip import MotionClip

__all__ = [
    "EXTRA_POINTS",
    "RetargetOptions",
    "SourceInfo",
    "analyze_source",
    "poses_from_joints",
    "retarget",
    "source_joints",
]

EXTRA_POINTS = ("l_hand", "r_hand", "l_toe", "r_toe", "head_top")
"""Optional points besides the 17 joints that orient wrists, ankles and the head."""


# ---- source analysis --------------------------------------------------------------


@dataclass(frozen=True)
class SourceInfo:
    """What retargeting measured about a source clip.

    ``up_axis`` is e.g. ``"+Y"``; ``height`` is the standing height in source units
    (measured, never assumed), ``units`` a guess from it (``"m"``, ``"cm"``, ``"mm"``,
    ``"inch"`` or ``"unknown"``); ``floor`` the floor level (source units, along up);
    ``head_offset`` how far along the head axis (from the Head joint towards its End
    Site) the head centre lies, source units; ``leg_length`` the hip-centre height
    when standing, source units.
    """

    mapping: JointMapping
    up_axis: str
    rotation: NDArray[np.float64] = field(repr=False)
    height: float
    units: str
    floor: float
    leg_length: float
    head_offset: float


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-12)


def _raw_points(
    clip: BVHClip, mapping: JointMapping, frames: ArrayLike | slice | None
) -> dict[str, NDArray[np.float64]]:
    """Source-unit, source-axes positions of the mapped joints and extras.

    ``head_axis`` holds unit vectors along the head: towards the Head's End Site,
    or, when that is missing or of zero length (as in some Bandai Namco files),
    continuing the neck bone in the Head joint's frame.
    """
    G_rot, G_pos = clip.global_transforms(frames)
    pts = {k: G_pos[:, clip.index(v)] for k, v in mapping.joints.items() if v in clip.names}
    h = clip.index(mapping.joints["head"])

    def end_point(j: int) -> NDArray[np.float64] | None:
        e = clip.end_site_of(j)
        if e is None or np.linalg.norm(clip.end_sites[e].offset) < 1e-9:
            return None
        return G_pos[:, j] + G_rot[:, j] @ np.asarray(clip.end_sites[e].offset)

    end = end_point(h)
    if end is not None:
        axis = end - pts["head"]
    elif np.linalg.norm(clip.offsets[h]) > 1e-9 and clip.parents[h] >= 0:
        axis = G_rot[:, h] @ clip.offsets[h]
    else:
        axis = pts["head"] - 0.5 * (pts["l_shoulder"] + pts["r_shoulder"])
    pts["head_axis"] = _unit(axis)
    if end is not None:
        pts["head_len"] = np.linalg.norm(axis, axis=-1)
    for side in ("l", "r"):  # fall back to the wrist's / ankle's End Site for hand / toe
        for joint, tip_name in (("wrist", "hand"), ("ankle", "toe")):
            if f"{side}_{tip_name}" not in pts:
                tip = end_point(clip.index(mapping.joints[f"{side}_{joint}"]))
                if tip is not None:
                    pts[f"{side}_{tip_name}"] = tip
    return pts


_AXES = ("+X", "+Y", "+Z", "-X", "-Y", "-Z")


def analyze_source(
    clip: BVHClip, skeleton: Skeleton | None = None, mapping: JointMapping | None = None
) -> SourceInfo:
    """Detect the mapping, up axis, standing height, units, floor and head centre.

    Height is the median over the clip of the (rotation-invariant) leg and trunk
    lengths, completed by the reference skeleton's head and foot proportions.
    """
    skeleton = skeleton or Skeleton()
    mapping = mapping_for(clip, mapping)
    step = max(1, clip.num_frames // 400)
    pts = _raw_points(clip, mapping, slice(None, None, step))
    pelvis = 0.5 * (pts["l_hip"] + pts["r_hip"])
    neck = 0.5 * (pts["l_shoulder"] + pts["r_shoulder"])
    trunk = np.median(_unit(neck - pelvis), axis=0)
    k = int(np.argmax(np.abs(trunk)))
    up = np.zeros(3)
    up[k] = np.sign(trunk[k])
    name = ("+" if up[k] > 0 else "-") + "XYZ"[k]
    # a proper rotation taking the source up axis onto +Y
    if name == "+Y":
        A = np.eye(3)
    else:
        rv = np.cross(up, [0.0, 1.0, 0.0])
        if np.linalg.norm(rv) < 1e-9:
            rv = np.array([0.0, 0.0, np.pi])  # -Y: turn over about Z
        else:
            rv = rv / np.linalg.norm(rv) * np.pi / 2
        A = Rotation.from_rotvec(rv).as_matrix()

    def dist(a: str, b: str) -> float:
        return float(np.median(np.linalg.norm(pts[a] - pts[b], axis=-1)))

    leg = 0.5 * (dist("l_hip", "l_knee") + dist("l_knee", "l_ankle"))
    leg += 0.5 * (dist("r_hip", "r_knee") + dist("r_knee", "r_ankle"))
    leg /= 1.0
    trunk_len = float(np.median(np.linalg.norm(neck - pelvis, axis=-1)))
    ours = skeleton.joint_positions(skeleton.rest_pose())
    o_leg = float(
        np.linalg.norm(ours[JOINT_INDEX["l_hip"]] - ours[JOINT_INDEX["l_knee"]])
        + np.linalg.norm(ours[JOINT_INDEX["l_knee"]] - ours[JOINT_INDEX["l_ankle"]])
    )
    o_trunk = float(np.linalg.norm(ours[JOINT_INDEX["neck"]] - ours[JOINT_INDEX["pelvis"]]))
    height = (leg + trunk_len) * skeleton.shape.height / (o_leg + o_trunk)
    units = "unknown"
    for u, per_m in (("m", 1.0), ("inch", 39.37), ("cm", 100.0), ("mm", 1000.0)):
        if 1.3 * per_m <= height <= 2.2 * per_m:
            units = u
            break

    # floor: low percentile of the lowest foot point, along up
    up_of = {key: v @ A.T for key, v in pts.items() if v.ndim == 2}
    feet = [up_of[f"{s}_{p}"][:, 1] for s in "lr" for p in ("ankle", "toe") if f"{s}_{p}" in pts]
    lowest = np.min(np.stack(feet), axis=0)
    floor = float(np.percentile(lowest, 5))
    ankle_h = float(
        np.percentile(np.concatenate([up_of["l_ankle"][:, 1], up_of["r_ankle"][:, 1]]), 5) - floor
    )
    ankle_h = max(ankle_h, 0.0)
    leg_length = leg + ankle_h

    # head centre: on the head axis, where our proportions put it from the neck
    o_head = float(np.linalg.norm(ours[JOINT_INDEX["head"]] - ours[JOINT_INDEX["neck"]]))
    want = o_head * height / skeleton.shape.height
    top = float(np.median(pts["head_len"])) if "head_len" in pts else want
    ds = np.linspace(0.0, top, 41)
    d = [np.median(np.linalg.norm(pts["head"] + t * pts["head_axis"] - neck, axis=-1)) for t in ds]
    head_offset = float(ds[int(np.argmin(np.abs(np.asarray(d) - want)))])
    return SourceInfo(mapping, name, A, height, units, floor, leg_length, head_offset)


def source_joints(
    clip: BVHClip,
    info: SourceInfo,
    skeleton: Skeleton,
    frames: ArrayLike | slice | None = None,
) -> tuple[NDArray[np.float64], dict[str, NDArray[np.float64]], NDArray[np.float64]]:
    """The source's 17 joints normalized: Y up, floor at 0, scaled to the skeleton's height.

    Returns ``(joints (T, 17, 3), extras {name: (T, 3)}, pelvis (T, 3))``; the last is
    the source pelvis, Y up with the floor at 0, in source units (for root motion).
    """
    pts = _raw_points(clip, info.mapping, frames)
    A = info.rotation
    up = {k: v @ A.T for k, v in pts.items() if v.ndim == 2}
    s = skeleton.shape.height / info.height
    pelvis = 0.5 * (up["l_hip"] + up["r_hip"])
    neck = 0.5 * (up["l_shoulder"] + up["r_shoulder"])
    head = up["head"] + info.head_offset * up["head_axis"]
    T = pelvis.shape[0]
    J = np.empty((T, NUM_JOINTS, 3))
    J[:, JOINT_INDEX["pelvis"]] = pelvis
    J[:, JOINT_INDEX["neck"]] = neck
    J[:, JOINT_INDEX["spine"]] = pelvis + (neck - pelvis) / 3.0
    J[:, JOINT_INDEX["chest"]] = pelvis + 2.0 * (neck - pelvis) / 3.0
    J[:, JOINT_INDEX["head"]] = head
    for key in LIMB_KEYS:
        J[:, JOINT_INDEX[key]] = up[key]
    floor = np.array([0.0, info.floor, 0.0])
    J = (J - floor) * s
    extras: dict[str, NDArray[np.float64]] = {
        k: (up[k] - floor) * s for k in ("l_hand", "r_hand", "l_toe", "r_toe") if k in up
    }
    extras["head_top"] = J[:, JOINT_INDEX["head"]] + up["head_axis"] * 0.1
    return J, extras, pelvis - floor


# ---- the solver -------------------------------------------------------------------


def _frame(x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
    """(..., 3, 3) rotation whose columns are x, y orthogonalized against x, and x cross y."""
    xh = _unit(x)
    yh = _unit(y - np.sum(y * xh, axis=-1, keepdims=True) * xh)
    return np.stack([xh, yh, np.cross(xh, yh)], axis=-1)


def _rotvec(R: NDArray[np.float64]) -> NDArray[np.float64]:
    flat = R.reshape(-1, 3, 3)
    out = np.full((flat.shape[0], 3), np.nan)
    ok = np.all(np.isfinite(flat), axis=(1, 2))
    if np.any(ok):
        out[ok] = Rotation.from_matrix(flat[ok]).as_rotvec()
    return out.reshape(R.shape[:-2] + (3,))


def _mat(rv: NDArray[np.float64]) -> NDArray[np.float64]:
    return Rotation.from_rotvec(rv.reshape(-1, 3)).as_matrix().reshape(rv.shape[:-1] + (3, 3))


def _fill(rv: NDArray[np.float64]) -> NDArray[np.float64]:
    """Forward-fill rows with NaN from the last valid row (zero before the first)."""
    ok = np.all(np.isfinite(rv), axis=-1)
    if np.all(ok):
        return rv
    idx = np.where(ok, np.arange(len(rv)), -1)
    idx = np.maximum.accumulate(idx)
    out = np.where((idx >= 0)[:, None], rv[np.maximum(idx, 0)], 0.0)
    return out


def _swing(rest_dir: NDArray[np.float64], target_local: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation vectors of the smallest rotations taking rest_dir onto target_local."""
    a = _unit(np.broadcast_to(rest_dir, target_local.shape))
    b = _unit(target_local)
    axis = np.cross(a, b)
    s = np.linalg.norm(axis, axis=-1, keepdims=True)
    c = np.sum(a * b, axis=-1, keepdims=True)
    ang = np.arctan2(s, c)
    alt = np.cross(a, np.array([0.0, 0.0, 1.0]))
    alt = np.where(
        np.linalg.norm(alt, axis=-1, keepdims=True) < 1e-6, np.cross(a, [1.0, 0, 0]), alt
    )
    axis = np.where(s < 1e-9, alt, axis)
    return _unit(axis) * ang


def _neutral(
    rest_dir: NDArray[np.float64], d: NDArray[np.float64], enabled: bool
) -> NDArray[np.float64]:
    """The rest direction to swing from: the skeleton's, or the median of d (finite rows)."""
    if not enabled:
        return rest_dir
    ok = np.all(np.isfinite(d), axis=-1) & (np.linalg.norm(d, axis=-1) > 1e-9)
    if not np.any(ok):
        return rest_dir
    m = np.median(_unit(d[ok]), axis=0)
    return m if np.linalg.norm(m) > 1e-6 else rest_dir


def _hinge_axis(
    lo: NDArray[np.float64], hi: NDArray[np.float64]
) -> tuple[NDArray[np.float64], float]:
    """The local axis a hinge (elbow, knee) bends about, with the sign of a positive bend."""
    span = np.maximum(np.abs(lo), np.abs(hi))
    k = int(np.argmax(span))
    axis = np.zeros(3)
    axis[k] = 1.0
    sign = 1.0 if hi[k] >= -lo[k] else -1.0
    return axis, sign


def poses_from_joints(
    skeleton: Skeleton,
    joints: ArrayLike,
    extras: Mapping[str, ArrayLike] | None = None,
    clamp: bool = False,
    neutral_extras: bool = False,
) -> NDArray[np.float64]:
    """Pose vectors (T, pose_dim) whose bones point like the given joints (T, 17, 3).

    The root is put at the given pelvis; bone lengths stay the skeleton's. NaN
    joints (lost by a tracker) are tolerated: the rotations that need them keep
    their last solvable value (the rest pose before any). ``extras`` may give
    ``l_hand``, ``r_hand``, ``l_toe``, ``r_toe`` and ``head_top`` positions (T, 3) to
    orient wrists, ankles and head; without them those stay straight. ``clamp``
    projects the result into the joint limits. With ``neutral_extras`` the median
    direction of each extra point (relative to its bone) is taken as the rest
    direction: rigs disagree on where a foot or head "points", so a clip's typical
    foot and head pose then maps onto the skeleton's rest foot and head.
    """
    X = np.asarray(joints, dtype=np.float64)
    if X.ndim == 2:
        X = X[None]
    if X.ndim != 3 or X.shape[1:] != (NUM_JOINTS, 3):
        raise ConfigError(f"joints must have shape (T, {NUM_JOINTS}, 3), got {np.shape(joints)}")
    T = X.shape[0]
    ex: dict[str, NDArray[np.float64]] = {}
    for k, v in (extras or {}).items():
        if k not in EXTRA_POINTS:
            raise ConfigError(f"unknown extra point {k!r}; use {', '.join(EXTRA_POINTS)}")
        arr = np.asarray(v, dtype=np.float64).reshape(-1, 3)
        if arr.shape[0] != T:
            raise ConfigError(f"extra {k!r} has {arr.shape[0]} frames, joints have {T}")
        ex[k] = arr
    ni = skeleton.node_index
    lo, hi = skeleton.limits
    off = skeleton.offsets
    rest_q = skeleton.rest_pose()
    rest_nodes = skeleton.node_positions(rest_q)
    rest = skeleton.joints_from_nodes(rest_nodes)
    jx = {n: X[:, i] for i, n in enumerate(JOINT_NAMES)}
    r0 = {n: rest[i] for i, n in enumerate(JOINT_NAMES)}
    local = np.zeros((T, skeleton.num_nodes, 3))

    # trunk: pelvis and chest frames from the hips/shoulders lines and the trunk axis
    axis = jx["neck"] - jx["pelvis"]
    hips = jx["l_hip"] - jx["r_hip"]
    shoulders = jx["l_shoulder"] - jx["r_shoulder"]
    hips = np.where(np.isfinite(hips).all(-1, keepdims=True), hips, shoulders)
    axis0 = r0["neck"] - r0["pelvis"]
    F_p0 = _frame(r0["l_hip"] - r0["r_hip"], axis0)
    F_c0 = _frame(r0["l_shoulder"] - r0["r_shoulder"], axis0)
    G_pelvis_t = _frame(hips, axis) @ F_p0.T
    G_chest_t = _frame(shoulders, axis) @ F_c0.T
    local[:, ni("pelvis")] = _fill(_rotvec(G_pelvis_t))
    G_pelvis = _mat(local[:, ni("pelvis")])
    rel = _rotvec(np.swapaxes(G_pelvis, -1, -2) @ G_chest_t)
    rel = _fill(rel)
    half = _mat(0.5 * rel)
    # the split bends the trunk; swing the lumbar so the neck joint lies on the trunk axis
    c = rest[JOINT_INDEX["neck"]] - rest_nodes[ni("neck")]
    inner = off[ni("thorax")] + np.einsum("tij,j->ti", half, off[ni("neck")] + c)
    v = off[ni("lumbar")] + np.einsum("tij,tj->ti", half, inner)
    t_loc = np.einsum("tji,tj->ti", G_pelvis, axis)
    S = _mat(np.nan_to_num(_swing(v, np.where(np.isfinite(t_loc), t_loc, v))))
    local[:, ni("lumbar")] = _rotvec(S @ half)
    local[:, ni("thorax")] = 0.5 * rel
    G_thorax = G_pelvis @ S @ _mat(rel)

    # neck swings the head joint; the clavicles undo it so the shoulders follow the chest
    head_dir = np.einsum("tji,tj->ti", G_thorax, jx["head"] - jx["neck"])
    neck_rv = _fill(_swing(r0["head"] - r0["neck"], head_dir))
    neck_rv = np.clip(neck_rv, lo[3 + 3 * ni("neck") : 6 + 3 * ni("neck")],
                      hi[3 + 3 * ni("neck") : 6 + 3 * ni("neck")])  # fmt: skip
    local[:, ni("neck")] = neck_rv
    G_neck = G_thorax @ _mat(neck_rv)
    for side in ("l", "r"):
        local[:, ni(f"{side}_clavicle")] = -neck_rv
    if "head_top" in ex:
        d = np.einsum("tji,tj->ti", G_neck, ex["head_top"] - jx["head"])
        local[:, ni("head")] = _fill(_swing(_neutral(off[ni("head_top")], d, neutral_extras), d))

    def limb(parent_G: NDArray[np.float64], top: str, mid: str, end: str) -> None:
        """Solve a two-bone limb: top node (3 DOF) and mid hinge from three joint positions."""
        it, im = ni(top), ni(mid)
        a = _unit(off[im])
        k, sign = _hinge_axis(lo[3 + 3 * im : 6 + 3 * im], hi[3 + 3 * im : 6 + 3 * im])
        k = k * sign  # rotating +angle about k bends the limb the natural way
        u = _unit(jx[mid] - jx[top])
        f = _unit(jx[end] - jx[mid])
        cosphi = np.clip(np.sum(u * f, axis=-1), -1.0, 1.0)
        phi = np.arccos(cosphi)
        # a lost end joint (NaN) leaves the upper bone solvable, with the fallback twist
        f_ok = np.all(np.isfinite(f), axis=-1)
        n_meas = np.where(f_ok[:, None], np.cross(u, np.nan_to_num(f)), 0.0)
        sinphi = np.linalg.norm(n_meas, axis=-1)
        # fallback hinge axis: the smallest swing from rest carries k along
        u_loc = np.einsum("tji,tj->ti", parent_G, u)
        sw = _mat(np.nan_to_num(_swing(a, u_loc)))
        n_fb = np.einsum("tij,tjk,k->ti", parent_G, sw, k)
        agree = np.sum(n_meas * n_fb, axis=-1)
        hyper = (agree < 0) & (phi < np.radians(30.0))
        n_meas = np.where(hyper[:, None], -n_meas, n_meas)
        phi = np.where(hyper, -phi, phi)
        w = np.clip(sinphi / 0.2, 0.0, 1.0)[:, None]
        n = w * _unit(n_meas) + (1.0 - w) * n_fb
        n = n - np.sum(n * u, axis=-1, keepdims=True) * u
        G_top = _frame(u, n) @ _frame(a, k).T
        local[:, it] = _fill(_rotvec(np.swapaxes(parent_G, -1, -2) @ G_top))
        G_top = parent_G @ _mat(local[:, it])
        # the hinge angle, measured in the solved frame (exact when the bend is planar)
        f_loc = np.einsum("tji,tj->ti", G_top, f)
        b0 = _unit(off[ni(end)])
        f_p = f_loc - np.sum(f_loc * k, axis=-1, keepdims=True) * k
        ang = np.arctan2(np.sum(np.cross(b0, f_p) * k, axis=-1), np.sum(b0 * f_p, axis=-1))
        local[:, im] = _fill(k[None] * ang[:, None])

    for side in ("l", "r"):
        G_clav = G_neck @ _mat(local[:, ni(f"{side}_clavicle")])
        limb(G_clav, f"{side}_shoulder", f"{side}_elbow", f"{side}_wrist")
        limb(G_pelvis, f"{side}_hip", f"{side}_knee", f"{side}_ankle")

    # wrists and ankles: swing towards the hand / toe points when given
    if any(k in ex for k in ("l_hand", "r_hand", "l_toe", "r_toe")):
        G = skeleton.forward(np.concatenate([np.zeros((T, 3)), local.reshape(T, -1)], axis=1))
        for side in ("l", "r"):
            for joint, tip in (("wrist", "hand"), ("ankle", "toe")):
                key = f"{side}_{tip}"
                if key not in ex:
                    continue
                j = ni(f"{side}_{joint}")
                parent = skeleton.parents[j]
                d = np.einsum("tji,tj->ti", G[:, parent, :3, :3], ex[key] - jx[f"{side}_{joint}"])
                # rotation of node j, so its child's offset points along d (in the parent frame)
                rest_dir = _neutral(off[ni(key)], d, neutral_extras)
                local[:, j] = _fill(_swing(rest_dir, d))
        for side in ("l", "r"):
            for joint in ("wrist", "ankle"):
                j = ni(f"{side}_{joint}")
                local[:, j] = np.clip(
                    local[:, j], lo[3 + 3 * j : 6 + 3 * j], hi[3 + 3 * j : 6 + 3 * j]
                )

    root = jx["pelvis"].copy()
    bad: NDArray[np.bool_] = ~np.all(np.isfinite(root), axis=-1)
    if np.any(bad):
        alt = 0.5 * (jx["l_hip"] + jx["r_hip"])
        root = np.where(bad[:, None], alt, root)
        ok = np.isfinite(root).all(-1)
        if not np.any(ok):
            root = np.broadcast_to(rest_q[:3], (T, 3)).copy()
        else:
            root = _fill(root)
            first = int(np.argmax(ok))
            root[:first] = root[first]
    q = np.concatenate([root, local.reshape(T, -1)], axis=1)
    return skeleton.clamp(q) if clamp else q


# ---- retargeting a clip -----------------------------------------------------------


@dataclass(frozen=True)
class RetargetOptions:
    """How :func:`retarget` treats the source.

    ``recenter`` moves the first frame's pelvis over the origin (keeping the path);
    ``clamp`` projects poses into the joint limits; ``mapping`` overrides the
    detected :class:`JointMapping`; ``feet_on_floor`` lifts the result so the feet
    rest on Y = 0 (and never go through it).
    """

    recenter: bool = True
    clamp: bool = False
    feet_on_floor: bool = True
    mapping: JointMapping | None = None

    def __post_init__(self) -> None:
        check_option_types(self)


def _foot_low(skeleton: Skeleton, poses: NDArray[np.float64]) -> NDArray[np.float64]:
    """Per-frame height of the lowest sole point (heels under the ankles, toes)."""
    rest_nodes = skeleton.node_positions(skeleton.rest_pose())
    nodes = skeleton.node_positions(poses)
    lows = []
    for side in ("l", "r"):
        for name in ("ankle", "toe"):
            i = skeleton.node_index(f"{side}_{name}")
            lows.append(nodes[:, i, 1] - rest_nodes[i, 1])
    return np.min(np.stack(lows), axis=0)


def retarget(
    clip: BVHClip,
    skeleton: Skeleton | None = None,
    options: RetargetOptions | None = None,
    frames: slice | None = None,
    name: str | None = None,
) -> MotionClip:
    """Retarget a BVH clip onto ``skeleton``: pose vectors at the source frame rate.

    ``frames`` selects a part of the clip (a slice of frame indices). The result's
    ``source_joints`` are the source's 17 joints normalized to the skeleton's height
    with the floor at 0; the root follows the source pelvis scaled by leg length.
    """
    from bodyplay.motion.clip import MotionClip

    skeleton = skeleton or Skeleton()
    opts = options or RetargetOptions()
    if frames is not None and not isinstance(frames, slice):
        raise ConfigError("frames must be a slice of frame indices, e.g. slice(0, 240)")
    info = analyze_source(clip, skeleton, opts.mapping)
    J, extras, pelvis = source_joints(clip, info, skeleton, frames if frames is not None else None)
    if J.shape[0] == 0:
        raise ConfigError(f"frames {frames} selects no frame of {clip.num_frames}")
    poses = poses_from_joints(skeleton, J, extras, neutral_extras=True)
    root = pelvis * (skeleton.pelvis_height / info.leg_length)
    if opts.recenter:
        root[:, [0, 2]] -= root[0, [0, 2]]
        J[:, :, [0, 2]] -= J[0, JOINT_INDEX["pelvis"], [0, 2]]
    poses[:, 0:3] = root
    if opts.clamp:
        poses = skeleton.clamp(poses)
    if opts.feet_on_floor:
        low = _foot_low(skeleton, poses)
        poses[:, 1] -= np.percentile(low, 5)
        poses[:, 1] += np.maximum(0.0, -(low - np.percentile(low, 5)))
    step = frames.step if frames is not None and frames.step else 1
    return MotionClip(
        skeleton=skeleton,
        poses=poses,
        fps=clip.fps / step,
        name=name or _clip_name(clip.source),
        source_joints=J,
    )


def _clip_name(source: str) -> str:
    base = source.replace("\\", "/").rsplit("/", 1)[-1]
    for ext in (".gz", ".bvh"):
        if base.endswith(ext):
            base = base[: -len(ext)]
    return base or "clip"
