"""Synthetic camera speed: frames per second written for one 640x480 camera.

Run: .venv/bin/python benchmarks/synth_bench.py [--frames 60] [--repeats 3]
Renders clip 13_29 (jumping jacks, fast: motion blur uses several sub-frames) and
131_01 (a walk) with default options, through `write_capture` into png and mp4, and
with motion blur off (max_subframes=1), and prints the median fps of the repeats.
"""

from __future__ import annotations

import argparse
import datetime
import platform
import statistics
import tempfile
import time

from bodyplay.body.actor import load_actor
from bodyplay.motion.clip import load_clip
from bodyplay.synth.camera import SyntheticCamera
from bodyplay.synth.options import make_synthetic_camera_options
from bodyplay.synth.writer import write_capture


def _fps(actor, clip, frames: int, **kw) -> float:  # type: ignore[no-untyped-def]
    opts = make_synthetic_camera_options(**kw)
    with SyntheticCamera(opts, clip, actor=actor) as cam, tempfile.TemporaryDirectory() as d:
        list(cam.from_clip(frames=2))  # warm up GL and numba
        t = time.perf_counter()
        summary = write_capture(d, cam, cam.from_clip(frames=frames))
        return summary.frames / (time.perf_counter() - t)


def main() -> int:
    """Print the median fps of each configuration."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    actor = load_actor("m")
    clips = {
        "13_29": load_clip("13_29", skeleton=actor.skeleton).slice(3.0, args.frames / 30 + 0.5),
        "131_01": load_clip("131_01", skeleton=actor.skeleton).slice(2.0, args.frames / 30 + 0.5),
    }
    configs = [
        ("13_29", "mp4, defaults (blur <= 4 sub-frames)", {}),
        ("13_29", "png, defaults", {"format": "png"}),
        ("13_29", "mp4, motion blur off", {"max_subframes": 1}),
        ("131_01", "mp4, defaults (walk)", {}),
    ]
    print(f"# synth_bench  {datetime.date.today()}  {platform.processor() or platform.machine()}"
          f"  python {platform.python_version()}  frames={args.frames}")
    for clip_name, label, kw in configs:
        runs = [_fps(actor, clips[clip_name], args.frames, **kw) for _ in range(args.repeats)]
        print(f"{clip_name:7s} {label:40s} median {statistics.median(runs):5.1f} fps "
              f"(runs: {', '.join(f'{r:.1f}' for r in runs)})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
