"""Validation set of the color-shirt tracker that represents users, not the benchmark.

The four clips of ``colorshirt_bench.py`` (and its four validation clips) are what
the tracker's rules were tuned on. This set is wider:

* **clips**: every clip in ``../shared/data/mocap`` (15 Bandai Namco clips, the 4 CMU
  clips that are also vendored as built-ins), the centre ``--seconds`` of each; a CMU
  clip is scored with a pose database built *without* that clip (the database
  samples the built-in CMU clips; Bandai clips are never in it);
* **players who travel in depth**: ``approach`` variants walk 1.2 m towards the
  camera over the clip, ``hop`` variants jump forward (three 0.25 m hops, the
  feet leaving the floor by up to 0.18 m);
* **bodies**: the actor cycles through the presets ``m``, ``m_slim``, ``l``, ``s``;
* **rooms**: shipped photos and procedurally generated rooms full of shirt
  colours (``posters``, ``fruit``, ``clothes``, see :func:`make_room`), cached
  as PNG under ``--work``;
* **light**: ``steady``, ``switch`` (the warm lamp goes off mid-capture) and
  ``mixed`` (in a generated cluttered room);
* **starts**: ``in view`` (the tracker sees the player from its first frame, the
  default of how people start) and ``empty`` (one second of the empty room first);
* **cameras**: two, and the first of them alone.

Every capture (two cameras, 640x480, one second of empty room then the clip) is
rendered once and cached under ``--work``; the ``in view`` runs skip its empty
frames. The clips are split deterministically: the eight the tracker was tuned on
go to the **tune** half with every other one of the rest (sorted by name); the
others form the **report** half. Tune only with ``--half tune``; report
``--half report``. Every figure so far is of **draw 0**; ``--draw N`` (N >= 1) renders
a fresh set of the same clips (another part of each clip, other rooms, body presets,
camera placement and noise, other generated rooms), to judge a change chosen on draw
0's halves on captures nobody has tuned on (``--half all --draw 1``). Per setting
it prints the median and the worst clip's upper-body MPJPE (cm, over the frames
with a pose), the share of frames with a pose (median and worst), and the median
time per camera frame counted from the
first frame (start-up included), with the machine and the date; once over all
clips, then split by room kind: ``photo`` (the shipped photos, as in the issue's
steady and lamp-switch rows) and ``clutter`` (the generated rooms full of shirt
colours, which the issue tried under mixed light only). The MPJPE is the issue's:
the mean distance of the eleven upper-body joints (pelvis to wrists, DESIGN.md) in
the world, *not* root-aligned, over the frames with a pose; the root-aligned
figure (the ten others relative to the pelvis) is printed beside it.

    nice .venv/bin/python benchmarks/colorshirt_validation.py --half report
    nice .venv/bin/python benchmarks/colorshirt_validation.py --half tune --settings steady-2-view
    .venv/bin/python benchmarks/colorshirt_validation.py --list     # the clips and settings

Results of each run are appended to ``--results`` (JSONL) and reused by later
invocations with the same ``--tag`` (``--fresh`` recomputes), so an interrupted run
resumes where it stopped. Each row keeps, per scored frame with a pose, its number
from the start, the eleven joints' errors (cm) and how many cameras' pixels counted
(``per_frame``): ``colorshirt_decompose.py`` splits the error by cause from them;
and with one camera the root's depth error along the camera's axis, the reported
``depth_std`` and the depth filter's own estimate's error (cm, ``per_frame_depth``):
``colorshirt_depth_noise.py`` splits it into bias and frame-to-frame noise.
"""

from __future__ import annotations

import argparse
import ast
import datetime
import hashlib
import json
import os
import shutil
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

