"""``bodyplay calibrate``: checkerboard photos -> calib.json for a one- or two-webcam rig."""

from __future__ import annotations

import argparse
import glob
import json
import math
from typing import Any

import numpy as np

from bodyplay.capture.calibration import Board, calibrate_rig, rig_geometry
from bodyplay.capture.camera import write_calib
from bodyplay.errors import ConfigError

__all__ = ["register", "run"]


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``calibrate`` sub-command."""
    p = subparsers.add_parser(
        "calibrate",
        help="calibrate cameras from checkerboard photos and write calib.json",
        description=(
            "Intrinsics per camera by Zhang's method; extrinsics from one board seen by every "
            "camera (its reference image), which defines the world: --board-pose floor (board "
            "flat on the floor: Y up is its normal) or wall (board hanging vertically: give "
            "--board-height). Repeat --images once per camera."
        ),
    )
    p.add_argument("--images", action="append", required=True, metavar="GLOB",
                   help="quoted glob of one camera's board photos; repeat per camera")
    p.add_argument("--board", required=True, metavar="COLSxROWS",
                   help="inner corners of the board, e.g. 9x6")
    p.add_argument("--square", type=float, required=True, metavar="METRES",
                   help="edge of one square in metres, e.g. 0.025")
    p.add_argument("--camera-name", action="append", metavar="NAME",
                   help="name per camera (default cam0, cam1, ...); repeat per camera")
    p.add_argument("--reference", action="append", metavar="IMAGE",
                   help="per camera, the photo of the board that defines the world (default: "
                        "the first photo of each camera, sorted by name)")
    p.add_argument("--board-pose", choices=["floor", "wall", "none"], default="floor",
                   help="where the reference board is (default floor); none = intrinsics only")
    p.add_argument("--board-height", type=float, metavar="METRES",
                   help="wall board: height of its centre above the floor")
    p.add_argument("--fit-k3", action="store_true",
                   help="also fit the k3 distortion term (needs many varied photos)")
    p.add_argument("--out", required=True, help="calib.json to write")
    p.add_argument("--json", action="store_true", help="print a machine-readable report")
    p.set_defaults(func=run)


def _expand(pattern: str) -> list[str]:
    files = sorted(glob.glob(pattern))
    if not files:
        raise ConfigError(f"--images {pattern!r} matches no file; quote the glob and check it")
    return files


def run(args: argparse.Namespace) -> int:
    """Calibrate, write calib.json and print the reprojection figures."""
    board = Board.parse(args.board, args.square)
    sets = [_expand(g) for g in args.images]
    result = calibrate_rig(
        sets,
        board,
        args.camera_name,
        reference=args.reference,
        board_pose=args.board_pose,
        board_height=args.board_height,
        fix_k3=not args.fit_k3,
    )
    path = write_calib(args.out, result.cameras)
    report: dict[str, Any] = {
        "calib": str(path),
        "board_pose": result.board_pose,
        "cameras": [
            {
                "name": c.name,
                "size": [c.width, c.height],
                "images_used": len(r.used),
                "images_rejected": [list(x) for x in r.rejected],
                "rms_px": round(r.rms_px, 4),
                "fx": round(float(c.K[0, 0]), 2),
                "fy": round(float(c.K[1, 1]), 2),
                "cx": round(float(c.K[0, 2]), 2),
                "cy": round(float(c.K[1, 2]), 2),
                "dist": [round(float(v), 5) for v in c.dist],
                "extrinsic_rms_px": None if math.isnan(e) else round(e, 4),
                "center_m": [round(float(v), 4) for v in c.center],
            }
            for c, r, e in zip(result.cameras, result.intrinsics, result.extrinsic_rms_px,
                               strict=True)
        ],
        "pairs": [
            {"a": a, "b": b, "axis_angle_deg": round(ang, 2), "baseline_m": round(base, 4)}
            for a, b, ang, base in (rig_geometry(result.cameras) if result.board_pose != "none"
                                    else [])
        ],
    }
    if args.json:
        print(json.dumps(report, indent=2))
        return 0
    for cam in report["cameras"]:
        print(f"{cam['name']}: {cam['size'][0]}x{cam['size'][1]}, {cam['images_used']} images "
              f"used, reprojection RMS {cam['rms_px']:.3f} px")
        print(f"  fx {cam['fx']:.1f}  fy {cam['fy']:.1f}  cx {cam['cx']:.1f}  cy {cam['cy']:.1f}"
              f"  dist {np.round(cam['dist'], 4).tolist()}")
        for name, why in cam["images_rejected"]:
            print(f"  rejected {name}: {why}")
        if cam["extrinsic_rms_px"] is not None:
            print(f"  reference board RMS {cam['extrinsic_rms_px']:.3f} px, centre "
                  f"{cam['center_m']} m")
    for pair in report["pairs"]:
        print(f"{pair['a']}-{pair['b']}: optical axes {pair['axis_angle_deg']:.1f} deg apart, "
              f"baseline {pair['baseline_m']:.3f} m")
    print(f"wrote {path}")
    return 0
