"""Time per camera frame of the color-shirt tracker, from the first frame, per stage.

Runs the tracker over the captures of ``colorshirt_validation.py`` (same cache,
same clips, halves and settings) and measures every frame from the first one
(start-up included: the body choice, the arm-length stage, numba's first calls):

* **CPU time of the tracking thread** (``time.thread_time``), the figure to quote on
  this shared machine: other jobs slow the wall clock, not the thread's CPU time;
* **wall time** (``time.perf_counter``), what a game would see at that load;
* per **stage**, the thread's CPU time spent in it (exclusive: a stage called inside
  another counts only for itself), as a share of the total.

Times are per camera frame (a two-camera frame set counts twice), as in the
validation table. The pose database is loaded before the first frame (it is built
once and cached; ``colorshirt_db_bench.py`` times that).

    nice .venv/bin/python benchmarks/colorshirt_speed.py --half tune --settings steady-1-view
    nice .venv/bin/python benchmarks/colorshirt_speed.py --half report --clips 131_01,131_03
"""

from __future__ import annotations

import argparse
import datetime
import functools
import json
import sys
import time
from collections import defaultdict
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

import colorshirt_validation as cv
from _identity import compare_poses
from _machine import machine
from bodyplay.capture.frames import FrameSet
from bodyplay.capture.sources import open_source
from bodyplay.trackers.colorshirt import ColorShirtOptions, camerawork, create_colorshirt_tracker
from bodyplay.trackers.colorshirt import tracker as tracker_module
from bodyplay.trackers.colorshirt.armsearch import ArmSearches
from bodyplay.trackers.colorshirt.ik import KinematicSolver
from bodyplay.trackers.colorshirt.locate import BackgroundMask, ShirtLocator
from bodyplay.trackers.colorshirt.placement import DatabasePlacement
from bodyplay.trackers.colorshirt.prediction import PoseRenderer

STAGES: tuple[tuple[str, object, str], ...] = (
    ("background (MOG2, plate)", BackgroundMask, "apply"),
    ("locate (histogram search)", ShirtLocator, "locate"),
    ("classify (white balance, Mahalanobis)", camerawork, "classify_camera"),
    ("query (40x40 map, database lookup)", camerawork, "make_query"),
    ("placement (blend, place)", DatabasePlacement, "place"),
    ("render (id maps of the fit)", PoseRenderer, "render"),
    ("skinning (mesh vertices)", PoseRenderer, "vertices"),
    ("6-DOF fit", KinematicSolver, "solve_global"),
    ("arm search", ArmSearches, "search"),
    ("reclassification (pose prior)", camerawork.CameraWork, "refine_classification"),
    ("anchors", tracker_module.ColorShirtTracker, "_anchors"),
    ("IK", KinematicSolver, "solve_ik"),
    ("white-balance refit", camerawork.CameraWork, "refit_white_balance"),
    ("head cue", tracker_module, "head_anchors"),
    ("floor cue (feet)", tracker_module, "floor_reading"),
    ("gate (shirt box of the pose)", camerawork.CameraWork, "remember_shirt"),
)
"""(stage, owner, attribute): the functions whose exclusive CPU time makes each stage."""


