"""Frames per second of the ninja game headless at 640x480, tracking excluded.

Plays the whole default fight through the game kit (rules, virtual ninja, moderngl
scene, HUD, mp4 encoding) from pose-level input (the virtual ninja's joints, no
camera and no tracker, so tracking is excluded by construction) and reports the
per-frame cost of everything else: game rules, scene drawing + read-back and video
encoding. Each run is repeated; the fastest repeat is quoted beside the median
(the shared machine's load varies by seconds). Wall time and process CPU time are
both given: under heavy load from other processes the CPU time is the fairer one.

    .venv/bin/python benchmarks/ninja_bench.py [--repeats 3] [--seconds 20]
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from _machine import machine

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # apps/ from a checkout
from apps.ninja.game import NinjaPlayer  # noqa: E402
from apps.ninja.game.game import NinjaGame  # noqa: E402

from bodyplay.app import make_game_options, run_game  # noqa: E402
from bodyplay.virtual import VirtualPoseSource  # noqa: E402

STAGES = ("game", "render", "video", "physics")


def one_run(seconds: float, width: int, height: int, out: Path) -> dict[str, float]:
    """One headless fight; per-frame ms of each stage, wall and CPU fps (no tracking)."""
    player = NinjaPlayer()
    source = VirtualPoseSource(player, fps=30.0, seconds=seconds, noise=0.02)
    opts = make_game_options(headless=True, out=out, progress=False, seed=0,
                             width=width, height=height)
    cpu0 = time.process_time()
    run_game(NinjaGame(player=player), opts, source=source)
    cpu = time.process_time() - cpu0
    s = json.loads((out / "summary.json").read_text())
    frames = int(s["frames"])
    per = s["timing"]["stage_ms_per_frame"]
    ms = sum(float(per.get(k, 0.0)) for k in STAGES)
    track_ms = float(per.get("tracking", 0.0))
    cpu_ms = 1000.0 * cpu / max(frames, 1) - track_ms  # tracking is the pose source here
    return {"frames": frames, "ms": ms, "fps": 1000.0 / ms, "cpu_fps": 1000.0 / cpu_ms,
            **{f"{k}_ms": float(per.get(k, 0.0)) for k in STAGES}, "result": s["result"]}


def main() -> None:
    """Print the table (median and best of the repeats) with machine, load and date."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=480)
    a = ap.parse_args()
    print(f"machine: {machine()}; date: {datetime.date.today()}; "
          f"load average {os.getloadavg()[0]:.1f}")
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(a.repeats):
            r = one_run(a.seconds, a.width, a.height, Path(tmp) / str(i))
            runs.append(r)
            print(f"  run {i}: {r['frames']} frames, {r['fps']:.0f} fps wall, "
                  f"{r['cpu_fps']:.0f} fps CPU ({r['result']})", flush=True)
    print(f"\nninja headless {a.width}x{a.height}, tracking excluded, {len(runs)} runs:")
    print("| | game ms | render ms | video ms | total ms/frame | fps (wall) | fps (CPU) |")
    print("|---|---|---|---|---|---|---|")
    for label, pick in (("median", np.median), ("best", np.min)):
        tot = float(pick([r["ms"] for r in runs]))
        cpu_fps = (float(np.median([r["cpu_fps"] for r in runs])) if label == "median"
                   else float(np.max([r["cpu_fps"] for r in runs])))
        print(f"| {label} | {pick([r['game_ms'] for r in runs]):.2f} "
              f"| {pick([r['render_ms'] for r in runs]):.2f} "
              f"| {pick([r['video_ms'] for r in runs]):.2f} | {tot:.2f} "
              f"| {1000.0 / tot:.0f} | {cpu_fps:.0f} |")


if __name__ == "__main__":
    main()
