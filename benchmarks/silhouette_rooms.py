"""Room variety of the silhouette tracker: rooms it was not tuned in, the player in view.

``silhouette_bench.py`` renders every capture in front of one wall (the grey
``brick`` photo), the room the tracker's settings were chosen in. A player's room
is anything: furniture the colour of their clothes, big objects behind them,
texture everywhere. This check renders a few clips in several rooms:

* **rooms**: the shipped background photos (``astronaut``, ``brick``, ``camera``,
  ``chelsea``, ``coffee``, ``grass``, ``gravel``, ``rocket``: big objects, faces,
  texture) and the generated rooms of ``colorshirt_validation.py`` (``posters``,
  ``fruit``, ``clothes``: a wall and floor full of saturated colours), cached as
  PNG under ``--work``;
* **halves**: the rooms and the clips are split. The **tune** half: the rooms
  ``brick`` (where the tracker was tuned), ``coffee`` (the room it was first seen
  to fail in), ``chelsea``, ``gravel``, ``posters`` with the tracker's tune clips
  (13_29 from 10 s, bow, raise-up-left-hand, wave-right-hand, kick). The
  **report** half: ``astronaut``, ``camera``, ``rocket``, ``grass``, ``fruit``,
  ``clothes`` with ``silhouette_bench.py``'s report clips (13_29 from 2 s, 131_03,
  wave-both-hands, punch, raise-up-both-hands, dance-short). Settings are chosen
  on the tune half only; the report half is run to report;
* **a photo of a person** (``--half photo``, a tune-side check): the tune clips in
  a generated room ``photo``, the ``brick`` photo with a life-size picture of a
  person standing beside the player (the actor rendered standing, in the first
  frame of the Bandai bow, pasted 1.15 times the player's size at the left), as
  the report rooms' ``astronaut`` photo is: a first guess that takes a picture
  for the player;
* each room shows ``--clips-per-room`` clips of its half (room *i* takes clips *i*,
  *i* + 1, ... of the half's list, so every clip is seen in as many rooms);
* one camera, 640x480, actor ``m``, steady light, the player in view from the
  first frame (no empty-room lead-in), ``--seconds`` of each clip.

Per capture: MPJPE over all 17 joints in the world (median over the frames with a
pose, and the mean), the share of frames with a pose, the first frame with one,
the body preset chosen and the tracker's CPU time per frame (process time, median).
Per room: the median and the worst of its clips' medians and the fewest frames
with a pose; then over the half: the median of the rooms and the worst room.
A capture without any pose counts as the worst (its MPJPE is printed as ``-``).

    nice .venv/bin/python benchmarks/silhouette_rooms.py                 # report half
    nice .venv/bin/python benchmarks/silhouette_rooms.py --half tune --set stance_weight=0
    nice .venv/bin/python benchmarks/silhouette_rooms.py --in brick     # the same clips in brick
    nice .venv/bin/python benchmarks/silhouette_rooms.py --half photo --clips-per-room 5
    .venv/bin/python benchmarks/silhouette_rooms.py --list

Captures are rendered once into ``--work`` (about 5 s each); tracking a half takes
a few minutes on two shared cores.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from bodyplay.capture.frames import FrameSet
from bodyplay.capture.jsonl import read_pose_jsonl
from bodyplay.capture.sources import open_source
from bodyplay.overrides import options_with_overrides
from bodyplay.trackers.silhouette import (
    SilhouetteOptions,
    create_silhouette_tracker,
    load_or_build_tree,
)

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine  # noqa: E402
from colorshirt_validation import (  # noqa: E402
    BODIES,
    CLUTTER_ROOMS,
    room_path,
    start_fraction,
)

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
BANDAI = DATA / "mocap" / "bandai_namco"
ROOMS = {
    "tune": ("coffee", "brick", "chelsea", "gravel", "posters"),
    "report": ("astronaut", "camera", "rocket", "grass", "fruit", "clothes"),
    "photo": ("photo",),
}
"""Rooms of each half; ``posters``, ``fruit`` and ``clothes`` are generated."""
CLIPS = {
    "tune": (("13_29", 10.0), ("dataset-1_bow_normal_001", 0.0),
             ("dataset-2_raise-up-left-hand_normal_001", 0.0),
             ("dataset-2_wave-right-hand_normal_001", 0.0), ("dataset-1_kick_normal_001", 0.0)),
    "report": (("13_29", 2.0), ("131_03", 0.0), ("dataset-2_wave-both-hands_normal_001", 0.0),
               ("dataset-1_punch_normal_001", 0.0),
               ("dataset-2_raise-up-both-hands_normal_001", 0.0),
               ("dataset-1_dance-short_normal_001", 0.0)),
}
CLIPS["photo"] = CLIPS["tune"]
"""Clips of each half (name or Bandai file stem, start in seconds)."""


def photo_room(work: Path) -> str:
    """The ``photo`` room's PNG (cached under ``work``): the shipped ``brick`` photo
    (stretched to 640x480) with a life-size picture of a standing person at the left
    of the player (the actor of ``bodyplay synth`` in the first frame of the Bandai
    bow, standing still, cut from a magenta wall, 1.15 times as large as the
    player, feet near the bottom of the frame)."""
    path = work / "rooms" / "photo.png"
    if path.exists():
        return str(path)
    import cv2

    from bodyplay.synth.backgrounds import _assets

    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = work / "rooms" / f"photo_figure.tmp{os.getpid()}"
    bow = str(BANDAI / "dataset-1_bow_normal_001.bvh")
    subprocess.run([sys.executable, "-m", "bodyplay.cli", "synth", "--clip", bow, "--out",
                    str(tmp), "--frames", "1", "--background", "#ff00ff", "--noise", "none",
                    "--format", "png"], check=True, stdout=subprocess.DEVNULL)
    fig = cv2.imread(str(tmp / "cam0" / "000000.png"))
    shutil.rmtree(tmp, ignore_errors=True)
    mask = np.abs(fig.astype(int) - np.array([255, 0, 255])).sum(axis=2) > 60
    ys, xs = np.nonzero(mask)
    crop = fig[ys.min():ys.max() + 1, xs.min():xs.max() + 1]
    cm = mask[ys.min():ys.max() + 1, xs.min():xs.max() + 1].astype(np.uint8)
    crop = cv2.resize(crop, None, fx=1.15, fy=1.15, interpolation=cv2.INTER_LINEAR)
    cm = cv2.resize(cm, None, fx=1.15, fy=1.15, interpolation=cv2.INTER_NEAREST) > 0
    wall = cv2.resize(cv2.imread(str(_assets() / "brick.jpg")), (640, 480))
    h, w = cm.shape
    y0, x0 = max(0, 465 - h), 20
    h, w = min(h, 480 - y0), min(w, 640 - x0)
    roi = wall[y0:y0 + h, x0:x0 + w]
    roi[cm[:h, :w]] = crop[:h, :w][cm[:h, :w]]
    cv2.imwrite(str(path), wall)
    return str(path)


def short(clip: str) -> str:
    """A clip's name without the Bandai dataset prefix and take number."""
    if clip.startswith("dataset"):
        return clip.split("_", 1)[1].rsplit("_normal", 1)[0]
    return clip


