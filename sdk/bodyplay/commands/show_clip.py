"""``bodyplay show-clip``: watch the actor perform a motion clip, shaded, in the shirt.

A quick look at real motion capture on the body model: one front camera, steady
light, no sensor noise, anti-aliased. Use ``bodyplay synth`` for captures meant for
trackers (calibration, truth, lighting presets, noise).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import numpy as np

from bodyplay.errors import ConfigError

__all__ = ["register", "run", "render_clip_video"]


def register(subparsers: Any) -> None:
    """Add the ``show-clip`` sub-command."""
    p = subparsers.add_parser(
        "show-clip",
        help="render the actor performing a clip (BVH or built-in name) to a video",
        description=__doc__,
    )
    p.add_argument("clip", help="BVH file or built-in clip name (e.g. 13_29)")
    p.add_argument("--out", required=True, help="video file to write (.mp4)")
    p.add_argument("--start", type=float, default=0.0, help="start time in the clip, seconds")
    p.add_argument("--seconds", type=float, help="seconds to render (default: whole clip)")
    p.add_argument("--fps", type=float, default=30.0)
    p.add_argument("--size", default="640x480", help="WIDTHxHEIGHT")
    p.add_argument("--background", default="gravel", help="shipped name, #rrggbb or image")
    p.add_argument("--body", default="m", help="body preset")
    p.add_argument("--still", help="also save the middle frame as this PNG")
    p.set_defaults(func=run)


def render_clip_video(
    clip_spec: str,
    out: str | Path,
    *,
    start: float = 0.0,
    seconds: float | None = None,
    fps: float = 30.0,
    size: str | tuple[int, int] = "640x480",
    background: str = "gravel",
    body: str = "m",
    still: str | Path | None = None,
) -> int:
    """Render ``clip_spec`` on the actor from a front camera into ``out``; return frames."""
    import cv2

    from bodyplay.body.actor import load_actor
    from bodyplay.capture.video import VideoWriter
    from bodyplay.motion.clip import load_clip
    from bodyplay.synth.camera import SyntheticCamera
    from bodyplay.synth.options import make_synthetic_camera_options

    options = make_synthetic_camera_options(
        cameras=1, fps=fps, size=size, background=background, lighting="steady",
        noise="none", body=body, msaa=4, max_subframes=1,
    )
    actor = load_actor(shape=options.body)
    clip = load_clip(clip_spec, skeleton=actor.skeleton)
    if not 0 <= start < clip.duration:
        raise ConfigError(f"--start {start} is outside the clip (0 .. {clip.duration:.2f} s)")
    part = clip.slice(start, seconds)

    with SyntheticCamera(options, part, actor=actor) as camera, VideoWriter(out, fps) as video:
        for sf in camera.from_clip():
            image = sf.frames[0].image
            video.write(image)

            if still is not None and sf.index == int(part.duration * fps / 2):
                cv2.imwrite(str(still), np.ascontiguousarray(image[:, :, ::-1]))
        return video.frames


def run(args: argparse.Namespace) -> int:
    """Render the clip and print where the video is."""
    t0 = time.perf_counter()
    n = render_clip_video(
        args.clip, args.out, start=args.start, seconds=args.seconds, fps=args.fps,
        size=args.size, background=args.background, body=args.body, still=args.still,
    )
    dt = time.perf_counter() - t0
    print(f"wrote {n} frames to {args.out} in {dt:.1f} s")
    if args.still:
        print(f"still: {args.still}")
    return 0