from _machine import machine
from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.shirt import SHIRT_COLORS
from bodyplay.body.skeleton import Skeleton
from bodyplay.capture.frames import FrameSet
from bodyplay.capture.jsonl import read_pose_jsonl
from bodyplay.capture.sources import open_source
from bodyplay.trackers.colorshirt import (
    ColorShirtOptions,
    DatabaseOptions,
    create_colorshirt_tracker,
)
from bodyplay.trackers.colorshirt.database import (
    PoseDatabase,
    load_or_build_database,
    sample_database_poses,
)

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
MOCAP = DATA / "mocap"
TUNED = (
    "dataset-2_wave-both-hands_normal_001",
    "dataset-1_punch_normal_001",
    "dataset-2_raise-up-both-hands_normal_001",
    "dataset-1_dance-short_normal_001",
    "dataset-1_bow_normal_001",
    "dataset-1_slash_normal_001",
    "dataset-2_raise-up-left-hand_normal_001",
    "dataset-1_respond_normal_001",
)
"""The clips of colorshirt_bench.py (test and validation): the tracker was tuned on them."""
TRAVEL = (
    ("approach", "dataset-2_wave-right-hand_normal_001"),
    ("hop", "dataset-1_punch_normal_002"),
    ("approach", "dataset-2_raise-up-left-hand_normal_001"),
    ("hop", "dataset-1_punch_normal_001"),
)
"""Variants that travel in depth: (kind, base clip); they join their base clip's half."""
BODIES = ("m", "m_slim", "l", "s")
PHOTO_ROOMS = ("brick", "coffee", "rocket", "gravel", "astronaut")
CLUTTER_ROOMS = ("posters", "fruit", "clothes")
STEADY_ROOMS = ("brick", "posters", "coffee", "clothes", "rocket", "fruit")
SWITCH_ROOMS = ("fruit", "gravel", "clothes", "astronaut", "posters", "brick")
DRAW_ROOM_STEP = 5
"""How far each draw moves a clip along the room lists (prime to their lengths, 6 and 3)."""
GOLDEN = 0.6180339887


@dataclass(frozen=True)
class Setting:
    """One way of running the tracker on a clip's capture."""

    name: str
    lighting: str
    cameras: int
    start: str  # "view" or "empty"


SETTINGS = tuple(
    Setting(f"{light}-{cams}-{start}", light, cams, start)
    for light in ("steady", "switch", "mixed")
    for cams in (2, 1)
    for start in ("view", "empty")
)
DEFAULT_SETTINGS = ("steady-2-view", "steady-2-empty", "steady-1-view", "steady-1-empty",
                    "switch-2-view", "switch-1-view", "mixed-2-view", "mixed-1-view")


@dataclass(frozen=True)
class Clip:
    """A validation clip: a mocap file, optionally made to travel in depth."""

    name: str
    path: Path
    travel: str | None = None  # None, "approach" or "hop"
    builtin: str | None = None  # name of the built-in clip it is (left out of the database)


DRAW_HELP = ("0: the captures every figure so far was measured on; 1, 2, ...: a fresh "
             "draw of the same clips (another part of each, other rooms, bodies, camera "
             "placement) to judge a change chosen on draw 0 on data nobody tuned on")


def all_clips() -> list[Clip]:
    """Every clip of the set, in a fixed order (sorted by name, travel variants last)."""
    clips = [Clip(p.stem, p) for p in sorted((MOCAP / "bandai_namco").glob("*.bvh"))]
    clips += [Clip(p.stem, p, builtin=p.stem) for p in sorted((MOCAP / "cmu").glob("*.bvh"))]
    clips.sort(key=lambda c: c.name)
    base = {c.name: c for c in clips}
    for kind, name in TRAVEL:
        if name in base:
            clips.append(replace(base[name], name=f"{kind}:{name}", travel=kind))
    return clips


def half_of(clip: Clip, clips: list[Clip]) -> str:
    """``tune`` or ``report``: tuned-on clips tune, the rest alternate by sorted name."""
    name = clip.name.split(":")[-1]
    if name in TUNED:
        return "tune"
    rest = sorted({c.name.split(":")[-1] for c in clips} - set(TUNED))
    return "report" if rest.index(name) % 2 == 0 else "tune"