def plan(half: str, per_room: int, draw: int = 0) -> list[tuple[str, str, float]]:
    """(room, clip, start) of a half: room *i* shows clips *i* + ``draw``, *i* +
    ``draw`` + 1, ... of the half's list; Bandai clips only when ../shared holds them.
    A start of -1 (every ``draw`` but 0) is :func:`capture`'s part of the clip."""
    clips = [c for c in CLIPS[half] if not c[0].startswith("dataset") or BANDAI.is_dir()]
    out = []
    for i, room in enumerate(ROOMS[half]):
        for k in range(min(per_room, len(clips))):
            clip, start = clips[(i + k + draw) % len(clips)]
            out.append((room, clip, start if draw == 0 else -1.0))
    return out


def capture(work: Path, room: str, clip: str, start: float, seconds: float,
            draw: int = 0, index: int = 0) -> Path:
    """The one-camera capture of a clip in a room, rendered once (no lead-in).

    ``draw`` 0 is the set every figure so far was measured on; a later draw is a
    fresh set nobody has tuned on, as ``colorshirt_validation.py``'s: another part of
    the clip (``start`` -1: its golden-ratio walk), another body preset and camera
    seed for the ``index``-th capture, other pictures of the generated rooms."""
    if start < 0:
        from bodyplay.motion.clip import load_clip

        full = load_clip(str(BANDAI / f"{clip}.bvh") if clip.startswith("dataset") else clip)
        start = round(start_fraction(draw) * max(0.0, full.duration - seconds), 2)
    key = f"{room}_{short(clip)}_{start:g}_{seconds:g}s"
    body = BODIES[(index + draw) % len(BODIES)]
    out = work / "captures" / (key if draw == 0 else f"{key}_{body}_d{draw}")
    if not (out / "truth.jsonl").exists():
        src = str(BANDAI / f"{clip}.bvh") if clip.startswith("dataset") else clip
        background = (room_path(work, room, draw) if room in CLUTTER_ROOMS
                      else photo_room(work) if room == "photo" else room)
        tmp = out.with_name(f"{out.name}.tmp{os.getpid()}")  # renamed once complete
        cmd = [sys.executable, "-m", "bodyplay.cli", "synth", "--clip", src, "--out", str(tmp),
               "--seconds", str(seconds), "--start", str(start), "--background", background]
        if draw:
            cmd += ["--body", body, "--seed", str(1000 * draw + index)]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        shutil.rmtree(out, ignore_errors=True)
        tmp.rename(out)
    return out


