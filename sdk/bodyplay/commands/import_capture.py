"""``bodyplay import``: turn a Pose2Sim or Sports2D recording into a capture folder."""

from __future__ import annotations

import argparse

from bodyplay.capture.external import import_capture


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``import`` sub-command."""
    p = subparsers.add_parser(
        "import",
        help="make a capture folder (cam0.mp4 ..., calib.json) from Pose2Sim/Sports2D data",
        description="Write a bodyplay capture folder from a Pose2Sim project "
        "(calibration/Calib.qca.txt + videos/) or a Sports2D folder (Calib*.toml + *.mp4).",
    )
    p.add_argument("source", help="the Pose2Sim project or Sports2D folder")
    p.add_argument("--out", required=True, help="capture folder to write")
    p.add_argument("--cameras", nargs="*", help="video stems to keep, in order (default: all)")
    p.add_argument("--copy", action="store_true", help="copy videos instead of symlinking")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Write the capture folder and print where it is."""
    out = import_capture(args.source, args.out, cameras=args.cameras, copy=args.copy)
    print(f"capture folder: {out}")
    return 0
