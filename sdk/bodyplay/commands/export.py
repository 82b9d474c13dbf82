"""``bodyplay export``: convert a recording's poses to BVH or poses.jsonl.

BVH export fits skeleton pose vectors to the recorded joints
(``bodyplay.motion.poses_from_joints``) and writes them with ``write_bvh``; lost
joints keep their last solvable rotation.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

import numpy as np

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import CaptureError, reading
from bodyplay.record.format import read_recording

__all__ = ["register", "run"]


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``export`` sub-command."""
    p = subparsers.add_parser(
        "export",
        help="export a recording's poses as BVH or poses.jsonl",
        description="Export the poses of a recording (from `bodyplay record`).",
    )
    p.add_argument("recording", metavar="REC")
    p.add_argument("--format", choices=("bvh", "poses"), default="bvh",
                   help="bvh (skeleton animation) or poses (poses.jsonl, DESIGN.md)")
    p.add_argument("--out", required=True)
    p.add_argument("--shape", default="m", help="body shape of the BVH skeleton (default m)")
    p.add_argument("--player", type=int, default=0, help="which player's poses")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Write the export; print how many frames went out."""
    rec = read_recording(args.recording)
    poses = [p for p in rec.poses if p.player == args.player]
    if not poses:
        raise CaptureError(f"{rec.path}: no poses of player {args.player} to export")
    with reading(rec.path, CaptureError, "recording"):
        _export(args, rec, poses)
    print(f"exported {len(poses)} frames to {args.out}", file=sys.stderr)
    return 0


def _export(args: argparse.Namespace, rec: Any, poses: list[Any]) -> None:
    joints = np.stack([p.joints for p in poses])
    if args.format == "bvh":
        from bodyplay.motion.bvh import write_bvh
        from bodyplay.motion.retarget import poses_from_joints

        sk = Skeleton.from_shape(args.shape)
        q = poses_from_joints(sk, joints)
        write_bvh(args.out, sk, q, rec.fps)
    else:
        from bodyplay.capture.jsonl import PoseTrack, write_pose_jsonl

        track = PoseTrack(
            frames=np.array([p.frame for p in poses]),
            t=np.array([p.t for p in poses]),
            joints=joints,
            state=np.array([p.state for p in poses]),
            ms=np.full(len(poses), np.nan),
        )
        write_pose_jsonl(args.out, track, ms=False)