def track(folder: Path, options: SilhouetteOptions, tree: Any) -> dict[str, Any]:
    """Run the tracker over a capture: MPJPE per frame (17 joints), poses, CPU time."""
    truth = read_pose_jsonl(folder / "truth.jsonl")
    src = open_source(folder)
    assert src.cameras is not None
    tracker = create_silhouette_tracker(options, src.cameras[:1], tree=tree)
    errs: list[float] = []
    cpu: list[float] = []
    first = -1
    frames = 0
    with src:
        for fs in src:
            c0 = time.process_time()
            r = tracker.process(FrameSet(fs.frames[:1], fs.t, fs.index))
            cpu.append(1000 * (time.process_time() - c0))
            T = truth.joints[fs.index]
            if not np.isfinite(T).all():
                continue
            frames += 1
            e = np.linalg.norm(r.joints - T, axis=1) if r.found else np.full(17, np.nan)
            if np.isfinite(e).all():
                errs.append(float(e.mean()))
                if first < 0:
                    first = frames - 1
    e = 100 * np.array(errs)
    return {"median_cm": float(np.median(e)) if e.size else float("nan"),
            "mean_cm": float(e.mean()) if e.size else float("nan"),
            "found": len(errs) / max(frames, 1), "first": first, "frames": frames,
            "body": tracker.body_name, "cpu_ms": float(np.median(cpu[1:])) if cpu else 0.0}


def _worst(values: list[float]) -> float:
    """The worst of clip medians; a capture without a pose is the worst (inf)."""
    return max(v if np.isfinite(v) else np.inf for v in values)


def summarize(rows: list[dict[str, Any]]) -> list[str]:
    """Per room: median / worst clip, fewest frames with a pose; then the half's
    median of rooms and its worst room (markdown lines)."""
    def fmt(v: float) -> str:
        return f"{v:.1f}" if np.isfinite(v) else "-"

    lines = ["| room | clips | MPJPE median of clips / worst clip (cm) | frames with a pose, "
             "fewest | first frame with a pose, latest |", "|---|---|---|---|---|"]
    meds, worsts = [], []
    for room in dict.fromkeys(r["room"] for r in rows):
        sel = [r for r in rows if r["room"] == room]
        v = [r["median_cm"] if r["found"] > 0 else float("inf") for r in sel]
        med, worst = float(np.median(v)), _worst(v)
        meds.append(med)
        worsts.append(worst)
        lines.append(f"| {room} | {', '.join(short(r['clip']) for r in sel)} | {fmt(med)} / "
                     f"{fmt(worst)} | {100 * min(r['found'] for r in sel):.0f}% | "
                     f"{max(r['first'] for r in sel)} |")
    found = [r["found"] for r in rows]
    lines.append(f"| **all rooms: median of rooms / worst room** | {len(rows)} captures | "
                 f"**{fmt(float(np.median(meds)))} / {fmt(max(worsts))}** | "
                 f"{100 * float(np.median(found)):.0f}% median, {100 * min(found):.0f}% fewest | |")
    return lines


