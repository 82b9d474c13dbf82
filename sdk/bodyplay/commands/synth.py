"""``bodyplay synth``: render a motion clip as a synthetic webcam capture folder.

Writes ``cam0.mp4`` (and ``cam1.mp4``) or ``cam0/000000.png ...``, ``calib.json``,
``truth.jsonl`` and ``meta.json`` (every parameter; ``--repeat OUT/meta.json``
renders the same capture again, byte for byte with ``--format png``).
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path
from typing import Any

from bodyplay.errors import BVHError, ConfigError

__all__ = ["register", "run"]


def register(subparsers: Any) -> None:
    """Add the ``synth`` sub-command."""
    from bodyplay.synth.lighting import LIGHTING_PRESETS
    from bodyplay.synth.sensor import NOISE_LEVELS

    p = subparsers.add_parser(
        "synth",
        help="render a motion clip as a synthetic webcam capture (video, calib, truth)",
        description=__doc__,
    )
    p.add_argument("--clip", help="BVH file or built-in clip name (e.g. 13_29)")
    p.add_argument("--out", required=True, help="capture folder to write")
    p.add_argument("--cameras", type=int, default=1, choices=(1, 2))
    span = p.add_mutually_exclusive_group()
    span.add_argument("--seconds", type=float, help="seconds to render (default: to the end)")
    span.add_argument("--frames", type=int, help="number of frames to render")
    p.add_argument("--start", type=float, default=0.0, help="start time in the clip, seconds")
    p.add_argument("--lead-in", type=float, default=0.0, metavar="SECONDS",
                   help="seconds of the empty room before the clip (a background plate for "
                        "trackers; truth joints are null there)")
    p.add_argument("--fps", type=float, default=30.0)
    p.add_argument("--size", default="640x480", help="WIDTHxHEIGHT (default 640x480)")
    p.add_argument("--background", default="brick", help="shipped name, #rrggbb or image file")
    p.add_argument("--lighting", default="steady", help=f"one of {', '.join(LIGHTING_PRESETS)}")
    p.add_argument("--noise", default="low", help=f"one of {', '.join(NOISE_LEVELS)}")
    p.add_argument("--body", default="m", help="body preset (xs, s, m_slim, m, m_heavy, l, ...)")
    p.add_argument("--occlude", action="append", default=[], metavar="START:SECONDS",
                   help="put an opaque panel in front of cam0 (repeatable)")
    p.add_argument("--format", default="mp4", choices=("mp4", "png"))
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--k1", type=float, default=0.0, help="radial lens distortion (e.g. -0.05)")
    p.add_argument("--repeat", metavar="META", help="repeat the run recorded in a meta.json")
    p.set_defaults(func=run)


def _options_and_run(args: argparse.Namespace) -> tuple[Any, dict[str, Any]]:
    from bodyplay.synth.options import SyntheticCameraOptions, make_synthetic_camera_options
    from bodyplay.synth.writer import read_meta

    if args.repeat:
        meta = read_meta(args.repeat)
        return SyntheticCameraOptions.from_dict(meta["options"]), dict(meta["run"])
    if not args.clip:
        raise ConfigError("--clip is required (a BVH file or a built-in name such as 13_29)")
    options = make_synthetic_camera_options(
        cameras=args.cameras,
        fps=args.fps,
        size=args.size,
        background=args.background,
        lighting=args.lighting,
        noise=args.noise,
        body=args.body,
        occlusions=args.occlude,
        seed=args.seed,
        format=args.format,
        k1=args.k1,
    )
    clip = args.clip
    if Path(clip).exists():
        clip = str(Path(clip).resolve())
    run_info = {"clip": clip, "start": args.start, "seconds": args.seconds, "frames": args.frames,
                "lead_in": args.lead_in}
    return options, run_info


def run(args: argparse.Namespace) -> int:
    """Render the clip and write the capture folder; print a one-line summary."""
    from bodyplay.body.actor import load_actor
    from bodyplay.motion.clip import load_clip
    from bodyplay.synth.camera import SyntheticCamera
    from bodyplay.synth.writer import write_capture

    options, run_info = _options_and_run(args)
    actor = load_actor(shape=options.body)
    clip_spec = str(run_info["clip"])
    try:
        clip = load_clip(clip_spec, skeleton=actor.skeleton)
    except (OSError, UnicodeDecodeError) as exc:
        raise BVHError(f"{clip_spec}: cannot read the clip ({exc}); pass a BVH file") from None
    start = float(run_info.get("start") or 0.0)
    seconds = run_info.get("seconds")
    frames = run_info.get("frames")
    if start < 0 or start > clip.duration:
        raise ConfigError(f"--start {start} is outside the clip (0 .. {clip.duration:.2f} s)")
    if frames is not None and frames < 1:
        raise ConfigError(f"--frames must be at least 1, got {frames}")
    if seconds is not None and seconds <= 0:
        raise ConfigError(f"--seconds must be positive, got {seconds}")
    # Frame the rig on the span rendered, not the whole clip.
    length = seconds if seconds is not None else (
        None if frames is None else frames / options.fps
    )
    lead_in = float(run_info.get("lead_in") or 0.0)
    if not 0.0 <= lead_in <= 60.0:
        raise ConfigError(f"--lead-in {lead_in} must be within 0..60 seconds")
    part = clip.slice(start, length)
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # lights that change (switch, flicker) do so over the whole recording
        camera = SyntheticCamera(options, part, actor=actor, duration=lead_in + part.duration)
    for w in caught:
        print(f"bodyplay synth: warning: {w.message}", file=sys.stderr)
    with camera:
        summary = write_capture(
            args.out, camera, camera.from_clip(frames=frames, lead_in=lead_in), run=run_info
        )
    dt = time.perf_counter() - t0
    print(
        f"wrote {summary.frames} frames x {len(camera.cameras)} camera(s) to {summary.folder} "
        f"({', '.join(summary.files)}) in {dt:.1f} s ({summary.frames / max(dt, 1e-9):.1f} fps)"
    )
    return 0
