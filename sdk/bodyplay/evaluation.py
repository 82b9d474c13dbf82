"""Accuracy of a tracker's poses against a truth: MPJPE, PCK, tracked share, jitter.

Frames are matched by their ``frame`` number. The evaluation set is every truth frame
and joint (of the chosen joint set) whose truth position is known. A joint the
tracker reported as null, and every joint of a truth frame the tracker wrote no record
for, counts as *missed*: it is left out of the mean error (never counted as zero
error), lowers the tracked share and counts as a miss in PCK. Jitter is the mean
magnitude of the second difference of positions over three consecutive frames,
divided by the frame interval squared: m/s^2, for the estimate and for the truth on
the same frames, so a filter's smoothing can be compared with the motion's own.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX, JOINT_NAMES, UPPER_BODY
from bodyplay.capture.jsonl import PoseTrack
from bodyplay.errors import ConfigError

__all__ = ["EvalResult", "evaluate", "plot_errors", "JOINT_SETS"]

JOINT_SETS: dict[str, tuple[str, ...]] = {"upper": UPPER_BODY, "all": JOINT_NAMES}
"""Named joint selections for :func:`evaluate` and ``bodyplay eval --joints``."""


def _num(x: float) -> float | None:
    """A float for JSON: NaN becomes null."""
    return None if not math.isfinite(x) else round(float(x), 6)


@dataclass(frozen=True, eq=False)
class EvalResult:
    """The figures of one evaluation (errors in cm, shares in 0..1).

    ``frames`` are the truth frames evaluated; ``frame_error_cm`` the mean error over
    the reported joints of each (NaN when none was reported) and ``frame_missed`` the
    number of joints missed in each. ``pck`` maps thresholds in cm to the share of
    joint-frames within them. Jitter is in m/s^2 (estimate, and truth on the same
    frames); ``ms_median`` is the median processing time of matched frames.
    """

    joints: tuple[str, ...]
    n_truth_frames: int
    n_matched_frames: int
    n_missing_frames: int
    n_extra_frames: int
    mpjpe_cm: float
    per_joint_cm: dict[str, float]
    per_joint_tracked: dict[str, float]
    pck: dict[float, float]
    frames_tracked: float
    joints_tracked: float
    jitter_ms2: float
    truth_jitter_ms2: float
    ms_median: float
    frames: NDArray[np.int64]
    frame_error_cm: NDArray[np.float64]
    frame_missed: NDArray[np.int64]

    @property
    def pck5(self) -> float:
        """Share of joint-frames within 5 cm (misses count as outside)."""
        return self.pck.get(5.0, math.nan)

    @property
    def pck10(self) -> float:
        """Share of joint-frames within 10 cm (misses count as outside)."""
        return self.pck.get(10.0, math.nan)

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready summary (NaN written as null; per-frame series left out)."""
        return {
            "joints": list(self.joints),
            "n_truth_frames": self.n_truth_frames,
            "n_matched_frames": self.n_matched_frames,
            "n_missing_frames": self.n_missing_frames,
            "n_extra_frames": self.n_extra_frames,
            "mpjpe_cm": _num(self.mpjpe_cm),
            "per_joint_cm": {k: _num(v) for k, v in self.per_joint_cm.items()},
            "per_joint_tracked": {k: _num(v) for k, v in self.per_joint_tracked.items()},
            "pck": {f"{k:g}": _num(v) for k, v in self.pck.items()},
            "frames_tracked": _num(self.frames_tracked),
            "joints_tracked": _num(self.joints_tracked),
            "jitter_ms2": _num(self.jitter_ms2),
            "truth_jitter_ms2": _num(self.truth_jitter_ms2),
            "ms_median": _num(self.ms_median),
        }

    def table(self) -> str:
        """A human-readable table of the summary and the per-joint figures."""

        def f(x: float, fmt: str = "{:.2f}") -> str:
            return fmt.format(x) if math.isfinite(x) else "-"

        lines = [
            f"frames: {self.n_truth_frames} truth, {self.n_matched_frames} matched, "
            f"{self.n_missing_frames} without estimate, {self.n_extra_frames} estimate-only",
            f"MPJPE            {f(self.mpjpe_cm)} cm  (over reported joints)",
        ]
        for thr, share in self.pck.items():
            lines.append(f"PCK@{thr:g}cm{' ' * max(1, 9 - len(f'{thr:g}'))}"
                         f"{f(100 * share, '{:.1f}')} %")
        lines += [
            f"frames tracked   {f(100 * self.frames_tracked, '{:.1f}')} %  (every joint reported)",
            f"joints tracked   {f(100 * self.joints_tracked, '{:.1f}')} %",
            f"jitter           {f(self.jitter_ms2)} m/s^2  (truth {f(self.truth_jitter_ms2)}"
            " m/s^2)",
            f"time per frame   {f(self.ms_median, '{:.1f}')} ms median",
            "",
            f"{'joint':<12}{'error cm':>10}{'tracked %':>11}",
        ]
        for name in self.joints:
            lines.append(
                f"{name:<12}{f(self.per_joint_cm[name]):>10}"
                f"{f(100 * self.per_joint_tracked[name], '{:.1f}'):>11}"
            )
        return "\n".join(lines)

    def to_json_str(self) -> str:
        """:meth:`to_json` as a JSON string."""
        return json.dumps(self.to_json(), indent=2)


