"""How far the generic tracking skeleton is from the synthetic actor's, pose for pose.

The tracker fits a generic skeleton (body preset ``m`` by default); the synthetic
truth comes from the MakeHuman actor's own skeleton, whose limbs and neck have
other lengths. Driving both with the same pose vectors (the clip retargeted to the
actor) and removing the best per-frame translation gives the error a perfect
tracker would still show: a floor under the benchmark's MPJPE.

    .venv/bin/python benchmarks/colorshirt_skeleton_floor.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from bodyplay.body import BODY_SHAPES, Skeleton
from bodyplay.body.actor import load_actor
from bodyplay.motion import load_clip

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
CLIPS = ("dataset-2_wave-both-hands_normal_001", "dataset-1_punch_normal_001",
         "dataset-2_raise-up-both-hands_normal_001", "dataset-1_dance-short_normal_001")


def main() -> int:
    """Print the per-preset floor (cm, upper body) over the benchmark clips."""
    actor = load_actor("m")
    poses = []
    for c in CLIPS:
        p = DATA / "mocap" / "bandai_namco" / f"{c}.bvh"
        if not p.exists():
            print("shared data not found")
            return 1
        poses.append(load_clip(p, actor.skeleton, fps=30.0).poses[:90])
    q = np.concatenate(poses)
    truth = actor.skeleton.joint_positions(q)[:, :11]
    for name in BODY_SHAPES:
        est = Skeleton.from_shape(name).joint_positions(q)[:, :11]
        est = est - (est - truth).mean(axis=1, keepdims=True)
        err = 100 * np.linalg.norm(est - truth, axis=2)
        print(f"preset {name:8s} floor MPJPE {err.mean():5.2f} cm  (per joint "
              f"{' '.join(f'{v:.1f}' for v in err.mean(axis=0))})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
