"""``bodyplay demo``: the most complete headless end-to-end run, with no camera.

A synthetic two-webcam capture of a real motion-capture clip (the MakeHuman actor in
the color shirt), tracked by the color-shirt tracker, written as an overlay video
and scored against the exact ground truth. Prints where every file is.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

from bodyplay.errors import BodyplayError

__all__ = ["register", "run"]


def register(subparsers: Any) -> None:
    """Add the ``demo`` sub-command."""
    p = subparsers.add_parser(
        "demo",
        help="headless end-to-end run: synthetic capture -> tracker -> overlay + accuracy",
        description=__doc__,
    )
    p.add_argument("--out", default="out/demo", help="folder for every output (default out/demo)")
    p.add_argument("--clip", default="13_29", help="BVH file or built-in clip (default 13_29)")
    p.add_argument("--start", type=float, default=8.0, help="start time in the clip, seconds")
    p.add_argument("--seconds", type=float, default=8.0, help="seconds to capture")
    p.add_argument("--lead-in", type=float, default=1.0,
                   help="seconds of the empty room before the player steps in (the tracker "
                        "learns its background plate there: floor and head cues; 0 = none)")
    p.add_argument("--cameras", type=int, default=2, choices=(1, 2))
    p.add_argument("--lighting", default="steady", help="synthetic lighting preset")
    p.add_argument("--seed", type=int, default=1)
    p.set_defaults(func=run)


def _step(title: str, argv: list[str]) -> None:
    from bodyplay.cli import main

    print(f"\n== {title}\n$ bodyplay {' '.join(argv)}", flush=True)
    t0 = time.perf_counter()
    code = main(argv)
    if code != 0:
        raise BodyplayError(f"demo step '{title}' failed (exit code {code})")
    print(f"   ({time.perf_counter() - t0:.1f} s)", flush=True)


def run(args: argparse.Namespace) -> int:
    """Run synth -> track -> eval and print where the files are."""
    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    capture = out / "capture"
    poses = out / "poses.jsonl"
    overlay = out / "overlay.mp4"
    report = out / "accuracy.json"
    plot = out / "error.png"
    _step(
        "synthetic capture of a real clip",
        ["synth", "--clip", args.clip, "--out", str(capture), "--cameras", str(args.cameras),
         "--start", str(args.start), "--seconds", str(args.seconds),
         "--lighting", args.lighting, "--seed", str(args.seed), "--lead-in", str(args.lead_in)],
    )
    _step(
        "color-shirt tracking",
        ["track", "--tracker", "colorshirt", "--input", str(capture), "--out", str(poses),
         "--overlay", str(overlay)],
    )
    from bodyplay.capture.jsonl import read_pose_jsonl
    from bodyplay.evaluation import evaluate, plot_errors

    print("\n== accuracy against the synthetic ground truth (upper body)", flush=True)
    result = evaluate(read_pose_jsonl(capture / "truth.jsonl"), read_pose_jsonl(poses), "upper")
    print(result.table())
    report.write_text(json.dumps(result.to_json(), indent=2))
    plot_errors(result, plot)
    print("\n== files")
    for label, path in (
        ("capture folder", capture),
        ("tracked poses", poses),
        ("overlay video", overlay),
        ("accuracy", report),
        ("error plot", plot),
    ):
        print(f"{label:>15}: {path}")
    return 0
