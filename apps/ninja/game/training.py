"""The ninja's motions as a training clip for the silhouette tracker's hierarchy.

The paper built its game's pose hierarchy from the game's own motions (400,000
poses of three subjects performing the five motions, thinned to about 30,000).
:func:`ninja_training_clip` does the same with what we have: the five motions of
the gesture tables (the key poses the virtual ninja performs), each performed
``variants`` times with a random speed (0.75-1.3), a random amplitude (every key
pose's rotations scaled by 0.8-1.15 from the idle pose) and random joint noise
(0.08 rad), so the tree holds motions *like* the game's rather than the exact test
script, plus a side step either way. After each round of the five it adds
everyday arm motions of the kinds a player makes between them (a hand raised,
either hand waving or punching, both hands raised), varied the same way but drawn
from a random stream of their own, so the tree has leaves for a raised or waving
arm (without them the tracker dropped such an arm to the side for a few frames:
"up, then down quickly", a false hit). Every frame stands on the floor (the
hierarchy reads the clip back through the retargeter, which puts the floor under
the lowest feet); written once as a BVH file (its name carries the generator's
version and seed). :func:`silhouette_options` adds it to the
vendored CMU clips the silhouette tracker's hierarchy is built from (the
hierarchy's cache key includes the clip's bytes, so it is built once).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.skeleton import Skeleton
from bodyplay.testing import GESTURE_MOTIONS, KEY_POSES, Timeline, key_pose
from bodyplay.testing.poses import grounded

__all__ = ["ninja_training_clip", "silhouette_options", "TRAINING_VERSION"]

TRAINING_VERSION = 6
"""Bumped whenever the generated clip changes (it is part of the file name)."""

_ORDER = ("transfigure", "crouch", "step_left", "hit", "step_right", "double_hit",
          "step_right", "crouch", "step_left", "hit", "double_hit")
_EVERYDAY = ("raise_right_hand", "raise_left_hand", "wave_right", "wave_left", "punch_right",
             "punch_left", "raise_both_hands")
"""Everyday arm motions (the kinds a player makes between the five) performed after
each round of the five, so the tree has leaves for a raised or waving arm."""


def _varied_keys(sk: Skeleton, gesture: str, rng: np.random.Generator, x: float,
                 amplitude: float, noise: float) -> list[tuple[float, NDArray[np.float64]]]:
    """The gesture's key poses with their rotations scaled from idle and jittered."""
    idle = key_pose("idle", sk)
    keys = []
    motion = GESTURE_MOTIONS[gesture]
    assert not isinstance(motion, str)
    for t, name in motion:
        q = key_pose(name, sk).copy()
        rot = idle[6:] + amplitude * (q[6:] - idle[6:])
        moved = np.abs(q[6:] - idle[6:]) > 1e-6  # jitter the joints the motion moves
        rot = rot + moved * rng.normal(0.0, noise, rot.shape)
        q[6:] = rot
        if KEY_POSES[name].get("grounded"):  # scaled, jittered legs: feet back on the floor
            q = grounded(sk, q)
        q[0] += x
        keys.append((float(t), q))
    return keys


def _on_floor(sk: Skeleton, poses: NDArray[np.float64]) -> NDArray[np.float64]:
    """Every frame moved vertically so that its lower ankle is at the standing ankle
    height: none of the five motions leaves the floor, but blending key poses sinks
    the feet into it on the way into a squat (up to 10 cm), and reading the clip
    back (:func:`bodyplay.motion.load_clip` puts the floor under the lowest feet)
    would then lift every standing frame 13 cm off the floor, making its templates
    taller than the player."""
    rest = sk.joint_positions(sk.rest_pose())
    ia, ib = JOINT_INDEX["l_ankle"], JOINT_INDEX["r_ankle"]
    j = sk.joint_positions(poses)
    out = np.array(poses, np.float64, copy=True)
    out[:, 1] += min(rest[ia, 1], rest[ib, 1]) - np.minimum(j[:, ia, 1], j[:, ib, 1])
    return out


