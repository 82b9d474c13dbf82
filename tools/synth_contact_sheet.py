"""Contact sheet of synthetic-camera stills, one per lighting preset (docs/img/...).

Run: .venv/bin/python tools/synth_contact_sheet.py [--out docs/img/lighting_contact_sheet.png]
Each still is frame 45 of clip 13_29 from 3 s, as `bodyplay synth` renders it
(noise "low", background "brick"); `switch` shows a frame after the lamp went off.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

from bodyplay.body.actor import load_actor
from bodyplay.motion.clip import load_clip
from bodyplay.synth.camera import SyntheticCamera
from bodyplay.synth.lighting import LIGHTING_PRESETS
from bodyplay.synth.options import make_synthetic_camera_options


def main() -> int:
    """Render one still per lighting preset and tile them 3 x 2 with labels."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", default="docs/img/lighting_contact_sheet.png")
    ap.add_argument("--background", default="brick")
    args = ap.parse_args()
    actor = load_actor("m")
    clip = load_clip("13_29", skeleton=actor.skeleton).slice(3.0, 2.0)
    tiles = []
    for name in LIGHTING_PRESETS:
        opts = make_synthetic_camera_options(lighting=name, background=args.background, seed=2)
        with SyntheticCamera(opts, clip, actor=actor) as cam:
            frame = None
            for sf in cam.from_clip(frames=46):
                frame = sf
            assert frame is not None
            img = frame.frames[0].image[:, :, ::-1].copy()
        small = cv2.resize(img, (320, 240), interpolation=cv2.INTER_AREA)
        cv2.putText(small, name, (8, 22), cv2.FONT_HERSHEY_SIMPLEX, 0.7, (0, 0, 0), 3)
        cv2.putText(small, name, (8, 22), cv2.FONT_HERSHEY_SIMPLEX, 0.7, (255, 255, 255), 1)
        tiles.append(small)
    sheet = np.vstack([np.hstack(tiles[0:3]), np.hstack(tiles[3:6])])
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(args.out, sheet)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
