"""Render the cloth docs' media: the three garments doing the CMU 13_29 jumping jacks.

Run: ``.venv/bin/python tools/cloth_media.py [--out docs/img] [--seconds 4]``. Writes
``cloth_jacks.mp4`` (the three garments side by side, 30 fps, small) and
``cloth_still.png`` (three moments of each garment). The body is drawn as the very
capsules the cloth collides with; the cloth is stepped at 60 Hz.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

from bodyplay.capture.camera import Camera, look_at
from bodyplay.capture.video import VideoWriter
from bodyplay.cloth import Cloth, ClothOptions, garment
from bodyplay.cloth.mesh import capsules_mesh
from bodyplay.motion import load_clip
from bodyplay.render.shaded import RenderMesh, ShadedRenderer, ShadedRendererOptions

_SKIN = (0.86, 0.70, 0.58)
_GARMENTS = ("robe", "cape", "skirt")


def main() -> None:
    """Simulate, render and write the clip and the still."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("docs/img"))
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--start", type=float, default=1.0, help="clip time to start at (s)")
    args = ap.parse_args()
    joints = load_clip("13_29").resample(60).joints()[1:]
    first = int(args.start * 60)
    n = int(args.seconds * 60)
    w, h = 240, 320
    views = {
        "robe": look_at((0.9, 1.2, 2.5), (0.0, 0.9, 0.0)),
        "cape": look_at((1.3, 1.3, -2.2), (0.0, 0.9, 0.0)),
        "skirt": look_at((0.7, 1.1, 2.6), (0.0, 0.85, 0.0)),
    }
    cams = {g: Camera.from_fov(g, w, h, 42.0, *views[g]) for g in _GARMENTS}
    cloths = {g: Cloth(garment(g), ClothOptions()) for g in _GARMENTS}
    for g in _GARMENTS:  # dress on the pose before the clip starts, settle a second
        for _ in range(60):
            cloths[g].step(1 / 60, joints[first])
    args.out.mkdir(parents=True, exist_ok=True)
    video = VideoWriter(args.out / "cloth_jacks.mp4", 30.0)
    still_at = {int(n * f) for f in (0.2, 0.45, 0.7)}
    stills: list[np.ndarray] = []
    bg = np.full((h, w, 3), (42, 44, 52), np.uint8)
    with ShadedRenderer(ShadedRendererOptions(width=w, height=h, samples=4)) as rd:
        for k in range(n):
            for g in _GARMENTS:
                cloths[g].step(1 / 60, joints[first + k])
            if k % 2 and k not in still_at:
                continue
            tiles = []
            for g in _GARMENTS:
                c = cloths[g]
                caps = c.capsules()
                assert caps is not None
                bv, bf = capsules_mesh(caps)
                meshes = [RenderMesh(bv, bf, _SKIN, closed=True),
                          RenderMesh(c.positions, c.faces, c.garment.color)]
                img = rd.render(meshes, cams[g], background=bg)
                cv2.putText(img, g, (8, 20), cv2.FONT_HERSHEY_DUPLEX, 0.55, (230, 230, 230), 1,
                            cv2.LINE_AA)
                tiles.append(img)
            frame = np.hstack(tiles)
            if k % 2 == 0:
                video.write(frame)
            if k in still_at:
                stills.append(frame)
    video.close()
    still = np.vstack(stills)
    cv2.imwrite(str(args.out / "cloth_still.png"), cv2.cvtColor(still, cv2.COLOR_RGB2BGR),
                [cv2.IMWRITE_PNG_COMPRESSION, 9])
    for name in ("cloth_jacks.mp4", "cloth_still.png"):
        print(args.out / name, f"{(args.out / name).stat().st_size / 1024:.0f} KiB")


if __name__ == "__main__":
    main()
