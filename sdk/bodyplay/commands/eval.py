"""``bodyplay eval``: compare a tracker's poses.jsonl with a truth.jsonl."""

from __future__ import annotations

import argparse
import json

from bodyplay.capture.jsonl import read_pose_jsonl
from bodyplay.errors import CaptureError
from bodyplay.evaluation import JOINT_SETS, evaluate, plot_errors

__all__ = ["register", "run"]


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``eval`` sub-command."""
    p = subparsers.add_parser(
        "eval",
        help="accuracy of poses.jsonl against truth.jsonl (MPJPE, PCK, tracked share, jitter)",
        description=(
            "Match frames by number and report MPJPE (cm), per-joint errors, PCK, the share "
            "of frames and joints tracked, jitter (m/s^2) and the median processing time. "
            "Joints reported null count as missed, never as zero error."
        ),
    )
    p.add_argument("--truth", required=True, help="truth.jsonl")
    p.add_argument("--poses", required=True, help="poses.jsonl written by a tracker")
    p.add_argument("--joints", choices=sorted(JOINT_SETS), default="upper",
                   help="joint set to score (default: upper = the first eleven)")
    p.add_argument("--pck", type=float, nargs="+", default=[5.0, 10.0], metavar="CM",
                   help="PCK thresholds in cm (default 5 10)")
    p.add_argument("--json", action="store_true", help="print a machine-readable summary")
    p.add_argument("--plot", metavar="FILE.png", help="draw the per-frame error over time")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Evaluate and print the table (or JSON); write the plot when asked."""
    truth = read_pose_jsonl(args.truth)
    poses = read_pose_jsonl(args.poses)
    for path, track in ((args.truth, truth), (args.poses, poses)):
        if len(track) == 0:
            raise CaptureError(f"{path}: no frames; nothing to evaluate")
    result = evaluate(truth, poses, joints=args.joints, thresholds_cm=args.pck)
    if args.plot:
        plot_errors(result, args.plot)
    if args.json:
        print(json.dumps(result.to_json(), indent=2))
    else:
        print(result.table())
        if args.plot:
            print(f"plot: {args.plot}")
    return 0
