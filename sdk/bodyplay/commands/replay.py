"""``bodyplay replay``: render a recording as a stick figure from any viewpoint, with
per-hand speed and acceleration, like the squash-analysis tool of the color-shirt paper.

The view is a virtual camera (:class:`~bodyplay.capture.camera.Camera` placed with
:func:`~bodyplay.capture.camera.look_at`) orbiting the mean pelvis position at
``--view AZIMUTH,ELEVATION`` degrees (azimuth 0: in front of the person, who faces
+Z; 90: on their left). A side panel plots both wrists' speed and acceleration over
the whole recording with a cursor at the current frame, and the figures are printed.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import BONES, JOINT_INDEX
from bodyplay.capture.camera import Camera, look_at
from bodyplay.capture.video import VideoWriter
from bodyplay.errors import CaptureError, ConfigError
from bodyplay.record.format import read_recording

__all__ = ["register", "run", "hand_kinematics", "view_camera", "draw_skeleton"]

HANDS = ("l_wrist", "r_wrist")
_COLORS = {"l": (255, 140, 40), "r": (40, 60, 255), "c": (230, 230, 230)}  # BGR
_HAND_COLORS = {"l_wrist": (255, 140, 40), "r_wrist": (40, 60, 255)}


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``replay`` sub-command."""
    p = subparsers.add_parser(
        "replay",
        help="render a recording as a stick figure video with hand speeds",
        description="Render a recording's poses from any viewpoint as an mp4 with per-hand "
        "speed and acceleration plots; print the hand figures.",
    )
    p.add_argument("recording", metavar="REC", help="recording file from `bodyplay record`")
    p.add_argument("--out", required=True, help="output video (.mp4, or .avi)")
    p.add_argument("--view", default="30,15", metavar="AZIMUTH,ELEVATION",
                   help="viewpoint in degrees (default 30,15)")
    p.add_argument("--size", default="640x480", metavar="WxH", help="view size in pixels")
    p.add_argument("--distance", type=float, default=4.0, help="camera distance in metres")
    p.add_argument("--csv", default=None, help="also write per-frame hand speeds to this CSV")
    p.set_defaults(func=run)


def _parse_pair(text: str, sep: str, what: str) -> tuple[float, float]:
    try:
        a, b = (float(v) for v in text.lower().split(sep))
    except ValueError:
        raise ConfigError(f"{what} must look like A{sep}B, got {text!r}") from None
    return a, b


def view_camera(center: NDArray[np.float64], azimuth: float, elevation: float,
                distance: float, width: int, height: int) -> Camera:
    """A 50-degree camera ``distance`` metres from ``center`` at the given angles."""
    if not -89.0 <= elevation <= 89.0:
        raise ConfigError(f"elevation must be within -89..89 degrees, got {elevation}")
    az, el = math.radians(azimuth), math.radians(elevation)
    eye = center + distance * np.array(
        [math.sin(az) * math.cos(el), math.sin(el), math.cos(az) * math.cos(el)]
    )
    R, t = look_at(eye, center)
    return Camera.from_fov("view", width, height, 50.0, R, t)


def hand_kinematics(times: NDArray[np.float64], joints: NDArray[np.float64]
                    ) -> dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]]:
    """Speed (m/s) and acceleration magnitude (m/s^2) of each wrist per frame.

    Central differences on the recorded times (NaN where the wrist was lost).
    """
    out: dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}
    for h in HANDS:
        p = joints[:, JOINT_INDEX[h]]
        if len(times) < 3:
            z = np.full(len(times), np.nan)
            out[h] = (z, z.copy())
            continue
        v = np.gradient(p, times, axis=0)
        a = np.gradient(v, times, axis=0)
        out[h] = (np.linalg.norm(v, axis=1), np.linalg.norm(a, axis=1))
    return out


def draw_skeleton(img: NDArray[np.uint8], cam: Camera, joints: NDArray[np.float64]) -> None:
    """Draw the stick figure of one pose (lost joints skipped) into ``img`` (BGR)."""
    uv = cam.project(joints)
    for a, b in BONES:
        pa, pb = uv[JOINT_INDEX[a]], uv[JOINT_INDEX[b]]
        if np.all(np.isfinite(pa)) and np.all(np.isfinite(pb)):
            side = b[0] if b[1] == "_" else "c"
            cv2.line(img, (int(pa[0]), int(pa[1])), (int(pb[0]), int(pb[1])), _COLORS[side], 3,
                     cv2.LINE_AA)
    for p in uv:
        if np.all(np.isfinite(p)):
            cv2.circle(img, (int(p[0]), int(p[1])), 4, (255, 255, 255), -1, cv2.LINE_AA)


def _floor(img: NDArray[np.uint8], cam: Camera, center: NDArray[np.float64]) -> None:
    cx, cz = round(float(center[0])), round(float(center[2]))
    for k in range(-3, 4):
        for a, b in (((cx + k, 0, cz - 3), (cx + k, 0, cz + 3)),
                     ((cx - 3, 0, cz + k), (cx + 3, 0, cz + k))):
            uv = cam.project(np.array([a, b], dtype=float))
            if np.all(np.isfinite(uv)):
                cv2.line(img, tuple(int(v) for v in uv[0]), tuple(int(v) for v in uv[1]),
                         (70, 70, 70), 1, cv2.LINE_AA)


