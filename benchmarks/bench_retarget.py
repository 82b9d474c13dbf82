"""Retargeting figures: limb-direction errors per clip and retargeting speed.

Run: .venv/bin/python benchmarks/bench_retarget.py
Prints, for every BVH in ../shared/data/mocap (or the built-in CMU clips), the
median and 95th-percentile angle between each retargeted bone and the source's,
and the median wall time of retargeting the whole clip (3 runs).
"""

from __future__ import annotations

import datetime
import platform
import time
from pathlib import Path

import numpy as np

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.skeleton import Skeleton
from bodyplay.motion import builtin_clip_path, list_builtin_clips, read_bvh, retarget

BONES = {
    "upper arms": [("l_shoulder", "l_elbow"), ("r_shoulder", "r_elbow")],
    "forearms": [("l_elbow", "l_wrist"), ("r_elbow", "r_wrist")],
    "thighs": [("l_hip", "l_knee"), ("r_hip", "r_knee")],
    "shins": [("l_knee", "l_ankle"), ("r_knee", "r_ankle")],
    "trunk": [("pelvis", "neck")],
    "shoulder line": [("r_shoulder", "l_shoulder")],
}


def angles(a: np.ndarray, b: np.ndarray, pairs: list[tuple[str, str]]) -> np.ndarray:
    """Angles in degrees between the bones (pairs) of two (T, 17, 3) joint arrays."""
    out = []
    for p, c in pairs:
        u = a[:, JOINT_INDEX[c]] - a[:, JOINT_INDEX[p]]
        v = b[:, JOINT_INDEX[c]] - b[:, JOINT_INDEX[p]]
        cos = np.sum(u * v, -1) / np.linalg.norm(u, axis=-1) / np.linalg.norm(v, axis=-1)
        out.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return np.concatenate(out)


def main() -> None:
    """Print the figures."""
    shared = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "mocap"
    paths = sorted(shared.glob("*/*.bvh")) or [builtin_clip_path(n) for n in list_builtin_clips()]
    sk = Skeleton()
    machine = platform.processor() or platform.machine()
    print(f"# bench_retarget  {datetime.date.today()}  {machine}  {platform.python_version()}")
    print("clip, frames, ms median (3 runs), frames/s, then median/p95 angle error (deg) per bone")
    for path in paths:
        clip = read_bvh(path)
        times = []
        for _ in range(3):
            t0 = time.perf_counter()
            motion = retarget(clip, sk)
            times.append(time.perf_counter() - t0)
        ms = 1000 * float(np.median(times))
        J, S = motion.joints(), motion.source_joints
        assert S is not None
        errs = "  ".join(
            f"{k} {np.median(angles(J, S, v)):.2f}/{np.percentile(angles(J, S, v), 95):.2f}"
            for k, v in BONES.items()
        )
        print(
            f"{path.name:45s} {clip.num_frames:5d} {ms:7.0f} ms "
            f"{clip.num_frames / (ms / 1000):7.0f} f/s  {errs}"
        )


if __name__ == "__main__":
    main()