class StageClock:
    """Exclusive CPU time of the tracking thread per stage (nested stages subtracted)."""

    def __init__(self) -> None:
        self.totals: dict[str, float] = defaultdict(float)
        self._stack: list[list[float]] = []
        self.counting = True
        """Whether the time spent is added to :attr:`totals` (off: frames left out)."""

    @contextmanager
    def stage(self, name: str) -> Iterator[None]:
        """Count the time inside, minus that of stages nested in it, for ``name``."""
        frame = [time.thread_time(), 0.0]
        self._stack.append(frame)
        try:
            yield
        finally:
            self._stack.pop()
            spent = time.thread_time() - frame[0]
            if self.counting:
                self.totals[name] += spent - frame[1]
            if self._stack:
                self._stack[-1][1] += spent

    def wrap(self, name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        """``fn`` counted as stage ``name``."""
        @functools.wraps(fn)
        def timed(*args: Any, **kwargs: Any) -> Any:
            with self.stage(name):
                return fn(*args, **kwargs)
        return timed


def instrument(clock: StageClock) -> Callable[[], None]:
    """Wrap every stage's function; returns the function that undoes it."""
    saved = []
    for name, owner, attr in STAGES:
        fn = getattr(owner, attr)
        saved.append((owner, attr, fn))
        setattr(owner, attr, clock.wrap(name, fn))

    def undo() -> None:
        for owner, attr, fn in saved:
            setattr(owner, attr, fn)
    return undo


def run(folder: Path, setting: cv.Setting, options: ColorShirtOptions, db: Any,
        clock: StageClock | None, steady_after: int = 0) -> dict[str, Any]:
    """Track one capture; per camera frame, CPU and wall ms from the first frame.

    ``steady_after``: the stage clock counts only the frame sets after this many
    (the start-up's left out); the times of every frame are returned."""
    truth_rows = (folder / "truth.jsonl").read_text().splitlines()
    src = open_source(folder)
    assert src.cameras is not None
    cams = src.cameras[: setting.cameras]
    tracker = create_colorshirt_tracker(options, cams, database=db)
    cpu, wall, proc, poses = [], [], [], []
    with src:
        for fs in src:
            empty = json.loads(truth_rows[fs.index])["joints"].get("pelvis") is None
            if setting.start == "view" and empty:
                continue
            frames = FrameSet(fs.frames[: setting.cameras], fs.t, fs.index)
            if clock is not None:
                clock.counting = len(cpu) >= steady_after
            c0, w0, p0 = time.thread_time(), time.perf_counter(), time.process_time()
            if clock is None:
                r = tracker.process(frames)
            else:
                with clock.stage("other (tracker.process itself)"):
                    r = tracker.process(frames)
            cpu.append(1000 * (time.thread_time() - c0) / setting.cameras)
            wall.append(1000 * (time.perf_counter() - w0) / setting.cameras)
            proc.append(1000 * (time.process_time() - p0) / setting.cameras)
            poses.append(np.asarray(r.joints, np.float64).copy())
    return {"cpu": cpu, "wall": wall, "process": proc, "poses": np.array(poses, np.float64)}


def main(argv: list[str] | None = None) -> int:
    """Time every (clip, setting) of a half; print medians, p90 and stage shares."""
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--half", choices=("tune", "report", "all"), default="tune")
    ap.add_argument("--settings", default="steady-1-view,steady-2-view")
    ap.add_argument("--clips", default="", help="only these clips (comma-separated names)")
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--db-size", type=int, default=20_000)
    ap.add_argument("--work", default="/work/cache-colorshirt")
    ap.add_argument("--set", action="append", default=[], metavar="OPTION=VALUE",
                    help="a tracker option for this run (repeatable)")
    ap.add_argument("--cv-threads", type=int, default=-1,
                    help="cv2.setNumThreads for the run (default: OpenCV's own, one per core)")
    ap.add_argument("--no-stages", action="store_true",
                    help="no per-stage clock (its wrappers cost about 1%% of the time)")
    ap.add_argument("--steady-after", type=int, default=0, metavar="N",
                    help="stage shares and the 'steady' medians of the frame sets after the "
                    "first N of each clip only (the start-up left out; 0: every frame)")
    ap.add_argument("--json", help="also write the figures (and every clip's CPU ms per "
                    "camera frame, frame by frame) to this JSON file")
    ap.add_argument("--poses", help="write every frame's joints to this .npz (one array "
                    "per setting and clip) to check that a speed change left them identical")
    ap.add_argument("--compare", help="a --poses .npz of another commit: print the largest "
                    "joint difference of every setting and clip against it")
    args = ap.parse_args(argv)
    if args.cv_threads >= 0:
        cv2.setNumThreads(args.cv_threads)
    if not (cv.MOCAP / "bandai_namco").exists():
        print("shared data not found (../shared/data/mocap); nothing to time")
        return 1
    clips = cv.all_clips()
    by_name = {s.name: s for s in cv.SETTINGS}
    settings = [by_name[n] for n in args.settings.split(",")]
    chosen = set(args.clips.split(",")) if args.clips else None
    picked = [(i, c) for i, c in enumerate(clips)
              if (args.half == "all" or cv.half_of(c, clips) == args.half)
              and (chosen is None or c.name in chosen)]
    options = cv.options_from(args)
    work = Path(args.work)
    dbs: dict[str, Any] = {}
    print(f"# colorshirt speed, half {args.half}, {datetime.date.today()}, {machine()}",
          flush=True)
    out: dict[str, Any] = {}
    joints: dict[str, NDArray[np.float64]] = {}
    for s in settings:
        clock = None if args.no_stages else StageClock()
        undo = instrument(clock) if clock is not None else (lambda: None)
        cpu: list[float] = []
        steady: list[float] = []
        wall: list[float] = []
        proc: list[float] = []
        per_frame: dict[str, list[float]] = {}
        try:
            for i, clip in picked:
                folder = cv.capture(work, clip, s.lighting, i, args.seconds)
                r = run(folder, s, options, cv.database_for(clip, options, dbs), clock,
                        args.steady_after)
                cpu += r["cpu"]
                steady += r["cpu"][args.steady_after:]
                wall += r["wall"]
                proc += r["process"]
                joints[f"{s.name}/{clip.name}"] = r["poses"]
                per_frame[clip.name] = [round(c, 2) for c in r["cpu"]]
                print(f"{s.name:15s} {clip.name:48s} CPU median {np.median(r['cpu']):6.1f} ms "
                      f"p90 {np.percentile(r['cpu'], 90):6.1f}  wall median "
                      f"{np.median(r['wall']):6.1f}  first frame {r['cpu'][0]:7.1f} ms CPU",
                      flush=True)
        finally:
            undo()
        row: dict[str, Any] = {
            "frames": len(cpu), "cpu_median": float(np.median(cpu)),
            "cpu_p90": float(np.percentile(cpu, 90)), "wall_median": float(np.median(wall)),
            "wall_p90": float(np.percentile(wall, 90)),
            "process_cpu_median": float(np.median(proc)), "cpu_per_frame": per_frame}
        if args.steady_after > 0 and steady:
            row["steady_cpu_median"] = float(np.median(steady))
            row["steady_cpu_mean"] = float(np.mean(steady))
            print(f"{s.name}: {len(steady)} camera frames after the first {args.steady_after} "
                  f"frame sets of each clip: CPU median {row['steady_cpu_median']:.1f} ms, "
                  f"mean {row['steady_cpu_mean']:.1f}")
        print(f"\n{s.name}: {len(cpu)} camera frames of {len(picked)} clips, from the first "
              f"frame: CPU median {row['cpu_median']:.1f} ms, p90 {row['cpu_p90']:.1f}; wall "
              f"median {row['wall_median']:.1f}, p90 {row['wall_p90']:.1f}; CPU of every thread "
              f"of the process median {row['process_cpu_median']:.1f}")
        if clock is not None:
            total = sum(clock.totals.values())
            shares = {k: v / total for k, v in sorted(clock.totals.items(), key=lambda kv: -kv[1])}
            row["stages"] = shares
            sets = len(steady) if args.steady_after > 0 else len(cpu)
            per = 1000.0 / max(sets * s.cameras, 1)  # ms per camera frame counted
            row["stage_ms"] = {k: v * per for k, v in clock.totals.items()}
            print("| stage | share of CPU time | ms per camera frame (mean) |\n|---|---|---|")
            for k, v in shares.items():
                print(f"| {k} | {100 * v:.1f}% | {clock.totals[k] * per:.2f} |")
        out[s.name] = row
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1))
    if args.poses:
        np.savez_compressed(args.poses, **joints)
    if args.compare:
        print(compare_poses(joints, dict(np.load(args.compare))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
