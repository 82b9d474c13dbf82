"""The pose set the shape hierarchy is built from (paper section 2.1).

Real motion: every frame of the training clips (default: the vendored CMU clips),
read at the tracker's frame rate, travel removed and turned to face the camera
(the clip's median heading; each clip is also used turned by a few yaws), kept in
sequence for the transition histograms. Frames turned away from the camera by
more than ``max_yaw_deg`` are left out: a silhouette cannot tell front from back,
and a game's player faces the screen. The paper's rule "only poses are stored
that differ at least 5 degrees in any joint angle from other poses" thins them
(:func:`dedup_poses`); every dropped frame maps to the kept pose that covered it.
Joint-limit-aware random upper bodies (:func:`bodyplay.motion.random_upper_body`)
add arm poses the clips lack, and with ``recombine_share`` the clips' limbs are
recombined into new motion (:mod:`.recombine`: one arm waving while the body
stands, a leg kicking), faced to the camera at a random yaw within the yaw offsets.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path

import numba
import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette.options import HierarchyOptions

__all__ = ["TrainingPoses", "training_poses", "dedup_poses", "clip_fingerprint", "mirror_poses"]


@dataclass(frozen=True, eq=False)
class TrainingPoses:
    """Kept poses and the training sequences as indices into them.

    ``poses``: (N, pose_dim) kept poses (pelvis over the origin); ``sequences``:
    one int array per (clip, yaw) of kept-pose indices, frame by frame (-1 where the
    frame was turned away from the camera by more than ``max_yaw_deg``);
    ``dedup_deg``: the angle the 5-degree rule ended up at (larger only when the
    set would exceed ``max_poses``); ``frames``: training frames before thinning.
    """

    poses: NDArray[np.float64]
    sequences: tuple[NDArray[np.int64], ...]
    dedup_deg: float
    frames: int


def clip_fingerprint(clips: tuple[str, ...]) -> str:
    """Hash of the clip files' contents (built-in names hash their files)."""
    from bodyplay.motion import builtin_clip_path, list_builtin_clips

    h = hashlib.sha1()
    names = clips or tuple(list_builtin_clips())
    for c in names:
        p = Path(c) if Path(c).exists() else builtin_clip_path(c)
        h.update(Path(p).name.encode())
        h.update(Path(p).read_bytes())
    return h.hexdigest()[:16]


def _quats(skeleton: Skeleton, poses: NDArray[np.float64]) -> NDArray[np.float64]:
    """(N, nodes, 4) unit quaternions of every rotating node (root orientation first)."""
    lo, hi = skeleton.limits
    rot = [i for i in range(skeleton.num_nodes) if i == 0 or hi[3 + 3 * i] > lo[3 + 3 * i]]
    rv = poses[:, 3:].reshape(len(poses), skeleton.num_nodes, 3)[:, rot]
    q = Rotation.from_rotvec(rv.reshape(-1, 3)).as_quat().reshape(len(poses), len(rot), 4)
    return np.ascontiguousarray(q)


@numba.njit(cache=True)
def _dedup(q: NDArray[np.float64], cos_half: float):  # type: ignore[no-untyped-def]  # pragma: no cover
    n, j = q.shape[0], q.shape[1]
    kept = np.empty(n, np.int64)
    owner = np.empty(n, np.int64)
    nk = 0
    for i in range(n):
        found = -1
        # most recent kept poses first: consecutive frames are the usual duplicates
        for kk in range(nk - 1, -1, -1):
            k = kept[kk]
            close = True
            for a in range(j):
                d = abs(q[i, a, 0] * q[k, a, 0] + q[i, a, 1] * q[k, a, 1]
                        + q[i, a, 2] * q[k, a, 2] + q[i, a, 3] * q[k, a, 3])
                if d < cos_half:
                    close = False
                    break
            if close:
                found = kk
                break
        if found < 0:
            kept[nk] = i
            owner[i] = nk
            nk += 1
        else:
            owner[i] = found
    return kept[:nk], owner


def dedup_poses(skeleton: Skeleton, poses: NDArray[np.float64], degrees: float = 5.0
                ) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The 5-degree rule: keep a pose only if, against every pose kept before it, some
    joint (or the global orientation) differs by at least ``degrees``.

    Returns the kept indices and, per input pose, the position (in the kept list)
    of the kept pose it duplicates (itself when kept).
    """
    if degrees <= 0:
        raise ConfigError("the de-duplication angle must be positive")
    q = _quats(skeleton, np.asarray(poses, np.float64))
    kept, owner = _dedup(q, float(np.cos(np.radians(degrees) / 2.0)))
    return kept, owner


def _face_camera(poses: NDArray[np.float64], yaw: float) -> NDArray[np.float64]:
    """Travel removed; the clip's median heading turned to face +Z, then by ``yaw``."""
    out = poses.copy()
    out[:, 0] = 0.0
    out[:, 2] = 0.0
    R = Rotation.from_rotvec(poses[:, 3:6])
    fwd = R.apply([0.0, 0.0, 1.0])
    heading = np.arctan2(fwd[:, 0], fwd[:, 2])
    mid = float(np.arctan2(np.median(np.sin(heading)), np.median(np.cos(heading))))
    out[:, 3:6] = (Rotation.from_euler("Y", yaw - mid) * R).as_rotvec()
    return out