# ---- rooms ---------------------------------------------------------------------------
def make_room(kind: str, seed: int, size: tuple[int, int] = (1280, 960)) -> NDArray[np.uint8]:
    """A procedural room photo (RGB) full of shirt-like colours.

    A wall over a floor band; ``posters``: framed rectangles and stripes in
    saturated colours near the shirt's; ``fruit``: bowls and piles of round fruit
    (orange, yellow, lime, red) on shelves and a table; ``clothes``: garments on a
    rail and folded piles, in the shirt's colours. Colours jitter around the
    shirt legend, so some pass its classifier and some only come close.
    """
    rng = np.random.default_rng(seed)
    w, h = size
    img = np.zeros((h, w, 3), np.float32)
    wall = rng.uniform(150, 215, 3)
    img[:] = wall
    floor_y = int(h * rng.uniform(0.62, 0.7))
    img[floor_y:] = rng.uniform(80, 140, 3)
    for x in range(0, w, int(rng.integers(60, 110))):  # floor boards
        cv2.line(img, (x, floor_y), (x + int(rng.integers(-40, 40)), h), (60, 50, 40), 2)
    palette = np.array([c.rgb for c in SHIRT_COLORS], np.float32)

    def color() -> tuple[float, ...]:
        c = palette[rng.integers(len(palette))] + rng.normal(0, 18, 3)
        return tuple(float(v) for v in np.clip(c, 0, 255))

    if kind == "posters":
        for _ in range(14):
            x0, y0 = int(rng.uniform(0, w - 120)), int(rng.uniform(20, floor_y - 150))
            pw, ph = int(rng.uniform(90, 260)), int(rng.uniform(120, 300))
            cv2.rectangle(img, (x0 - 6, y0 - 6), (x0 + pw + 6, y0 + ph + 6), (30, 30, 30), -1)
            cv2.rectangle(img, (x0, y0), (x0 + pw, y0 + ph), color(), -1)
            for _ in range(int(rng.integers(1, 5))):
                a, b = int(rng.uniform(x0, x0 + pw)), int(rng.uniform(y0, y0 + ph))
                cv2.rectangle(img, (a, b), (min(a + int(rng.uniform(20, 90)), x0 + pw),
                                            min(b + int(rng.uniform(15, 80)), y0 + ph)),
                              color(), -1)
        for _ in range(3):  # a striped rug
            y = int(rng.uniform(floor_y + 20, h - 80))
            for k in range(6):
                cv2.rectangle(img, (int(w * 0.2), y + 12 * k), (int(w * 0.8), y + 12 * k + 12),
                              color(), -1)
    elif kind == "fruit":
        for shelf in range(3):
            y = int(floor_y * (0.3 + 0.25 * shelf))
            cv2.rectangle(img, (0, y), (w, y + 14), (110, 80, 50), -1)
            for _ in range(40):
                r = int(rng.uniform(14, 34))
                x = int(rng.uniform(0, w))
                c = palette[rng.choice([0, 1, 2, 3])] + rng.normal(0, 15, 3)
                cv2.circle(img, (x, y - r), r, tuple(float(v) for v in np.clip(c, 0, 255)), -1)
        ty = floor_y + 40
        cv2.rectangle(img, (int(w * 0.55), ty), (int(w * 0.95), ty + 25), (120, 85, 55), -1)
        for _ in range(60):
            r = int(rng.uniform(12, 30))
            x, y = int(rng.uniform(w * 0.55, w * 0.95)), int(ty - rng.uniform(0, 60))
            c = palette[rng.choice([0, 1, 2, 3, 4])] + rng.normal(0, 15, 3)
            cv2.circle(img, (x, y), r, tuple(float(v) for v in np.clip(c, 0, 255)), -1)
    elif kind == "clothes":
        rail = int(floor_y * 0.18)
        cv2.line(img, (0, rail), (w, rail), (60, 60, 60), 5)
        x = 10
        while x < w - 60:
            gw = int(rng.uniform(70, 140))
            gh = int(rng.uniform(200, 380))
            c = color()
            cv2.rectangle(img, (x, rail), (x + gw, rail + gh), c, -1)  # body
            cv2.rectangle(img, (x - 18, rail), (x + 4, rail + gh // 2), color(), -1)  # sleeve
            cv2.rectangle(img, (x + gw - 4, rail), (x + gw + 18, rail + gh // 2), c, -1)
            x += gw + int(rng.uniform(-20, 30))
        for _ in range(5):  # folded piles on the floor
            x0 = int(rng.uniform(0, w - 200))
            y0 = int(rng.uniform(floor_y + 10, h - 60))
            for k in range(4):
                cv2.rectangle(img, (x0, y0 - 18 * k), (x0 + 160, y0 - 18 * k + 16), color(), -1)
    elif kind != "plain":
        raise ValueError(f"unknown room {kind!r}")
    img += rng.normal(0, 4, img.shape).astype(np.float32)  # texture
    return np.clip(cv2.GaussianBlur(img, (3, 3), 0), 0, 255).astype(np.uint8)


def room_path(work: Path, room: str, draw: int = 0) -> str:
    """A shipped background name, or the cached PNG of a generated room (another
    picture of the same kind in each ``draw``)."""
    if room not in CLUTTER_ROOMS:
        return room
    name = room if draw == 0 else f"{room}-d{draw}"
    path = work / "rooms" / f"{name}.png"
    if not path.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
        seed = int(hashlib.sha1(name.encode()).hexdigest()[:8], 16)
        cv2.imwrite(str(path), cv2.cvtColor(make_room(room, seed), cv2.COLOR_RGB2BGR))
    return str(path)


def room_for(lighting: str, index: int, draw: int = 0) -> str:
    """The room of the ``index``-th clip under a lighting (cluttered rooms for mixed);
    each ``draw`` moves every clip to another room of the list."""
    rooms = {"steady": STEADY_ROOMS, "switch": SWITCH_ROOMS, "mixed": CLUTTER_ROOMS}[lighting]
    return rooms[(index + DRAW_ROOM_STEP * draw) % len(rooms)]


def body_for(index: int, draw: int = 0) -> str:
    """The actor's body preset of the ``index``-th clip (another one in each ``draw``)."""
    return BODIES[(index + draw) % len(BODIES)]


def start_fraction(draw: int) -> float:
    """Where a clip's part starts, as a share of the time left beside it: the centre
    in draw 0, elsewhere in later draws (a golden-ratio walk over the clip)."""
    return 0.5 if draw == 0 else (0.5 + GOLDEN * draw) % 1.0


# ---- captures --------------------------------------------------------------------------
def _travel(poses: NDArray[np.float64], joints: NDArray[np.float64], kind: str,
            fps: float) -> NDArray[np.float64]:
    """Poses moved towards where the actor faces: a walk (approach) or forward hops."""
    j = joints
    left = (j[:, JOINT_INDEX["l_hip"]] - j[:, JOINT_INDEX["r_hip"]]).sum(axis=0)
    fwd = np.cross(left, np.array([0.0, 1.0, 0.0]))
    fwd[1] = 0.0
    fwd /= max(float(np.linalg.norm(fwd)), 1e-9)
    n = poses.shape[0]
    s = np.linspace(0.0, 1.0, n)
    out = poses.copy()
    if kind == "approach":
        out[:, 0:3] += 1.2 * s[:, None] * fwd
    else:  # three hops, each 0.25 m forward and up to 0.18 m up, the feet off the floor
        phase = 3.0 * s
        k = np.minimum(np.floor(phase), 2.0)
        f = np.clip((phase - k) / 0.45, 0.0, 1.0)  # the hop's flight is 45% of its cycle
        out[:, 0:3] += (0.25 * (k + f))[:, None] * fwd
        out[:, 1] += 0.18 * np.sin(np.pi * f) * (f < 1.0)
    return out


def capture(work: Path, clip: Clip, lighting: str, index: int, seconds: float,
            lead_in: float = 1.0, draw: int = 0) -> Path:
    """The cached two-camera capture of a clip under a lighting: lead-in, then the clip.

    ``draw`` 0 is the set every figure so far was measured on; a later draw is a
    fresh set of the same clips that nobody has tuned on: another part of each clip,
    another room and body preset, other cameras' placement and noise (the rig's and
    the camera's seed), other generated rooms.
    """
    from bodyplay.body.actor import load_actor
    from bodyplay.motion.clip import load_clip
    from bodyplay.synth.camera import SyntheticCamera
    from bodyplay.synth.options import make_synthetic_camera_options
    from bodyplay.synth.writer import write_capture

    room = room_for(lighting, index, draw)
    body = body_for(index, draw)
    key = f"{clip.name.replace(':', '_')}_{lighting}_{room}_{body}_{seconds:g}s"
    if draw:
        key += f"_d{draw}"
    out = work / "captures" / key
    if (out / "meta.json").exists():
        return out
    actor = load_actor(shape=body)
    full = load_clip(str(clip.path), skeleton=actor.skeleton)
    start = max(0.0, start_fraction(draw) * (full.duration - seconds))
    part = full.slice(start, min(seconds, full.duration))
    if clip.travel:
        part = replace(part, poses=_travel(part.poses, part.joints(), clip.travel, part.fps),
                       source_joints=None)
    options = make_synthetic_camera_options(cameras=2, background=room_path(work, room, draw),
                                            lighting=lighting, body=body,
                                            seed=index + 1000 * draw)
    cam = SyntheticCamera(options, part, actor=actor, duration=lead_in + part.duration)
    tmp = out.with_name(f"{out.name}.tmp{os.getpid()}")  # another run may render it too
    with cam:
        write_capture(tmp, cam, cam.from_clip(lead_in=lead_in),
                      run={"clip": clip.name, "start": start, "seconds": seconds,
                           "lead_in": lead_in, "travel": clip.travel, "draw": draw})
    try:
        tmp.rename(out)
    except OSError:
        shutil.rmtree(tmp)
    return out


# ---- databases -------------------------------------------------------------------------
def _sampler_without(builtin: str) -> Callable[..., NDArray[np.float64]]:
    """A database pose sampler that leaves one built-in clip out."""
    def poses(skeleton: Skeleton, n: int, rng: np.random.Generator,
              options: DatabaseOptions) -> NDArray[np.float64]:
        from bodyplay.motion import list_builtin_clips, sample_poses

        clips = [c for c in list_builtin_clips() if c != builtin]
        yaw = float(np.radians(options.yaw_deg))
        return np.asarray(sample_poses(skeleton, n, rng, clips=clips, mode="mixed",
                                       yaw_range=(-yaw, yaw),
                                       max_tilt=float(np.radians(options.tilt_deg))),
                          dtype=np.float64)

    poses.__qualname__ = f"sample_database_poses_without_{builtin}"
    return poses


def database_for(clip: Clip, options: ColorShirtOptions, cache: dict[str, PoseDatabase]
                 ) -> PoseDatabase:
    """The pose database a clip is scored with: without the clip's own poses."""
    key = clip.builtin or ""
    if key not in cache:
        sampler = _sampler_without(clip.builtin) if clip.builtin else sample_database_poses
        cache[key] = load_or_build_database(
            Skeleton.from_shape("m"),
            DatabaseOptions(size=options.database_size, yaw_deg=options.database_yaw),
            pose_source=sampler)
    return cache[key]


def add_capture_arguments(ap: argparse.ArgumentParser, setting: str) -> None:
    """The arguments of a script that tracks one setting's captures of a half
    (``--half``, ``--setting`` defaulting to ``setting``, ``--clips``, ``--seconds``,
    ``--db-size``, ``--work``, ``--set``), as ``colorshirt_offsets.py`` and
    ``colorshirt_clutter.py`` take them."""
    ap.add_argument("--half", choices=("tune", "report", "all"), default="tune")
    ap.add_argument("--setting", default=setting)
    ap.add_argument("--clips", default="", help="only these clips (comma-separated names)")
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--draw", type=int, default=0, help=DRAW_HELP)
    ap.add_argument("--db-size", type=int, default=20_000)
    ap.add_argument("--work", default="/work/cache-colorshirt")
    ap.add_argument("--set", action="append", default=[], metavar="OPTION=VALUE")


def options_from(args: argparse.Namespace) -> ColorShirtOptions:
    """The tracker's options of :func:`add_capture_arguments`' ``--db-size`` and ``--set``."""
    extra = {k: ast.literal_eval(v) for k, v in (i.split("=", 1) for i in args.set)}
    return ColorShirtOptions(database_size=args.db_size, **extra)


def half_captures(args: argparse.Namespace, setting: Setting
                  ) -> Iterator[tuple[Clip, Path, PoseDatabase]]:
    """Each clip of ``args.half`` (and ``--clips``) with its capture in ``setting``'s
    lighting (rendered once, cached under ``--work``) and its pose database."""
    chosen = set(args.clips.split(",")) if args.clips else None
    clips = all_clips()
    dbs: dict[str, PoseDatabase] = {}
    for i, clip in enumerate(clips):
        if (args.half != "all" and half_of(clip, clips) != args.half) or (
                chosen is not None and clip.name not in chosen):
            continue
        folder = capture(Path(args.work), clip, setting.lighting, i, args.seconds,
                         draw=args.draw)
        yield clip, folder, database_for(clip, options_from(args), dbs)


# ---- running ---------------------------------------------------------------------------
def run_one(folder: Path, setting: Setting, options: ColorShirtOptions,
            db: PoseDatabase) -> dict[str, Any]:
    """Track one capture in one setting: MPJPE, found share, timing, depth error."""
    truth = read_pose_jsonl(folder / "truth.jsonl")
    src = open_source(folder)
    assert src.cameras is not None
    cams = src.cameras[: setting.cameras]
    tracker = create_colorshirt_tracker(options, cams, database=db)
    errs, aligned, ms, cpu, depth, calib = [], [], [], [], [], []
    per_frame: list[list[float]] = []  # for colorshirt_decompose.py
    per_depth: list[list[float | None]] = []  # for colorshirt_depth_noise.py
    frames = found = 0
    with src:
        for fs in src:
            has_truth = bool(np.isfinite(truth.joints[fs.index][0]).all())
            if setting.start == "view" and not has_truth:
                continue  # the tracker starts with the player in view
            c0 = time.thread_time()
            r = tracker.process(FrameSet(fs.frames[: setting.cameras], fs.t, fs.index))
            cpu.append(1000 * (time.thread_time() - c0) / setting.cameras)
            ms.append(r.ms / setting.cameras)
            if not has_truth:
                continue
            frames += 1
            if r.found:
                found += 1
                t = truth.joints[fs.index][:11]
                joint = np.linalg.norm(r.joints[:11] - t, axis=1)
                errs.append(float(joint.mean()))
                used = r.extras.get("cameras_used")
                per_frame.append([frames - 1, *(round(100 * float(e), 2) for e in joint),
                                  len(used) if isinstance(used, list) else setting.cameras])
                rel = (r.joints[:11] - r.joints[0]) - (t - t[0])  # the root aligned
                aligned.append(float(np.linalg.norm(rel[1:], axis=1).mean()))
                c = cams[0]
                depth.append(float(c.world_to_camera(r.joints[0])[2]
                                   - c.world_to_camera(t[0])[2]))
                std = r.extras.get("depth_std")
                if isinstance(std, float):  # one camera: is the reported std honest?
                    calib.append(abs(depth[-1]) < 2.0 * std)
                if setting.cameras == 1:  # with the depth filter's own estimate's error
                    post = tracker.diagnostics.get("depth_post")
                    filt = (round(100 * (float(post[0]) - c.world_to_camera(t[0])[2]), 2)
                            if isinstance(post, tuple) else None)
                    per_depth.append([frames - 1, round(100 * depth[-1], 2),
                                      round(100 * std, 2) if isinstance(std, float) else None,
                                      filt])
    e = np.array(errs)
    return {"mpjpe_cm": float(100 * e.mean()) if len(e) else float("nan"),
            "worst_frame_cm": float(100 * e.max()) if len(e) else float("nan"),
            "root_aligned_cm": float(100 * np.mean(aligned)) if aligned else float("nan"),
            "found": found / max(frames, 1), "frames": frames,
            "ms_median": float(np.median(ms)) if ms else float("nan"),
            "ms_p90": float(np.percentile(ms, 90)) if ms else float("nan"),
            "cpu_ms_median": float(np.median(cpu)) if cpu else float("nan"),
            "cpu_ms_p90": float(np.percentile(cpu, 90)) if cpu else float("nan"),
            "depth_within_2std": float(np.mean(calib)) if calib else float("nan"),
            "root_depth_bias_cm": float(100 * np.mean(depth)) if depth else float("nan"),
            "root_depth_abs_cm": float(100 * np.mean(np.abs(depth))) if depth else float("nan"),
            "body": tracker.body_name,
            "per_frame": per_frame, "per_frame_depth": per_depth}


def room_kind(row: dict[str, Any]) -> str:
    """``clutter`` for the generated rooms full of shirt colours, ``photo`` for the
    shipped photos (the kind of room of the issue's steady and switch rows)."""
    return "clutter" if any(f"_{r}_" in row["capture"] for r in CLUTTER_ROOMS) else "photo"


def summarize(rows: list[dict[str, Any]], settings: list[Setting]) -> list[str]:
    """Per setting: median and worst clip, found share, time (markdown lines); then the
    same split by room kind, and the root-aligned error beside it."""
    lines = ["| setting | rooms | clips | MPJPE median (cm) | worst clip (cm) | root aligned "
             "median (cm) | pose on frames median / worst | ms per camera frame (median, "
             "from frame 1) | CPU ms (tracking thread) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for s in settings:
        every = [r for r in rows if r["setting"] == s.name]
        for kind in ("all", "photo", "clutter"):
            sel = [r for r in every if kind == "all" or room_kind(r) == kind]
            if not sel:
                continue
            mp = np.array([r["mpjpe_cm"] for r in sel])
            worst = sel[int(np.nanargmax(mp))] if np.isfinite(mp).any() else sel[0]
            ra = np.array([r.get("root_aligned_cm", np.nan) for r in sel])
            fd = np.array([r["found"] for r in sel])
            ms = np.array([r["ms_median"] for r in sel])
            cpu = np.array([r.get("cpu_ms_median", np.nan) for r in sel])
            med_ra = f"{np.nanmedian(ra):.2f}" if np.isfinite(ra).any() else "-"
            lines.append(f"| {s.name} | {kind} | {len(sel)} | {np.nanmedian(mp):.2f} | "
                         f"{worst['mpjpe_cm']:.2f} ({worst['clip']}) | {med_ra} | "
                         f"{100 * np.median(fd):.0f}% / {100 * fd.min():.0f}% | "
                         f"{np.median(ms):.1f} | {np.median(cpu):.1f} |")
    return lines


def main(argv: list[str] | None = None) -> int:
    """Render what is missing, track every (clip, setting) of a half, print the table."""
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--half", choices=("tune", "report", "all"), default="tune")
    ap.add_argument("--settings", default=",".join(DEFAULT_SETTINGS),
                    help=f"comma-separated, of {', '.join(s.name for s in SETTINGS)}")
    ap.add_argument("--clips", default="", help="only these clips (comma-separated names)")
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--draw", type=int, default=0, help=DRAW_HELP)
    ap.add_argument("--db-size", type=int, default=20_000)
    ap.add_argument("--work", default="/work/cache-colorshirt",
                    help="cache of rooms and captures (outside the repository)")
    ap.add_argument("--results", default="",
                    help="JSONL of per-run results (default WORK/results.jsonl)")
    ap.add_argument("--tag", default="current", help="label of this code/option state")
    ap.add_argument("--fresh", action="store_true", help="recompute runs already in --results")
    ap.add_argument("--list", action="store_true", help="print the clips and their halves")
    ap.add_argument("--set", action="append", default=[], metavar="OPTION=VALUE",
                    help="override a ColorShirtOptions field (part of the tag's key)")
    ap.add_argument("--json", help="also write this invocation's rows to this JSON file")
    args = ap.parse_args(argv)
    if args.draw < 0:
        ap.error(f"--draw must be 0 (the set measured so far) or a later draw, got {args.draw}")
    if not (MOCAP / "bandai_namco").exists():
        print("shared data not found (../shared/data/mocap); nothing to validate")
        return 1
    clips = all_clips()
    if args.list:
        for i, c in enumerate(clips):
            print(f"{half_of(c, clips):6s} {c.name:48s} body {body_for(i, args.draw):7s} rooms "
                  + ", ".join(f"{lt} {room_for(lt, i, args.draw)}"
                              for lt in ("steady", "switch", "mixed")))
        return 0
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    results = Path(args.results) if args.results else work / "results.jsonl"
    by_name = {s.name: s for s in SETTINGS}
    settings = [by_name[n] for n in args.settings.split(",")]
    chosen = set(args.clips.split(",")) if args.clips else None
    extra = {k: ast.literal_eval(v) for k, v in (i.split("=", 1) for i in args.set)}
    options = ColorShirtOptions(database_size=args.db_size, **extra)
    tag = args.tag + ("" if not extra else " " + " ".join(sorted(args.set)))
    done: dict[tuple[str, str, str, float, int], dict[str, Any]] = {}
    if results.exists() and not args.fresh:
        for line in results.read_text().splitlines():
            r = json.loads(line)
            done[(r["tag"], r["clip"], r["setting"], r["seconds"], r.get("draw", 0))] = r
    print(f"# colorshirt validation, half {args.half}, draw {args.draw}, "
          f"{datetime.date.today()}, {machine()}, tag {tag!r}", flush=True)
    t0 = time.perf_counter()
    dbs: dict[str, PoseDatabase] = {}
    rows = []
    order = list(enumerate(clips))
    if args.clips:  # in the order given
        order.sort(key=lambda ic: args.clips.split(",").index(ic[1].name)
                   if ic[1].name in chosen else -1)  # type: ignore[operator]
    picked = [(i, c) for i, c in order if (args.half == "all" or half_of(c, clips) == args.half)
              and (chosen is None or c.name in chosen)]
    for s in settings:  # setting by setting: an interrupted run has whole settings
        for i, clip in picked:
            key = (tag, clip.name, s.name, args.seconds, args.draw)
            if key in done:
                rows.append(done[key])
                continue
            folder = capture(work, clip, s.lighting, i, args.seconds, draw=args.draw)
            r = run_one(folder, s, options, database_for(clip, options, dbs))
            r.update(tag=tag, clip=clip.name, setting=s.name, seconds=args.seconds, draw=args.draw,
                     half=half_of(clip, clips), capture=folder.name,
                     date=str(datetime.date.today()))
            with results.open("a") as f:
                f.write(json.dumps(r) + "\n")
            rows.append(r)
            print(f"{s.name:15s} {clip.name:48s} {r['mpjpe_cm']:6.2f} cm "
                  f"(root aligned {r['root_aligned_cm']:5.2f}, {room_kind(r)})  found "
                  f"{100 * r['found']:5.1f}%  {r['ms_median']:5.1f} ms  depth bias "
                  f"{r['root_depth_bias_cm']:6.1f} cm  body {r['body']}", flush=True)
    print("\n".join(summarize(rows, settings)))
    print(f"# total {time.perf_counter() - t0:.0f} s")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
