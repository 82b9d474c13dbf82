"""Systematic offsets of the color-shirt tracker's joints against the synthetic truth.

``colorshirt_decompose.py`` splits a validation run's error by clip, frame and joint
from the errors' sizes; this script keeps their directions. It tracks the captures
of ``colorshirt_validation.py`` (the same cache, clips, halves and settings) and, on
every frame with a pose after the first ``--skip`` seconds (the start), expresses
each upper-body joint's error in the *truth body's frame*: ``x`` towards the
player's left (right hip to left hip, level), ``y`` up, ``z`` the way the player
faces. Per clip it prints the mean offset of the torso joints (a bias every frame
shares: a model that sits differently in the body than the truth does, not noise),
and along each arm how far the elbow and the wrist sit along their bone (negative:
short of the truth) and how much longer the tracker's upper arm and forearm are
than the truth's. The last lines give the median over clips, and the MPJPE with
each joint's median offset over clips taken away: what a fix of that systematic
part alone could give.

    nice .venv/bin/python benchmarks/colorshirt_offsets.py --half tune --setting steady-2-empty
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

import colorshirt_validation as validation
from _machine import machine
from bodyplay.body.joints import JOINT_INDEX, UPPER_BODY
from bodyplay.capture.frames import FrameSet
from bodyplay.capture.jsonl import read_pose_jsonl
from bodyplay.capture.sources import open_source
from bodyplay.trackers.colorshirt import ColorShirtOptions, create_colorshirt_tracker

_ARMS = (("l", JOINT_INDEX["l_shoulder"], JOINT_INDEX["l_elbow"], JOINT_INDEX["l_wrist"]),
         ("r", JOINT_INDEX["r_shoulder"], JOINT_INDEX["r_elbow"], JOINT_INDEX["r_wrist"]))
_ARM_COLUMNS = tuple(f"{s}_{what}" for s, *_ in _ARMS
                     for what in ("elbow_along", "wrist_along", "upper_len", "fore_len"))


def body_frame(truth: NDArray[np.float64]) -> NDArray[np.float64]:
    """(3, 3) rows x (right hip to left hip, level), y (up), z (facing) of a truth
    pose's 17 joints."""
    lat = truth[JOINT_INDEX["l_hip"]] - truth[JOINT_INDEX["r_hip"]]
    lat[1] = 0.0
    lat /= np.linalg.norm(lat)
    up = np.array([0.0, 1.0, 0.0])
    return np.stack([lat, up, np.cross(lat, up)])