def _frame_interval(track: PoseTrack) -> float:
    """Seconds per frame number, from the track's timestamps (NaN if unknown)."""
    if len(track) < 2:
        return math.nan
    df = np.diff(track.frames.astype(float))
    dt = np.diff(track.t)
    ok = (df > 0) & (dt > 0)
    if not np.any(ok):
        return math.nan
    return float(np.median(dt[ok] / df[ok]))


def _jitter(pos: NDArray[np.float64], frames: NDArray[np.int64], dt: float) -> NDArray[np.float64]:
    """(M-2, J) acceleration magnitudes at the middle of consecutive frame triplets."""
    if pos.shape[0] < 3 or not math.isfinite(dt):
        return np.zeros((0, pos.shape[1]))
    consecutive = (frames[2:] - frames[1:-1] == 1) & (frames[1:-1] - frames[:-2] == 1)
    acc = (pos[2:] - 2 * pos[1:-1] + pos[:-2]) / (dt * dt)
    mag = np.linalg.norm(acc, axis=-1)
    mag[~consecutive] = np.nan
    return mag


def evaluate(
    truth: PoseTrack,
    poses: PoseTrack,
    joints: Literal["upper", "all"] | Sequence[str] = "upper",
    thresholds_cm: Sequence[float] = (5.0, 10.0),
) -> EvalResult:
    """Compare ``poses`` with ``truth`` over the selected joints (see module docs)."""
    if isinstance(joints, str):
        if joints not in JOINT_SETS:
            raise ConfigError(
                f"joints must be one of {sorted(JOINT_SETS)} or names, got {joints!r}"
            )
        names = JOINT_SETS[joints]
    else:
        names = tuple(joints)
        unknown = [n for n in names if n not in JOINT_INDEX]
        if unknown or not names:
            raise ConfigError(f"unknown joints {unknown}; expected names from JOINT_NAMES")
    thresholds = tuple(float(x) for x in thresholds_cm)
    if any(not (x > 0) for x in thresholds):
        raise ConfigError(f"PCK thresholds must be positive cm, got {thresholds}")
    if len(truth) == 0:
        raise ConfigError("the truth has no frames; nothing to evaluate")
    idx = np.array([JOINT_INDEX[n] for n in names])

    pose_pos = {int(f): i for i, f in enumerate(poses.frames)}
    rows = np.array([pose_pos.get(int(f), -1) for f in truth.frames])
    matched = rows >= 0
    truth_j = truth.joints[:, idx]  # (N, J, 3)
    est_j = np.full_like(truth_j, np.nan)
    est_j[matched] = poses.joints[rows[matched]][:, idx]
    valid = np.all(np.isfinite(truth_j), axis=-1)  # judged joint-frames
    reported = valid & np.all(np.isfinite(est_j), axis=-1)
    err = np.linalg.norm(est_j - truth_j, axis=-1) * 100.0  # cm, NaN if missed
    err[~reported] = np.nan

    n_valid = int(valid.sum())
    with np.errstate(invalid="ignore"):
        mpjpe = float(np.nanmean(err[reported])) if reported.any() else math.nan
        per_joint = {
            n: (float(np.mean(err[reported[:, k], k])) if reported[:, k].any() else math.nan)
            for k, n in enumerate(names)
        }
        per_joint_tracked = {
            n: (float(reported[:, k].sum() / valid[:, k].sum()) if valid[:, k].any() else math.nan)
            for k, n in enumerate(names)
        }
        pck = {
            thr: (float(np.sum(reported & (np.nan_to_num(err, nan=np.inf) <= thr)) / n_valid)
                  if n_valid else math.nan)
            for thr in thresholds
        }
    frame_has_truth = valid.any(axis=1)
    frame_full = np.all(reported == valid, axis=1) & frame_has_truth
    frames_tracked = (
        float(frame_full.sum() / frame_has_truth.sum()) if frame_has_truth.any() else math.nan
    )
    joints_tracked = float(reported.sum() / n_valid) if n_valid else math.nan
    counts = reported.sum(axis=1)
    sums = np.where(reported, err, 0.0).sum(axis=1)
    frame_err = np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)
    frame_missed = (valid & ~reported).sum(axis=1).astype(np.int64)

    dt = _frame_interval(truth)
    acc_est = _jitter(est_j, truth.frames, dt)
    acc_tru = _jitter(truth_j, truth.frames, dt)
    both = np.isfinite(acc_est) & np.isfinite(acc_tru)
    jitter = float(acc_est[both].mean()) if both.any() else math.nan
    truth_jitter = float(acc_tru[both].mean()) if both.any() else math.nan

    ms = poses.ms[rows[matched]] if matched.any() else np.zeros(0)
    ms = ms[np.isfinite(ms)]
    ms_median = float(np.median(ms)) if ms.size else math.nan
    extra = int(np.setdiff1d(poses.frames, truth.frames).size)

    return EvalResult(
        joints=names,
        n_truth_frames=len(truth),
        n_matched_frames=int(matched.sum()),
        n_missing_frames=int((~matched).sum()),
        n_extra_frames=extra,
        mpjpe_cm=mpjpe,
        per_joint_cm=per_joint,
        per_joint_tracked=per_joint_tracked,
        pck=pck,
        frames_tracked=frames_tracked,
        joints_tracked=joints_tracked,
        jitter_ms2=jitter,
        truth_jitter_ms2=truth_jitter,
        ms_median=ms_median,
        frames=truth.frames.copy(),
        frame_error_cm=frame_err.astype(np.float64),
        frame_missed=frame_missed,
    )


