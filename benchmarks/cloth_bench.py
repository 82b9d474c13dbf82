"""Cloth speed: one step of each garment, step time against particle count, the whole app.

Run: ``.venv/bin/python benchmarks/cloth_bench.py`` (``--quick`` for a short run).
Every garment is driven by the real CMU 13_29 jumping jacks at 60 Hz (the clip's
first frame dropped); after 60 warm-up steps (dressing included) the next
``--steps`` steps are timed one by one (``Cloth.step`` wall time) and the median,
95th percentile and rate (1 / median) printed, beside the CPU time of the process
(what a step costs when the machine is not shared: this machine's 2 cores are
shared by several jobs, so wall times are inflated by the load average printed),
with the constraint error (mean relative stretch) and the worst penetration over
those steps. The app figure runs ``python -m apps.cloth_mirror --input pose:13_29
--headless`` (640x480, video written, tracking excluded: pose input) and reports
rendered video frames per second of wall time outside the tracking stage, and of
process CPU time.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from _machine import machine  # type: ignore[import-not-found]

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def _jacks() -> np.ndarray:
    from bodyplay.motion import load_clip

    return load_clip("13_29").resample(60).joints()[1:]


def time_steps(name: str, resolution: float, steps: int, parallel: bool = False
               ) -> dict[str, float]:
    """Median / p95 step time (ms) of a garment on the jumping jacks, with its figures."""
    from bodyplay.cloth import Cloth, ClothOptions, garment

    joints = _jacks()
    cloth = Cloth(garment(name, resolution=resolution), ClothOptions(parallel=parallel))
    for j in joints[:60]:
        cloth.step(1 / 60, j)
    ms, cpu, strain, pen = [], [], [], []
    for j in joints[60:60 + steps]:
        t0, c0 = time.perf_counter(), time.process_time()
        r = cloth.step(1 / 60, j)
        ms.append(1000.0 * (time.perf_counter() - t0))
        cpu.append(1000.0 * (time.process_time() - c0))
        strain.append(r.mean_strain)
        pen.append(r.max_penetration)
    med = statistics.median(ms)
    return {"particles": cloth.num_particles, "median_ms": med,
            "cpu_ms": statistics.median(cpu),
            "p95_ms": float(np.percentile(ms, 95)), "hz": 1000.0 / med,
            "mean_strain": float(np.mean(strain)), "max_pen_mm": 1000.0 * max(pen)}


def app_fps(seconds: float, garment: str) -> dict[str, float]:
    """Video frames per second of the whole headless app (tracking excluded)."""
    from apps.cloth_mirror.__main__ import main

    c0 = time.process_time()
    with tempfile.TemporaryDirectory() as d:
        code = main(["--input", "pose:13_29", "--seconds", str(seconds), "--garment", garment,
                     "--headless", "--out", d, "--no-progress"])
        if code != 0:
            raise SystemExit(f"cloth_mirror exited with {code}")
        s = json.loads((Path(d) / "summary.json").read_text())
    cpu = time.process_time() - c0
    t = s["timing"]
    busy = t["wall_seconds"] - t["stage_seconds"]["tracking"]
    frames = s["game_seconds"] * 30.0
    return {"video_frames": frames, "seconds": busy, "fps": frames / busy,
            "cpu_seconds": cpu, "cpu_fps": frames / cpu,
            "cloth_ms": s["cloth_step_ms"]["median"],
            "render_ms": t["stage_ms_per_frame"]["render"]}


def main() -> None:
    """Print every figure of docs/benchmarks.md's cloth section."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=300, help="timed steps per case")
    ap.add_argument("--quick", action="store_true", help="fewer steps, shorter app run")
    args = ap.parse_args()
    steps = 60 if args.quick else args.steps
    print(f"machine: {machine()}; load average {os.getloadavg()[0]:.1f}; "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(f"\none step (1/60 s of jumping jacks), {steps} steps timed after 60 warm-up")
    print(f"{'garment':8} {'solver':9} {'particles':>9} {'median ms':>10} {'p95 ms':>8} "
          f"{'rate Hz':>8} {'CPU ms':>7} {'CPU Hz':>7} {'stretch %':>9} {'pen mm':>7}")
    for name in ("robe", "cape", "skirt"):
        for parallel in (False, True):
            r = time_steps(name, 1.0, steps, parallel)
            print(f"{name:8} {'parallel' if parallel else 'serial':9} {r['particles']:9d} "
                  f"{r['median_ms']:10.2f} {r['p95_ms']:8.2f} {r['hz']:8.0f} "
                  f"{r['cpu_ms']:7.2f} {1000 / r['cpu_ms']:7.0f} "
                  f"{100 * r['mean_strain']:9.2f} {r['max_pen_mm']:7.2f}")
    print("\nstep time against particle count (skirt, serial)")
    print(f"{'resolution':>10} {'particles':>9} {'median ms':>10} {'CPU ms':>7} "
          f"{'CPU us/particle':>16}")
    for res in (0.5, 0.75, 1.0, 1.5, 2.0):
        r = time_steps("skirt", res, max(30, steps // 2))
        print(f"{res:10.2f} {r['particles']:9d} {r['median_ms']:10.2f} {r['cpu_ms']:7.2f} "
              f"{1000 * r['cpu_ms'] / r['particles']:16.2f}")
    print("\nwhole app, headless 640x480, pose input (no tracking), video written")
    a = app_fps(4.0 if args.quick else 10.0, "robe")
    print(f"robe: {a['video_frames']:.0f} video frames in {a['seconds']:.1f} s = "
          f"{a['fps']:.1f} frames/s wall; {a['cpu_seconds']:.1f} s of CPU (all threads, "
          f"llvmpipe's included) = {a['cpu_fps']:.1f} frames/s of CPU "
          f"(cloth step median {a['cloth_ms']:.2f} ms wall)")
    print(f"load average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