def ninja_training_clip(folder: Path | None = None, fps: float = 30.0, variants: int = 6,
                        seed: int = 0) -> Path:
    """Write (once) and return the BVH of the five motions' varied performances, with
    varied everyday arm motions after each round."""
    from bodyplay.motion.bvh import write_bvh

    folder = folder or Path.home() / ".cache" / "bodyplay"
    path = folder / f"ninja_motions_v{TRAINING_VERSION}_{variants}x_seed{seed}.bvh"
    if path.exists():
        return path
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    # the everyday motions draw from their own stream (not the test scripts' seeds)
    everyday_rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(7,)))
    sk = Skeleton()
    tl = Timeline(sk, blend=0.15).hold("idle", 0.5)
    x = 0.0
    for _ in range(variants):
        for g in _ORDER:
            speed = float(rng.uniform(0.75, 1.3))
            amp = float(rng.uniform(0.8, 1.15))
            keys = [(t / speed, q) for t, q in
                    _varied_keys(sk, g, rng, x, amp if "step" not in g else 1.0, 0.08)]
            tl.keys(keys, start=tl.cursor + float(rng.uniform(0.2, 0.5)), label=g)
            x += 0.5 if g == "step_left" else -0.5 if g == "step_right" else 0.0
        for e in everyday_rng.permutation(list(_EVERYDAY)):
            speed = float(everyday_rng.uniform(0.75, 1.3))
            amp = float(everyday_rng.uniform(0.8, 1.15))
            keys = [(t / speed, q) for t, q in
                    _varied_keys(sk, str(e), everyday_rng, x, amp, 0.08)]
            tl.keys(keys, start=tl.cursor + float(everyday_rng.uniform(0.2, 0.5)),
                    label=str(e))
    times = np.arange(0.0, tl.duration, 1.0 / fps)
    tmp = path.with_suffix(".tmp.bvh")
    write_bvh(tmp, sk, _on_floor(sk, tl.poses(times)), fps)
    tmp.replace(path)
    return path


def silhouette_options(folder: Path | None = None) -> Any:
    """Silhouette tracker options whose hierarchy also holds the ninja's motions.

    Measured on the tune half of ``benchmarks/ninja_gestures.py`` (docs/ninja.md):
    the clip poses are not clamped into the joint limits (the hit swings the
    shoulder to 1.9 rad, past its 1.7 limit); Algorithm 1 clusters with the
    larger of the distance's two directions at every level
    (``HierarchyOptions.membership``: a member is near its prototype both as the
    observed shape and as the template the filter scores, so the folded arms of
    transfigure no longer hang under a prototype with the arms spread, which the
    filter scores far from a fold and prunes: transfigure recall 0.00 -> 0.75);
    ``explore`` 24 (the tree is finer at the top, 2,910 level-1 nodes instead of
    540: 8 left hits pruned); ``sigma`` 0.35 (0.5: 2 false hits, 1 false double
    hit, transfigure 0.75, hit 0.50; 0.25: transfigure 0.25); no per-arm
    refinement (``arm_candidates`` 0; on, hit recall 1.00 -> 0.75 and double hit
    1.00 -> 0.50); ``transition_frames`` 3 (the prediction reaches three frames
    along the training motion, so the filter follows a hit's swing on a thin arm
    that it lost a frame of: hit recall on the first 16 tune scripts 13 -> 16,
    transfigure 15 either way); ``fit_prior`` 0.05 with ``shift_search`` (1, 1) (a
    share of the prior for the leaves that fit best this frame, and a vertical
    search of the template's place: a thin player's arm swung over the head lost to
    the arms-down leaf's prior, and the body preset a few centimetres taller than
    the player fits the raised arm only a couple of pixels lower; tune half 32:
    hit recall 0.97 -> 1.00, transfigure 0.91 -> 0.97, docs/ninja.md)."""
    from bodyplay.motion import list_builtin_clips
    from bodyplay.trackers.silhouette.options import HierarchyOptions, SilhouetteOptions

    clips = tuple(list_builtin_clips()) + (str(ninja_training_clip(folder)),)
    return SilhouetteOptions(hierarchy=HierarchyOptions(clips=clips, clamp=False,
                                                        membership=("both", "both", "both")),
                             explore=24, sigma=0.35, arm_candidates=0, transition_frames=3,
                             fit_prior=0.05, shift_search=(1, 1))