def _panel(times: NDArray[np.float64],
           kin: dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]],
           width: int, height: int) -> tuple[NDArray[np.uint8], list[tuple[int, int, int]]]:
    """The static plot panel and, per plot, (top, bottom, left) for the cursor."""
    img = np.full((height, width, 3), 25, np.uint8)
    boxes: list[tuple[int, int, int]] = []
    half = height // 2
    for k, (label, unit) in enumerate((("speed", "m/s"), ("acceleration", "m/s^2"))):
        top, bottom, left, right = k * half + 24, (k + 1) * half - 12, 44, width - 10
        vals = np.concatenate([kin[h][k] for h in HANDS])
        vmax = float(np.nanpercentile(vals, 99)) if np.any(np.isfinite(vals)) else 1.0
        vmax = max(vmax, 1e-6)
        cv2.rectangle(img, (left, top), (right, bottom), (80, 80, 80), 1)
        cv2.putText(img, f"hand {label} ({unit}), max {vmax:.1f}", (left, top - 8),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.42, (220, 220, 220), 1, cv2.LINE_AA)
        span = max(float(times[-1] - times[0]), 1e-9)
        x = left + (times - times[0]) / span * (right - left)
        for h in HANDS:
            y = bottom - np.clip(kin[h][k] / vmax, 0, 1) * (bottom - top)
            pts = np.stack([x, y], axis=1)
            ok = np.all(np.isfinite(pts), axis=1)
            if ok.sum() > 1:
                cv2.polylines(img, [pts[ok].astype(np.int32).reshape(-1, 1, 2)], False,
                              _HAND_COLORS[h], 1, cv2.LINE_AA)
        boxes.append((top, bottom, left))
    return img, boxes


def run(args: argparse.Namespace) -> int:
    """Render the recording; print per-hand peak and mean speed and peak acceleration."""
    rec = read_recording(args.recording)
    poses = rec.poses
    if len(poses) < 2:
        raise CaptureError(f"{rec.path}: needs at least two poses to replay, has {len(poses)}")
    az, el = _parse_pair(args.view, ",", "--view")
    w, h = (int(v) for v in _parse_pair(args.size, "x", "--size"))
    times, joints = rec.times, rec.joints()
    pelvis = joints[:, JOINT_INDEX["pelvis"]]
    if not np.any(np.isfinite(pelvis)):
        raise CaptureError(f"{rec.path}: the pelvis is never tracked; nothing to centre on")
    center = np.nanmean(pelvis, axis=0)
    center[1] = max(float(center[1]), 0.9)
    cam = view_camera(center, az, el, args.distance, w, h)
    kin = hand_kinematics(times, joints)
    pw = max(w // 2, 240)
    panel, boxes = _panel(times, kin, pw, h)
    out = Path(args.out)
    span = max(float(times[-1] - times[0]), 1e-9)
    with VideoWriter(out, rec.fps) as video:
        for i, p in enumerate(poses):
            view = np.full((h, w, 3), 40, np.uint8)
            _floor(view, cam, center)
            draw_skeleton(view, cam, p.joints)
            cv2.putText(view, f"t {p.t:6.2f} s  frame {p.frame}", (10, 22),
                        cv2.FONT_HERSHEY_SIMPLEX, 0.55, (230, 230, 230), 1, cv2.LINE_AA)
            for k, hand in enumerate(HANDS):
                sp, ac = kin[hand][0][i], kin[hand][1][i]
                cv2.putText(view, f"{hand}: {sp:5.2f} m/s {ac:6.1f} m/s^2", (10, 46 + 20 * k),
                            cv2.FONT_HERSHEY_SIMPLEX, 0.5, _HAND_COLORS[hand], 1, cv2.LINE_AA)
            side = panel.copy()
            x = int(boxes[0][2] + (p.t - times[0]) / span * (pw - 10 - boxes[0][2]))
            for top, bottom, _ in boxes:
                cv2.line(side, (x, top), (x, bottom), (0, 220, 220), 1)
            video.write(np.hstack([view, side])[:, :, ::-1])  # drawn in BGR; write RGB
    for hand in HANDS:
        sp, ac = kin[hand]
        if not np.any(np.isfinite(sp)):
            print(f"{hand}: never tracked")
            continue
        i = int(np.nanargmax(sp))
        print(f"{hand}: peak speed {sp[i]:.2f} m/s at t={times[i]:.2f} s, mean "
              f"{np.nanmean(sp):.2f} m/s, peak acceleration {np.nanmax(ac):.1f} m/s^2")
    if args.csv:
        with open(args.csv, "w") as fh:
            fh.write("frame,t," + ",".join(f"{h}_speed,{h}_accel" for h in HANDS) + "\n")
            for i, p in enumerate(poses):
                vals = [f"{kin[hd][k][i]:.4f}" for hd in HANDS for k in (0, 1)]
                fh.write(f"{p.frame},{p.t:.6f}," + ",".join(vals) + "\n")
    print(f"wrote {len(poses)} frames to {out}", file=sys.stderr)
    return 0
