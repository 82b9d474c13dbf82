"""Synthetic training motion for the shape hierarchy: real motion recombined limb by limb.

The paper builds its tree from 57,136 poses of motion capture of the motions the
games need; the project may ship only four CMU clips (jumping jacks, twists,
squats, walks, hops: about 2,000 frames). Their arms always move together with
their own legs and torso: no frame raises one arm while the body stands still, a
wave, a punch or a kick is missing. A silhouette shows each limb separately, so
the pose set gains most from limbs combined in ways the clips never show.

A recombined sequence (:func:`recombined_sequences`) takes a stretch of real
motion (a clip, or its left-right mirror) as its base, and each body part (torso,
either arm, either leg) independently

* with probability ``swap`` follows another stretch of real motion (any clip or
  mirror, so a left arm can move like any right arm), played at a random speed
  (time-warped by a factor in ``speed``);
* with probability ``random_limb`` moves smoothly through random configurations
  within the skeleton's joint limits, a new one every ``key_every`` frames (arms
  over their whole range; at most one leg per sequence, so that the body still
  stands on a foot);
* otherwise keeps the base's motion.

Every frame is a pose within the joint limits (each part's rotations come whole
from a real frame, or from within the limit box), and sequences are motion, so
the transition histograms and the dynamic model learn from them as from the
clips.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError

__all__ = ["LIMB_GROUPS", "limb_columns", "random_limb_config", "recombined_sequences"]

LIMB_GROUPS: tuple[tuple[str, ...], ...] = (
    ("lumbar", "thorax", "neck", "head"),
    ("l_clavicle", "l_shoulder", "l_elbow", "l_wrist"),
    ("r_clavicle", "r_shoulder", "r_elbow", "r_wrist"),
    ("l_hip", "l_knee", "l_ankle"),
    ("r_hip", "r_knee", "r_ankle"),
)
"""The body parts recombined independently (skeleton node names): torso with
head, left arm, right arm, left leg, right leg."""

_LEGS = (3, 4)

# share of each node's limit box a random limb moves over (the rest of a box holds
# poses people rarely take: a fully twisted spine, a bent-back wrist)
_RANGE = {"lumbar": 0.5, "thorax": 0.5, "neck": 0.4, "head": 0.4,
          "l_clavicle": 0.8, "r_clavicle": 0.8, "l_wrist": 0.5, "r_wrist": 0.5,
          "l_ankle": 0.5, "r_ankle": 0.5}


def limb_columns(skeleton: Skeleton, names: tuple[str, ...]) -> NDArray[np.int64]:
    """The pose-vector columns of the named joints' rotations (three per joint)."""
    return np.concatenate([np.arange(3 + 3 * skeleton.node_index(n), 6 + 3 * skeleton.node_index(n))
                           for n in names]).astype(np.int64)


def random_limb_config(skeleton: Skeleton, names: tuple[str, ...], rng: np.random.Generator
                       ) -> NDArray[np.float64]:
    """Rotations of the named joints drawn uniformly within the skeleton's joint limits
    (narrowed per joint by ``_RANGE``), in :func:`limb_columns` order."""
    lo, hi = skeleton.limits
    out = []
    for n in names:
        i = 3 + 3 * skeleton.node_index(n)
        mid, half = 0.5 * (lo[i:i + 3] + hi[i:i + 3]), 0.5 * (hi[i:i + 3] - lo[i:i + 3])
        out.append(rng.uniform(mid - half * _RANGE.get(n, 1.0), mid + half * _RANGE.get(n, 1.0)))
    return np.concatenate(out)


def _random_motion(skeleton: Skeleton, names: tuple[str, ...], n: int, key_every: int,
                   rng: np.random.Generator) -> NDArray[np.float64]:
    """``n`` frames through a new random configuration every ``key_every`` frames,
    eased in and out (a blend of two configurations stays within the limit box)."""
    keys = [random_limb_config(skeleton, names, rng) for _ in range((n - 1) // key_every + 2)]
    t = np.arange(n) / key_every
    k = np.minimum(t.astype(np.int64), len(keys) - 2)
    w = (t - k)[:, None]
    w = w * w * (3.0 - 2.0 * w)  # smooth start and stop at every key
    K = np.array(keys)
    return (1.0 - w) * K[k] + w * K[k + 1]


def _stretch(source: NDArray[np.float64], length: int, speed: float,
             rng: np.random.Generator) -> NDArray[np.float64]:
    """``length`` frames of ``source`` from a random start at ``speed`` times its rate
    (nearest frame; bounced back at the clip's ends)."""
    n = len(source)
    if n == 1:
        return np.repeat(source, length, axis=0)
    t = rng.uniform(0, n - 1) + speed * np.arange(length)
    period = 2 * (n - 1)
    t = np.mod(t, period)
    t = np.where(t > n - 1, period - t, t)
    return source[np.rint(t).astype(np.int64)]


def recombined_sequences(skeleton: Skeleton, sources: list[NDArray[np.float64]], frames: int,
                         rng: np.random.Generator, swap: float = 0.5, random_limb: float = 0.2,
                         length: int = 30, speed: tuple[float, float] = (0.5, 2.0),
                         key_every: int = 10) -> list[NDArray[np.float64]]:
    """Sequences of recombined real motion, ``frames`` frames in all (see the module
    docstring). ``sources``: the real clips' poses (T, pose_dim), already including
    any mirrored copies; ``length`` frames per sequence. Root position and
    orientation come from the base stretch."""
    if not sources or any(len(s) < 1 for s in sources):
        raise ConfigError("recombination needs at least one non-empty source clip")
    if not (0 <= swap <= 1 and 0 <= random_limb <= 1 and swap + random_limb <= 1):
        raise ConfigError("swap and random_limb are probabilities with swap + random_limb <= 1")
    if length < 2 or key_every < 1 or not 0 < speed[0] <= speed[1]:
        raise ConfigError("length must be at least 2 frames, key_every at least 1 and speed a "
                          "range of positive factors")
    cols = [limb_columns(skeleton, g) for g in LIMB_GROUPS]
    out: list[NDArray[np.float64]] = []
    total = 0
    while total < frames:
        n = max(2, min(length, frames - total))
        seq = _stretch(sources[int(rng.integers(len(sources)))], n, 1.0, rng).copy()
        random_leg = False
        for g, c in enumerate(cols):
            u = rng.random()
            if u < random_limb and not (g in _LEGS and random_leg):
                random_leg |= g in _LEGS
                seq[:, c] = _random_motion(skeleton, LIMB_GROUPS[g], n, key_every, rng)
            elif u < random_limb + swap:
                src = sources[int(rng.integers(len(sources)))]
                seq[:, c] = _stretch(src, n, float(rng.uniform(*speed)), rng)[:, c]
        out.append(skeleton.clamp(seq))
        total += n
    return out