def plot_errors(result: EvalResult, path: str | Path, size: tuple[int, int] = (900, 360)) -> Path:
    """Draw the mean error per frame over time as a PNG (missed joints marked in red).

    The blue line is the per-frame mean error of reported joints (cm); a red tick at
    the bottom marks each frame where a joint was missed, its height growing with
    the number missed; grey gaps are frames where nothing was reported.
    """
    w, h = size
    if w < 200 or h < 120:
        raise ConfigError(f"plot size must be at least 200x120, got {w}x{h}")
    img = np.full((h, w, 3), 255, np.uint8)
    left, right, top, bottom = 60, 15, 25, 40
    pw, ph = w - left - right, h - top - bottom
    frames = result.frames.astype(float)
    err = result.frame_error_cm
    f0, f1 = (frames[0], frames[-1]) if frames.size else (0.0, 1.0)
    f1 = f1 if f1 > f0 else f0 + 1
    ymax = float(np.nanmax(err)) if np.any(np.isfinite(err)) else 1.0
    ymax = max(ymax * 1.1, 1.0)

    def xy(f: float, e: float) -> tuple[int, int]:
        return (
            int(round(left + (f - f0) / (f1 - f0) * pw)),
            int(round(top + ph - e / ymax * ph)),
        )

    cv2.rectangle(img, (left, top), (left + pw, top + ph), (0, 0, 0), 1)
    for k in range(5):
        e = ymax * k / 4
        y = xy(f0, e)[1]
        cv2.line(img, (left - 4, y), (left, y), (0, 0, 0), 1)
        cv2.putText(img, f"{e:.1f}", (5, y + 4), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (0, 0, 0), 1)
    for k in range(5):
        f = f0 + (f1 - f0) * k / 4
        x = xy(f, 0)[0]
        cv2.line(img, (x, top + ph), (x, top + ph + 4), (0, 0, 0), 1)
        cv2.putText(img, f"{int(round(f))}", (x - 12, top + ph + 18), cv2.FONT_HERSHEY_SIMPLEX,
                    0.4, (0, 0, 0), 1)
    nj = max(len(result.joints), 1)
    for f, m in zip(frames, result.frame_missed, strict=True):
        if m > 0:
            x = xy(f, 0)[0]
            cv2.line(img, (x, top + ph), (x, top + ph - int(ph * 0.15 * m / nj) - 2),
                     (0, 0, 220), 1)
    pts: list[tuple[int, int]] = []
    for f, e in zip(frames, err, strict=True):
        if math.isfinite(e):
            pts.append(xy(f, e))
        elif pts:
            cv2.polylines(img, [np.array(pts, np.int32)], False, (200, 90, 0), 1, cv2.LINE_AA)
            pts = []
    if pts:
        cv2.polylines(img, [np.array(pts, np.int32)], False, (200, 90, 0), 1, cv2.LINE_AA)
    title = (f"mean joint error per frame (cm); MPJPE {result.mpjpe_cm:.2f} cm; "
             "red: missed joints")
    cv2.putText(img, title, (left, 16), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (0, 0, 0), 1)
    cv2.putText(img, "frame", (left + pw // 2 - 20, h - 6), cv2.FONT_HERSHEY_SIMPLEX, 0.4,
                (0, 0, 0), 1)
    p = Path(path)
    if not cv2.imwrite(str(p), img):
        raise ConfigError(f"{p}: cannot write the plot; check the folder exists and the suffix")
    return p
