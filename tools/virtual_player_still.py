"""Make docs/img/virtual_keeper.png and docs/img/virtual_keeper_reaches.png.

Run: .venv/bin/python tools/virtual_player_still.py [--out docs/img/virtual_keeper.png]
     [--reaches docs/img/virtual_keeper_reaches.png]

The first: a ReachController keeper filmed by two synthetic cameras and tracked by
the color-shirt tracker; three moments of camera 0 (the ready stance, a reach to its
left, a two-handed catch) are cropped side by side, with the true joints (green)
and the tracked ones (red) drawn on them. The second: one synthetic frame at the
arrival of each of six balls (a wide ball: lunge; a low one: crouch; low in the
middle: both hands; a header; high in the middle; high to the side), no tracking.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

from bodyplay.body.joints import BONES, JOINT_INDEX
from bodyplay.runtime.session import create_session
from bodyplay.virtual import ReachController, VirtualPlayerSource

BALLS = ((0.3, 1.0, (0.55, 1.45, 0.3)), (1.4, 2.1, (0.0, 1.15, 0.35)))
MOMENTS = (0.3, 0.97, 2.07)
REACHES = ((-1.25, 1.1, 0.3), (0.45, 0.3, 0.35), (0.0, 0.3, 0.4), (0.02, 1.63, 0.25),
           (0.0, 2.0, 0.3), (0.75, 1.85, 0.3))


def _draw(img: np.ndarray, uv: np.ndarray, color: tuple[int, int, int]) -> None:
    for a, b in BONES:
        ia, ib = JOINT_INDEX[a], JOINT_INDEX[b]
        if ia < 11 and ib < 11 and np.all(np.isfinite(uv[[ia, ib]])):
            cv2.line(img, tuple(int(v) for v in uv[ia]), tuple(int(v) for v in uv[ib]),
                     color, 2, cv2.LINE_AA)
    for p in uv[:11]:
        if np.all(np.isfinite(p)):
            cv2.circle(img, (int(p[0]), int(p[1])), 4, color, -1, cv2.LINE_AA)


def reaches(out: Path) -> None:
    """One frame at the arrival of each ball of REACHES, side by side."""
    tiles = []
    for point in REACHES:
        keeper = ReachController()
        with VirtualPlayerSource(keeper, seconds=0.9, seed=3, size=(480, 360)) as src:
            for fs in src:
                if fs.index == 0:
                    keeper.set_target(0.9, point, now=0.0)
                if abs(fs.t - 0.9) < 1e-6 and src.cameras and src.truth is not None:
                    # centred between the body and the ball, so a wide reach fits
                    uv = src.cameras[0].project(np.stack([src.truth[0], np.asarray(point)]))
                    x0 = int(np.clip(uv[:, 0].mean() - 160, 0, 480 - 320))
                    tiles.append(fs.frames[0].image[20:340, x0:x0 + 320])
    _save(out, np.concatenate(tiles, axis=1))


def _save(out: Path, rgb: np.ndarray) -> None:
    out.parent.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(str(out), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_PNG_COMPRESSION, 9])
    print(f"wrote {out} ({out.stat().st_size // 1024} KB)")


def main() -> int:
    """Render, track, crop, save."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", default="docs/img/virtual_keeper.png")
    ap.add_argument("--reaches", default="docs/img/virtual_keeper_reaches.png")
    args = ap.parse_args()
    reaches(Path(args.reaches))
    keeper = ReachController()
    src = VirtualPlayerSource(keeper, cameras=2, seconds=2.2, seed=3)
    session = create_session(source=src, tracker="colorshirt")
    pending = list(BALLS)
    tiles = []
    assert src.cameras is not None
    cam = src.cameras[0]
    with session:
        while (ev := session.step()) is not None or not session.done:
            assert src.last is not None
            t = src.last.t
            while pending and pending[0][0] <= t + 1e-9:
                _, arrival, point = pending.pop(0)
                keeper.set_target(arrival, point, now=t)
            if ev is None or src.truth is None or not any(abs(t - m) < 0.017 for m in MOMENTS):
                continue
            img = src.last.frames[0].image.copy()
            _draw(img, cam.project(src.truth), (40, 220, 40))
            _draw(img, cam.project(ev.joints), (230, 30, 30))
            uv = cam.project(src.truth[:11])
            cx, cy = np.median(uv, axis=0)
            x0 = int(np.clip(cx - 150, 0, img.shape[1] - 300))
            y0 = int(np.clip(cy - 170, 0, img.shape[0] - 300))
            tiles.append(img[y0:y0 + 300, x0:x0 + 300])
    _save(Path(args.out), np.concatenate(tiles, axis=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
