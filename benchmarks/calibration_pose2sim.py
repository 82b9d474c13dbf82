"""Checkerboard calibration of the Pose2Sim rig against its Qualisys calibration.

Calibrates each of the four cameras from the checkerboard photos shipped with the
Pose2Sim demo (7x4 inner corners, 60 mm squares, per its Config.toml) and prints
focal lengths, principal points, distortion and reprojection RMS next to the values
of Calib.qca.txt, plus the Qualisys rig geometry (angles between optical axes,
baselines). Run: ``.venv/bin/python benchmarks/calibration_pose2sim.py``.
"""

from __future__ import annotations

import datetime
import platform
import sys
import time
from pathlib import Path

import cv2
import numpy as np

from bodyplay.capture.calibration import (
    Board,
    calibrate_intrinsics,
    read_qualisys_calib,
    rig_geometry,
)
from bodyplay.capture.camera import Camera

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "video" / "pose2sim_single"
BOARD = Board(7, 4, 0.06)


def border_distortion_px(cam: Camera) -> float:
    """Largest shift the distortion model applies to a point on the image border."""
    n = 60
    w, h = cam.width - 1, cam.height - 1
    u = np.concatenate([np.linspace(0, w, n), np.full(n, w), np.linspace(0, w, n), np.zeros(n)])
    v = np.concatenate([np.zeros(n), np.linspace(0, h, n), np.full(n, h), np.linspace(0, h, n)])
    pts = np.stack([u, v], -1).reshape(-1, 1, 2)
    und = cv2.undistortPoints(pts, cam.K, cam.dist, P=cam.K).reshape(-1, 2)
    return float(np.linalg.norm(und - pts.reshape(-1, 2), axis=1).max())


def main() -> int:
    """Print the agreement table."""
    calib = DATA / "calibration"
    if not calib.is_dir():
        print(f"no data at {calib}", file=sys.stderr)
        return 1
    qualisys = read_qualisys_calib(calib / "Calib.qca.txt")
    print(f"# {datetime.date.today()} on {platform.node()} ({platform.processor() or 'cpu'})")
    print("| camera | views used | RMS px | fx / fy (ours) | fx / fy (Qualisys) | df % |"
          " cx, cy (ours) | cx, cy (Qualisys) | d(c) px | k1, k2 (ours) | k1, k2 (Qualisys) |"
          " border distortion px ours / Qualisys | s |")
    print("|" + "---|" * 13)
    for q in qualisys:
        files = sorted((calib / "intrinsics" / f"int_{q.name}_img").glob("*.jpg"))
        t0 = time.perf_counter()
        r = calibrate_intrinsics(files, BOARD, q.name)
        dt = time.perf_counter() - t0
        a = r.camera
        df = 100 * (a.K[0, 0] / q.K[0, 0] - 1)
        dc = float(np.hypot(a.K[0, 2] - q.K[0, 2], a.K[1, 2] - q.K[1, 2]))
        print(
            f"| {q.name} | {len(r.used)}/{len(files)} | {r.rms_px:.3f} "
            f"| {a.K[0, 0]:.1f} / {a.K[1, 1]:.1f} | {q.K[0, 0]:.1f} / {q.K[1, 1]:.1f} | {df:+.2f} "
            f"| {a.K[0, 2]:.1f}, {a.K[1, 2]:.1f} | {q.K[0, 2]:.1f}, {q.K[1, 2]:.1f} | {dc:.1f} "
            f"| {a.dist[0]:.4f}, {a.dist[1]:.4f} | {q.dist[0]:.4f}, {q.dist[1]:.4f} "
            f"| {border_distortion_px(a):.1f} / {border_distortion_px(q):.1f} | {dt:.1f} |"
        )
    print()
    print("Qualisys rig geometry (pairs): optical-axis angle deg, baseline m")
    for a_name, b_name, ang, base in rig_geometry(qualisys):
        print(f"  {a_name}-{b_name}: {ang:6.1f} deg  {base:.3f} m")
    return 0


if __name__ == "__main__":
    sys.exit(main())