def mirror_poses(skeleton: Skeleton, poses: NDArray[np.float64]) -> NDArray[np.float64]:
    """Poses mirrored left-right (through the body's sagittal plane x = 0).

    The reflection diag(-1, 1, 1) turns a rotation vector (x, y, z) into (x, -y, -z)
    and the root position's x into -x; every ``l_`` node takes its ``r_`` partner's
    mirrored rotation and the other way round. The skeleton's rest offsets and
    joint limits are left-right symmetric, so a pose within the limits stays so.
    """
    names = skeleton.node_names
    src = np.arange(len(names))
    for i, n in enumerate(names):
        if n.startswith(("l_", "r_")):
            src[i] = names.index(("r_" if n[0] == "l" else "l_") + n[2:])
    p = np.asarray(poses, np.float64)
    rv = p[..., 3:].reshape(*p.shape[:-1], len(names), 3)[..., src, :].copy()
    rv[..., 1:] *= -1.0
    out = p.copy()
    out[..., 0] *= -1.0
    out[..., 3:] = rv.reshape(*p.shape[:-1], 3 * len(names))
    return out


def training_poses(skeleton: Skeleton, options: HierarchyOptions) -> TrainingPoses:
    """Clip frames (turned by each yaw offset), thinned by the 5-degree rule, plus
    joint-limit-aware random upper bodies (see the module docstring)."""
    from bodyplay.motion import list_builtin_clips, load_clip, random_upper_body

    names = options.clips or tuple(list_builtin_clips())
    if not names:
        raise ConfigError("no motion clips to build the shape hierarchy from")
    seqs: list[NDArray[np.float64]] = []
    clip_poses: list[NDArray[np.float64]] = []
    for name in names:
        clip = load_clip(name, skeleton, fps=options.clip_fps)
        if abs(clip.fps - options.clip_fps) > 1e-6:
            clip = clip.resample(options.clip_fps)
        clip_poses.append(skeleton.clamp(clip.poses) if options.clamp else clip.poses)
        for yaw in options.yaw_offsets_deg:
            turned = _face_camera(clip.poses, float(np.radians(yaw)))
            seqs.append(skeleton.clamp(turned) if options.clamp else turned)
    n_clip_frames = sum(len(s) for s in seqs)
    if options.mirror:
        seqs += [skeleton.clamp(mirror_poses(skeleton, s)) if options.clamp
                 else mirror_poses(skeleton, s) for s in seqs]
    rng = np.random.default_rng(options.seed)
    n_yaws = max(1, len(options.yaw_offsets_deg))
    if options.recombine_share > 0:
        from bodyplay.trackers.silhouette.recombine import recombined_sequences

        sources = [p for c in clip_poses for p in (c, mirror_poses(skeleton, c))]
        yaws = np.radians(options.yaw_offsets_deg)
        for seq in recombined_sequences(
                skeleton, sources, int(round(options.recombine_share * n_clip_frames / n_yaws)),
                rng, swap=options.recombine_swap, random_limb=options.recombine_random):
            seqs.append(skeleton.clamp(_face_camera(seq, float(rng.uniform(yaws.min(),
                                                                            yaws.max())))))
    frames = np.concatenate(seqs)
    fwd = Rotation.from_rotvec(frames[:, 3:6]).apply([0.0, 0.0, 1.0])
    facing = np.abs(np.degrees(np.arctan2(fwd[:, 0], fwd[:, 2]))) <= options.max_yaw_deg
    n_rand = int(round(options.random_share * n_clip_frames / n_yaws))
    extra = (random_upper_body(skeleton, n_rand, rng, yaw_range=(-np.pi / 4, np.pi / 4),
                               max_tilt=0.1) if n_rand else np.zeros((0, skeleton.pose_dim)))
    allp = np.concatenate([frames[facing], extra])
    deg = options.dedup_deg
    while True:
        kept, owner = dedup_poses(skeleton, allp, deg)
        if len(kept) <= options.max_poses:
            break
        deg *= 1.2  # the set would be too large for the time budget: loosen the rule
    # per training frame, its kept pose (-1 for frames turned away from the camera)
    owner_all = np.full(len(frames), -1, np.int64)
    owner_all[facing] = owner[: int(facing.sum())]
    sequences = []
    s = 0
    for seq in seqs:
        sequences.append(owner_all[s : s + len(seq)])
        s += len(seq)
    return TrainingPoses(allp[kept], tuple(sequences), deg, len(allp))
