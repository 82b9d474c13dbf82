"""Joint mappings: which joints of a motion-capture skeleton are ours.

Explicit mappings for the CMU (both cgspeed releases) and Bandai Namco skeletons,
and :func:`guess_mapping`, a fallback that reads joint names and the hierarchy.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass

from bodyplay.errors import ConfigError
from bodyplay.motion.bvh import BVHClip

__all__ = [
    "BANDAI_MAPPING",
    "CMU_MAPPING",
    "CMU_MAX_MAPPING",
    "JointMapping",
    "LIMB_KEYS",
    "guess_mapping",
    "mapping_for",
]

LIMB_KEYS = (
    "l_shoulder", "l_elbow", "l_wrist", "r_shoulder", "r_elbow", "r_wrist",
    "l_hip", "l_knee", "l_ankle", "r_hip", "r_knee", "r_ankle",
)  # fmt: skip


@dataclass(frozen=True)
class JointMapping:
    """Which source joints stand for our joints.

    ``joints`` maps each of the twelve limb joints (``l_shoulder`` ... ``r_ankle``,
    glenohumeral and hip centres, not clavicles) and ``head`` (the source's head
    bone; its End Site gives the head top) to a source joint name; optional keys
    ``l_hand``, ``r_hand`` (a finger joint beyond the wrist) and ``l_toe``,
    ``r_toe`` orient the wrists and ankles.
    """

    name: str
    joints: Mapping[str, str]

    def missing(self, clip: BVHClip) -> list[str]:
        """Required keys whose source joint is not in ``clip`` (or not mapped)."""
        need = (*LIMB_KEYS, "head")
        return [k for k in need if self.joints.get(k) not in clip.names]


def _sided(side: str, parts: Mapping[str, str]) -> dict[str, str]:
    return {f"{side}_{k}": v for k, v in parts.items()}


CMU_MAPPING = JointMapping(
    "cmu",
    {
        **_sided("l", {"shoulder": "LeftArm", "elbow": "LeftForeArm", "wrist": "LeftHand",
                       "hand": "LeftHandIndex1", "hip": "LeftUpLeg", "knee": "LeftLeg",
                       "ankle": "LeftFoot", "toe": "LeftToeBase"}),
        **_sided("r", {"shoulder": "RightArm", "elbow": "RightForeArm", "wrist": "RightHand",
                       "hand": "RightHandIndex1", "hip": "RightUpLeg", "knee": "RightLeg",
                       "ankle": "RightFoot", "toe": "RightToeBase"}),
        "head": "Head",
    },
)  # fmt: skip
"""CMU (cgspeed MotionBuilder-friendly release): LeftArm is the glenohumeral joint."""

CMU_MAX_MAPPING = JointMapping(
    "cmu-3dsmax",
    {
        **_sided("l", {"shoulder": "LeftShoulder", "elbow": "LeftElbow", "wrist": "LeftWrist",
                       "hand": "LFingers", "hip": "LeftHip", "knee": "LeftKnee",
                       "ankle": "LeftAnkle", "toe": "LeftToe"}),
        **_sided("r", {"shoulder": "RightShoulder", "elbow": "RightElbow",
                       "wrist": "RightWrist", "hand": "RFingers", "hip": "RightHip",
                       "knee": "RightKnee", "ankle": "RightAnkle", "toe": "RightToe"}),
        "head": "Head",
    },
)  # fmt: skip
"""CMU (cgspeed 3ds Max-friendly release): LeftCollar is the clavicle, LeftShoulder
the glenohumeral joint."""

BANDAI_MAPPING = JointMapping(
    "bandai-namco",
    {
        **_sided("l", {"shoulder": "UpperArm_L", "elbow": "LowerArm_L", "wrist": "Hand_L",
                       "hip": "UpperLeg_L", "knee": "LowerLeg_L", "ankle": "Foot_L",
                       "toe": "Toes_L"}),
        **_sided("r", {"shoulder": "UpperArm_R", "elbow": "LowerArm_R", "wrist": "Hand_R",
                       "hip": "UpperLeg_R", "knee": "LowerLeg_R", "ankle": "Foot_R",
                       "toe": "Toes_R"}),
        "head": "Head",
    },
)  # fmt: skip
"""Bandai Namco Research motion dataset (joint_Root/Hips/UpperArm_L ...)."""

_KNOWN_MAPPINGS = (CMU_MAPPING, CMU_MAX_MAPPING, BANDAI_MAPPING)


def _side(name: str) -> str | None:
    if re.search(r"left", name, re.I) or re.search(r"(^l(?=[A-Z_.\-])|[_.\-\s]l$)", name):
        return "l"
    if re.search(r"right", name, re.I) or re.search(r"(^r(?=[A-Z_.\-])|[_.\-\s]r$)", name):
        return "r"
    if re.search(r"(^l_|_l$)", name, re.I):
        return "l"
    if re.search(r"(^r_|_r$)", name, re.I):
        return "r"
    return None


def guess_mapping(clip: BVHClip) -> JointMapping:
    """Map a BVH skeleton by its joint names and structure (the fallback).

    Finds, on each side, the joint named like a wrist/hand and a foot/ankle; the
    elbow/knee is its parent and the shoulder/hip its grandparent (so clavicles and
    hip-joint helpers are skipped). The head is the joint named ``head``.
    """
    children: dict[int, list[int]] = {i: [] for i in range(clip.num_joints)}
    for i, p in enumerate(clip.parents):
        if p >= 0:
            children[p].append(i)

    def depth(i: int) -> int:
        d = 0
        while clip.parents[i] >= 0:
            i = clip.parents[i]
            d += 1
        return d

    def find(side: str | None, pattern: str) -> int | None:
        hits = [
            i for i, n in enumerate(clip.names)
            if re.search(pattern, n, re.I) and (side is None or _side(n) == side)
        ]  # fmt: skip
        return min(hits, key=depth) if hits else None

    out: dict[str, str] = {}
    problems: list[str] = []
    for side in ("l", "r"):
        for end, mid, top, tip, pat in (
            ("wrist", "elbow", "shoulder", "hand", r"(hand|wrist)"),
            ("ankle", "knee", "hip", "toe", r"(foot|ankle)"),
        ):
            j = find(side, pat)
            if j is None or clip.parents[j] < 0 or clip.parents[clip.parents[j]] < 0:
                problems.append(f"{side}_{end}")
                continue
            out[f"{side}_{end}"] = clip.names[j]
            out[f"{side}_{mid}"] = clip.names[clip.parents[j]]
            out[f"{side}_{top}"] = clip.names[clip.parents[clip.parents[j]]]
            if children[j]:
                out[f"{side}_{tip}"] = clip.names[children[j][0]]
    h = find(None, r"head")
    if h is None:
        problems.append("head")
    else:
        out["head"] = clip.names[h]
    if problems:
        raise ConfigError(
            f"cannot map {clip.source or 'the BVH skeleton'} onto bodyplay's joints: no joint "
            f"found for {', '.join(problems)} (joints are {', '.join(clip.names)}); "
            "pass a JointMapping"
        )
    return JointMapping("guessed", out)


def mapping_for(clip: BVHClip, mapping: JointMapping | None = None) -> JointMapping:
    """The given mapping (checked against the clip), else the first known one that fits,
    else :func:`guess_mapping`."""
    if mapping is not None:
        miss = mapping.missing(clip)
        if miss:
            raise ConfigError(
                f"mapping {mapping.name!r} does not fit {clip.source or 'the clip'}: "
                f"{', '.join(f'{k}={mapping.joints.get(k)!r}' for k in miss)} not found"
            )
        return mapping
    for m in _KNOWN_MAPPINGS:
        if not m.missing(clip):
            return m
    return guess_mapping(clip)