def frame_offsets(joints: NDArray[np.float64], truth: NDArray[np.float64]
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """One frame: (11, 3) upper-body errors in the truth body's frame, and per arm the
    elbow's and the wrist's error along their bones and the upper arm's and the
    forearm's length error (8,), all in metres."""
    d = (joints[:11] - truth[:11]) @ body_frame(truth).T
    arm = []
    for _, sh, el, wr in _ARMS:
        ua, fa = truth[el] - truth[sh], truth[wr] - truth[el]
        arm += [float((joints[el] - truth[el]) @ ua / np.linalg.norm(ua)),
                float((joints[wr] - truth[wr]) @ fa / np.linalg.norm(fa)),
                float(np.linalg.norm(joints[el] - joints[sh]) - np.linalg.norm(ua)),
                float(np.linalg.norm(joints[wr] - joints[el]) - np.linalg.norm(fa))]
    return d, np.array(arm)


def track_offsets(folder: Path, setting: validation.Setting, options: ColorShirtOptions,
                  db: object, skip: float) -> tuple[NDArray[np.float64], NDArray[np.float64], str]:
    """Track one capture; (F, 11, 3) body-frame errors and (F, 8) arm figures of its
    frames with a pose after ``skip`` seconds of the clip, and the body chosen."""
    truth = read_pose_jsonl(folder / "truth.jsonl")
    src = open_source(folder)
    assert src.cameras is not None
    cams = src.cameras[: setting.cameras]
    tracker = create_colorshirt_tracker(options, cams, database=db)  # type: ignore[arg-type]
    offs, arms = [], []
    first: float | None = None
    with src:
        for fs in src:
            t = truth.joints[fs.index]
            has = bool(np.isfinite(t[0]).all())
            if setting.start == "view" and not has:
                continue
            r = tracker.process(FrameSet(fs.frames[: setting.cameras], fs.t, fs.index))
            if not has:
                continue
            first = fs.t if first is None else first
            if r.found and fs.t - first >= skip:
                d, a = frame_offsets(r.joints, t)
                offs.append(d)
                arms.append(a)
    return (np.array(offs).reshape(-1, 11, 3), np.array(arms).reshape(-1, 8),
            tracker.body_name)


def main(argv: list[str] | None = None) -> int:
    """Track a half's clips in one setting and print the joints' systematic offsets."""
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    validation.add_capture_arguments(ap, "steady-2-empty")
    ap.add_argument("--skip", type=float, default=1.0, help="seconds of each clip left out")
    args = ap.parse_args(argv)
    if not (validation.MOCAP / "bandai_namco").exists():
        print("shared data not found (../shared/data/mocap); nothing to measure")
        return 1
    setting = {s.name: s for s in validation.SETTINGS}[args.setting]
    options = validation.options_from(args)
    print(f"# colorshirt offsets, half {args.half}, {args.setting}, {machine()}, "
          f"options {' '.join(args.set) or 'default'}; cm, truth body frame "
          f"(x left, y up, z facing), after {args.skip:g} s", flush=True)
    print("| clip | body | MPJPE | pelvis x y z | spine z | chest z | neck z | "
          + " | ".join(_ARM_COLUMNS) + " |")
    print("|---|---|---" + "|---" * (4 + len(_ARM_COLUMNS)) + "|")
    means, arm_means, errors = [], [], []
    for clip, folder, db in validation.half_captures(args, setting):
        offs, arms, body = track_offsets(folder, setting, options, db, args.skip)
        if not len(offs):
            print(f"| {clip.name} | {body} | no pose |")
            continue
        m, a = 100 * offs.mean(0), 100 * arms.mean(0)
        means.append(m)
        arm_means.append(a)
        errors.append(100 * offs)
        p = m[JOINT_INDEX["pelvis"]]
        print(f"| {clip.name} | {body} | {np.linalg.norm(errors[-1], axis=2).mean():.2f} | "
              f"{p[0]:.1f} {p[1]:.1f} {p[2]:.1f} | "
              + " | ".join(f"{m[JOINT_INDEX[j], 2]:.1f}" for j in ("spine", "chest", "neck"))
              + " | " + " | ".join(f"{v:.1f}" for v in a) + " |", flush=True)
    if not means:
        return 1
    med = np.median(np.array(means), axis=0)
    print("\nmedian over clips of each clip's mean offset (cm, x / y / z), and each "
          "joint's mean error size:")
    for j, name in enumerate(UPPER_BODY):
        size = np.median([np.linalg.norm(e[:, j], axis=1).mean() for e in errors])
        print(f"  {name:11s} {med[j, 0]:5.1f} {med[j, 1]:5.1f} {med[j, 2]:5.1f}   "
              f"|error| {size:5.2f}")
    print("  arms (median over clips): " + ", ".join(
        f"{c} {v:.1f}" for c, v in zip(_ARM_COLUMNS, np.median(arm_means, axis=0), strict=True)))
    before = [np.linalg.norm(e, axis=2).mean() for e in errors]
    after = [np.linalg.norm(e - med, axis=2).mean() for e in errors]
    print(f"MPJPE after the skip, median / mean / worst clip: {np.median(before):.2f} / "
          f"{np.mean(before):.2f} / {np.max(before):.2f}; with the median offsets taken "
          f"away: {np.median(after):.2f} / {np.mean(after):.2f} / {np.max(after):.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
