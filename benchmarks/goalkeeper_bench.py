"""Goalkeeper speed: the game without tracking, and the whole pipeline end to end.

1. Game step + rendering, tracking excluded: a round against the pose-level virtual
   keeper (no images, no tracker) at 640x480, headless EGL, video on; frames per
   second of (physics + game rules + drawing and read-back) per video frame, and
   with the mp4 encoding added. Several rounds, the median reported.
2. End to end: the virtual keeper filmed by one synthetic camera, tracked by the
   color-shirt tracker, the game played on the tracked poses, drawn and encoded;
   frames per second with and without the synthetic camera's own rendering (a real
   webcam delivers its frames for free), and the share of time per stage.

Run from the repository root: ``.venv/bin/python benchmarks/goalkeeper_bench.py``
(``--quick`` for a short run). Prints the machine, the load and the figures.
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from apps.goalkeeper.game import GoalkeeperGame, GoalkeeperOptions  # noqa: E402

from _machine import machine  # noqa: E402
from bodyplay.app import make_game_options, run_game  # noqa: E402


def _round(shots: int, seed: int, camera: bool, out: Path) -> dict[str, Any]:
    """One headless round; the summary gets ``cpu_seconds`` (the process, all threads)."""
    game = GoalkeeperGame(GoalkeeperOptions(shots=shots), virtual_poses=not camera)
    opts = make_game_options(headless=True, out=out, seed=seed, progress=False)
    cpu0 = time.process_time()
    s = run_game(game, opts).summary
    s["cpu_seconds"] = time.process_time() - cpu0
    return s


def game_only(rounds: int, shots: int) -> None:
    """Part 1: frames per second of game + rendering (tracking excluded)."""
    fps, fps_video, fps_cpu, saves = [], [], [], []
    for k in range(rounds):
        with tempfile.TemporaryDirectory() as tmp:
            s = _round(shots, k, camera=False, out=Path(tmp))
        st = s["timing"]["stage_seconds"]
        video_frames = round(s["game_seconds"] * 30) + 1
        game = st["physics"] + st["game"] + st["render"]
        fps.append(video_frames / game)
        fps_video.append(video_frames / (game + st["video"]))
        fps_cpu.append(video_frames / s["cpu_seconds"])
        saves.append(f"{s['saves']}/{s['shots']}")
    print(f"game step + rendering 640x480 (tracking excluded), {rounds} rounds of {shots} "
          f"shots: median {statistics.median(fps):.0f} frames/s "
          f"(min {min(fps):.0f}) wall; with mp4 encoding {statistics.median(fps_video):.0f} "
          f"frames/s; whole run in CPU time (everything, all threads) "
          f"{statistics.median(fps_cpu):.0f} frames/s; saves {', '.join(saves)}")


def end_to_end(shots: int) -> None:
    """Part 2: the whole pipeline on one synthetic camera with the color shirt."""
    with tempfile.TemporaryDirectory() as tmp:
        s = _round(shots, 0, camera=True, out=Path(tmp))
    t = s["timing"]
    st = t["stage_seconds"]
    total = sum(st.values())
    frames = s["frames"]
    no_cam = total - st["capture"]
    print(f"end to end, 1 synthetic camera + colorshirt, {frames} frames, "
          f"{s['saves']}/{s['shots']} saves, tracking share {s['tracking_share']:.2f}:")
    print(f"  {frames / total:.1f} frames/s all stages; {frames / no_cam:.1f} frames/s "
          "without the synthetic camera's rendering (what a real webcam costs nothing for); "
          f"{frames / s['cpu_seconds']:.1f} frames/s of CPU time (all threads, everything)")
    print("  share per stage: " + ", ".join(
        f"{k} {100 * v / total:.0f}% ({1000 * v / frames:.1f} ms)" for k, v in st.items()))


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="fewer rounds and shots")
    p.add_argument("--game-only", action="store_true", help="skip the end-to-end part")
    args = p.parse_args()
    print(f"{machine()}; {dt.date.today()}; load {os.getloadavg()[0]:.1f}")
    game_only(rounds=2 if args.quick else 5, shots=4 if args.quick else 10)
    if not args.game_only:
        end_to_end(shots=3 if args.quick else 6)
    print(f"load at the end {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
