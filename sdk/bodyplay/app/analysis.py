"""Squash-style motion analysis for games: hand speed and acceleration over a round.

The color-shirt paper's "squash analysis" reports the speed and acceleration of
the player's arm. :class:`HandTrace` records both wrists from every pose event of
a run; :meth:`HandTrace.kinematics` differentiates them with a Savitzky-Golay
filter (a local cubic fit over ``window`` seconds, which smooths tracker jitter
instead of amplifying it as plain finite differences would); :meth:`HandTrace.stats`
gives the figures for summary.json and :func:`plot_hand_motion` draws the plot
(OpenCV, no plotting library) with the game's moments marked.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray
from scipy.signal import savgol_filter

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.errors import ConfigError
from bodyplay.events.types import PoseEvent

__all__ = ["HandTrace", "HandKinematics", "Marker", "plot_hand_motion", "HANDS"]

HANDS: tuple[str, ...] = ("l_wrist", "r_wrist")
_COLORS = {"l_wrist": (40, 140, 255), "r_wrist": (255, 70, 50)}  # RGB


@dataclass(frozen=True, eq=False)
class HandKinematics:
    """Per-frame ``times`` (s) and, per wrist, ``speed`` (m/s) and ``accel`` (m/s^2)
    magnitudes; NaN where the wrist was lost."""

    times: NDArray[np.float64]
    speed: dict[str, NDArray[np.float64]]
    accel: dict[str, NDArray[np.float64]]


@dataclass(frozen=True)
class Marker:
    """A moment to mark on the plot: time ``t`` (s), ``label``, RGB ``color``."""

    t: float
    label: str = ""
    color: tuple[int, int, int] = (120, 120, 120)


class HandTrace:
    """Records both wrists from pose events (subscribe :meth:`on_pose` or call it).

    ``window`` is the Savitzky-Golay window in seconds (0.2 s: seven frames at 30 fps).
    Times are taken from the events (capture time), so paused stretches stay visible.
    """

    def __init__(self, window: float = 0.2) -> None:
        if not 0.02 <= window <= 2.0:
            raise ConfigError(f"window must be 0.02..2 seconds, got {window}")
        self.window = float(window)
        self._t: list[float] = []
        self._p: list[NDArray[np.float64]] = []

    def __len__(self) -> int:
        return len(self._t)

    def on_pose(self, event: PoseEvent) -> None:
        """Record one pose (wrists the state calls ``lost`` are recorded as NaN)."""
        p = np.full((len(HANDS), 3), np.nan)
        for k, h in enumerate(HANDS):
            i = JOINT_INDEX[h]
            if event.state[i] != "lost":
                p[k] = event.joints[i]
        self._t.append(float(event.t))
        self._p.append(p)

    def kinematics(self) -> HandKinematics:
        """Smoothed speed and acceleration of each wrist at every recorded frame."""
        t = np.asarray(self._t, dtype=np.float64)
        n = len(t)
        speed: dict[str, NDArray[np.float64]] = {}
        accel: dict[str, NDArray[np.float64]] = {}
        if n < 5:
            for h in HANDS:
                speed[h] = np.full(n, np.nan)
                accel[h] = np.full(n, np.nan)
            return HandKinematics(t, speed, accel)
        P = np.stack(self._p)  # (n, 2, 3)
        dt = float(np.median(np.diff(t)))
        win = max(5, int(round(self.window / dt)) | 1)
        for k, h in enumerate(HANDS):
            x = P[:, k]
            ok = np.all(np.isfinite(x), axis=1)
            sp = np.full(n, np.nan)
            ac = np.full(n, np.nan)
            # differentiate each run of consecutive tracked frames on its own
            edges = np.flatnonzero(np.diff(np.r_[0, ok.astype(np.int8), 0]))
            for a, b in zip(edges[::2], edges[1::2], strict=True):
                if b - a < 5:
                    continue
                w = min(win, (b - a) if (b - a) % 2 else (b - a - 1))
                seg = x[a:b]
                v = savgol_filter(seg, w, 3 if w > 3 else 2, deriv=1, delta=dt, axis=0)
                acc = savgol_filter(seg, w, 3 if w > 3 else 2, deriv=2, delta=dt, axis=0)
                sp[a:b] = np.linalg.norm(v, axis=1)
                ac[a:b] = np.linalg.norm(acc, axis=1)
            speed[h], accel[h] = sp, ac
        return HandKinematics(t, speed, accel)

    def stats(self) -> dict[str, Any]:
        """Per wrist: peak and mean speed (m/s), peak and mean acceleration (m/s^2),
        the time of the peak speed, and the share of frames tracked."""
        kin = self.kinematics()
        out: dict[str, Any] = {}
        for h in HANDS:
            sp, ac = kin.speed[h], kin.accel[h]
            ok = np.isfinite(sp)
            if not ok.any():
                out[h] = {"tracked_share": 0.0}
                continue
            i = int(np.nanargmax(sp))
            out[h] = {
                "peak_speed": round(float(sp[i]), 3),
                "peak_speed_t": round(float(kin.times[i]), 3),
                "mean_speed": round(float(np.nanmean(sp)), 3),
                "peak_accel": round(float(np.nanmax(ac)), 2),
                "mean_accel": round(float(np.nanmean(ac)), 2),
                "tracked_share": round(float(ok.mean()), 4),
            }
        return out


def plot_hand_motion(
    trace: HandTrace,
    path: str | Path,
    markers: Sequence[Marker] = (),
    size: tuple[int, int] = (960, 480),
    title: str = "hand speed and acceleration",
) -> Path:
    """Draw both wrists' speed (top) and acceleration (bottom) over time as a PNG, with
    vertical ``markers`` (e.g. green saves, red goals); returns the path."""
    w, h = size
    if w < 320 or h < 200:
        raise ConfigError(f"plot size must be at least 320x200, got {w}x{h}")
    kin = trace.kinematics()
    img = np.full((h, w, 3), 255, np.uint8)
    t = kin.times
    t0, t1 = (float(t[0]), float(t[-1])) if len(t) > 1 else (0.0, 1.0)
    t1 = t1 if t1 > t0 else t0 + 1.0
    left, right, top0, gap, bottom_pad = 70, 20, 40, 36, 36
    ph = (h - top0 - gap - bottom_pad) // 2
    font = cv2.FONT_HERSHEY_SIMPLEX
    cv2.putText(img, title, (left, 24), font, 0.6, (0, 0, 0), 1, cv2.LINE_AA)
    for k, hand in enumerate(HANDS):
        cv2.putText(img, hand.replace("_wrist", " hand"), (w - 230 + 110 * k, 24), font, 0.5,
                    _COLORS[hand][::-1], 2, cv2.LINE_AA)
    for row, (series, unit) in enumerate(((kin.speed, "speed m/s"), (kin.accel, "accel m/s^2"))):
        top = top0 + row * (ph + gap)
        bottom = top + ph
        vals = np.concatenate([series[hd] for hd in HANDS]) if len(t) else np.zeros(0)
        vmax = float(np.nanpercentile(vals, 99.5)) if np.any(np.isfinite(vals)) else 1.0
        vmax = max(vmax * 1.05, 1e-3)

        def x_of(tt: NDArray[np.float64] | float) -> Any:
            return left + (np.asarray(tt) - t0) / (t1 - t0) * (w - left - right)

        cv2.rectangle(img, (left, top), (w - right, bottom), (0, 0, 0), 1)
        for q in range(5):
            val = vmax * q / 4
            y = int(round(bottom - q / 4 * ph))
            cv2.line(img, (left - 4, y), (left, y), (0, 0, 0), 1)
            cv2.putText(img, f"{val:.1f}", (6, y + 4), font, 0.4, (0, 0, 0), 1, cv2.LINE_AA)
        cv2.putText(img, unit, (left + 6, top + 16), font, 0.45, (60, 60, 60), 1, cv2.LINE_AA)
        for m in markers:
            x = int(round(float(x_of(m.t))))
            if left <= x <= w - right:
                cv2.line(img, (x, top), (x, bottom), m.color[::-1], 1)
        for hand in HANDS:
            ys = bottom - np.clip(series[hand] / vmax, 0.0, 1.0) * ph
            pts = np.stack([x_of(t), ys], axis=1)
            ok = np.all(np.isfinite(pts), axis=1)
            # draw each tracked run as its own polyline (gaps stay gaps)
            edges = np.flatnonzero(np.diff(np.r_[0, ok.astype(np.int8), 0]))
            for a, b in zip(edges[::2], edges[1::2], strict=True):
                if b - a > 1:
                    cv2.polylines(img, [pts[a:b].astype(np.int32).reshape(-1, 1, 2)], False,
                                  _COLORS[hand][::-1], 1, cv2.LINE_AA)
    for q in range(6):
        tt = t0 + (t1 - t0) * q / 5
        x = int(round(float(left + (tt - t0) / (t1 - t0) * (w - left - right))))
        cv2.putText(img, f"{tt:.0f} s", (x - 12, h - 12), font, 0.4, (0, 0, 0), 1, cv2.LINE_AA)
    p = Path(path)
    if not cv2.imwrite(str(p), img):
        raise ConfigError(f"cannot write the plot to {p}")
    return p