def main(argv: list[str] | None = None) -> int:
    """Render what is missing, track every capture of a half, print the tables."""
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--half", choices=("tune", "report", "photo"), default="report",
                   help="photo: the tune clips in front of a photo of a person (tune side)")
    p.add_argument("--work", default="/tmp/bodyplay_silhouette_rooms",
                   help="cache of rooms and captures (outside the repository)")
    p.add_argument("--seconds", type=float, default=4.0)
    p.add_argument("--clips-per-room", type=int, default=2)
    p.add_argument("--rooms", default="", help="only these rooms (comma-separated)")
    p.add_argument("--in", dest="same", default="",
                   help="every capture of the half in this one room instead (a reference: "
                        "the same clips in the room the tracker was tuned in, `--in brick`)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="a SilhouetteOptions field (background.NAME, hierarchy.NAME)")
    p.add_argument("--draw", type=int, default=0,
                   help="a fresh set nobody has tuned on (N >= 1): another part of each "
                        "clip, body, camera seed and pictures of the generated rooms")
    p.add_argument("--list", action="store_true", help="print the plan of both halves")
    p.add_argument("--json", help="also write the per-capture rows to this file")
    args = p.parse_args(argv)
    if args.draw < 0:
        p.error(f"--draw must be 0 (the set every figure was measured on) or more, got {args.draw}")
    if args.list:
        for half in ("tune", "report", "photo"):
            for room, clip, start in plan(half, args.clips_per_room, args.draw):
                print(f"{half:6s} {room:10s} {short(clip)} from "
                      + (f"{start:g} s" if start >= 0 else f"draw {args.draw}'s part"))
        return 0
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    options = options_with_overrides(SilhouetteOptions(), args.set)
    only = set(args.rooms.split(",")) if args.rooms else None
    planned = [(i, t) for i, t in enumerate(plan(args.half, args.clips_per_room, args.draw))
               if only is None or t[0] in only]  # i: the capture's body and seed
    names = [t[0] for _, t in planned]
    todo = [(args.same, clip, start) if args.same else (room, clip, start)
            for _, (room, clip, start) in planned]  # --in: the same clips in one room
    print(f"# silhouette tracker in {len(set(names))} rooms"
          + (f" (all of it in {args.same})" if args.same else "") + f", half {args.half}, "
          f"{datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, {machine()}"
          + (f", draw {args.draw}" if args.draw else "")
          + (f", set {' '.join(args.set)}" if args.set else ""), flush=True)
    tree = load_or_build_tree(options.hierarchy, progress=False)
    rows = []
    t0 = time.perf_counter()
    done: dict[Path, dict[str, Any]] = {}  # with --in, a capture may come twice
    for (index, _), (room, clip, start), name in zip(planned, todo, names, strict=True):
        folder = capture(work, room, clip, start, args.seconds, args.draw, index)
        if folder not in done:
            done[folder] = track(folder, options, tree)
        r = dict(done[folder])
        r.update(room=name if room == name else f"{name} (in {room})", clip=clip, start=start)
        rows.append(r)
        med = f"{r['median_cm']:5.1f}" if r["found"] > 0 else "    -"
        print(f"  {r['room']:10s} {short(clip):22s} {med} / {r['mean_cm']:5.1f} cm  pose "
              f"{100 * r['found']:3.0f}% from frame {r['first']:3d}  body {r['body']}  "
              f"cpu {r['cpu_ms']:.1f} ms", flush=True)
    print()
    print("\n".join(summarize(rows)))
    print(f"# {time.perf_counter() - t0:.0f} s")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
