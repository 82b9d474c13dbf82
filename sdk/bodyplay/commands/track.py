"""``bodyplay track``: run a tracker over a capture and write poses.jsonl.

``bodyplay track --tracker colorshirt --input CAPTURE --out poses.jsonl`` reads a
capture folder (``calib.json`` + ``cam0.mp4`` ...), feeds every frame set to the
tracker and writes one TrackResult record per frame (world metres, per-joint
state, processing ms). ``--overlay FILE.mp4`` draws the estimated skeleton and the
classified shirt patches over camera 0's frames.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.errors import ConfigError

__all__ = ["register", "run", "draw_overlay"]


def register(subparsers: Any) -> None:
    """Add the ``track`` sub-command."""
    p = subparsers.add_parser(
        "track", help="track poses in a capture folder and write poses.jsonl",
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--tracker", default="colorshirt", help="tracker name (default colorshirt)")
    p.add_argument("--input", required=True,
                   help="capture folder with calib.json, or a video / webcam (0, webcam, "
                   "webcam:N) with --calib")
    p.add_argument("--calib", help="calib.json whose first camera a video or webcam input uses")
    p.add_argument("--out", required=True, help="poses.jsonl to write")
    p.add_argument("--cameras", type=int, help="use only the first N cameras")
    p.add_argument("--frames", type=int, help="stop after N frame sets")
    p.add_argument("--overlay", metavar="FILE.mp4", help="write camera 0 with the estimate drawn")
    cs = p.add_argument_group("colorshirt options")
    cs.add_argument("--no-adaptive-wb", action="store_true",
                    help="keep the first frame's white balance (no refit, no references)")
    cs.add_argument("--no-pose-prior", action="store_true",
                    help="no pose-assisted classification and no IK priors")
    cs.add_argument("--db-size", type=int, default=20_000, help="poses in the database")
    cs.add_argument("--cache", help="database cache folder (default ~/.cache/bodyplay)")
    cs.add_argument("--color-model", help="color model JSON from `bodyplay colors fit`")
    cs.add_argument("--body", default="auto",
                    help="body preset of the generic skeleton, or 'auto' (default): "
                         "chosen among all presets on the first frames")
    cs.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="any other ColorShirtOptions field (repeatable), e.g. "
                         "--set max_speed=4 --set measurement_noise=0 --set locate.tau=0.12; "
                         "see docs/colorshirt.md for the list; with --tracker silhouette "
                         "a SilhouetteOptions field, e.g. --set max_distance=12 "
                         "--set background.learn_after=8")
    p.set_defaults(func=run)


def _make_tracker(args: argparse.Namespace, cameras: tuple[Any, ...], plugins: Any) -> Any:
    if args.tracker == "colorshirt":
        from bodyplay.trackers.colorshirt import (
            ColorShirtOptions,
            create_colorshirt_tracker,
            options_with_overrides,
        )

        opts = ColorShirtOptions(
            adaptive_white_balance=not args.no_adaptive_wb,
            pose_prior=not args.no_pose_prior,
            database_size=args.db_size,
            database_cache=args.cache,
            color_model=args.color_model,
            body=args.body,
        )
        opts = options_with_overrides(opts, args.set)
        return create_colorshirt_tracker(opts, cameras, progress=True)
    from bodyplay.trackers import create_tracker

    if args.tracker == "silhouette":
        from bodyplay.trackers.silhouette import create_silhouette_tracker

        # the first use builds the shape hierarchy (minutes): show its progress
        return create_silhouette_tracker(_silhouette_options(args.set), cameras,
                                         progress=True)
    if args.set:
        raise ConfigError(f"--set applies to the colorshirt and silhouette trackers' "
                          f"options, not to {args.tracker!r}")
    # any other tracker plugin (entry point group ``bodyplay.trackers``), default options
    return create_tracker(args.tracker, cameras, registry=plugins)


def _silhouette_options(items: list[str]) -> Any:
    """SilhouetteOptions with ``--set NAME=VALUE`` applied (any field, ``background.NAME``
    and ``hierarchy.NAME`` for the nested ones; e.g. ``--set max_distance=12`` for a
    camera far from the player)."""
    from bodyplay.overrides import options_with_overrides
    from bodyplay.trackers.silhouette import SilhouetteOptions

    return options_with_overrides(SilhouetteOptions(), items)


def draw_overlay(image: NDArray[np.uint8], result: Any, camera: Any,
                 camera_index: int = 0) -> NDArray[np.uint8]:
    """Camera image (RGB) with classified patches tinted in and the skeleton drawn."""
    from bodyplay.body.joints import BONES, JOINT_INDEX
    from bodyplay.body.shirt import SHIRT_COLORS

    out = image.copy()
    _draw_silhouette(out, result)
    pal = np.zeros((256, 3), np.uint8)
    pal[1 : len(SHIRT_COLORS) + 1] = [c.rgb for c in SHIRT_COLORS]
    for idx, window, ids in result.extras.get("classified", []):
        if idx != camera_index:
            continue
        x0, y0 = int(window.x0), int(window.y0)
        w = min(int(round(window.width / window.scale)), out.shape[1] - x0)
        h = min(int(round(window.height / window.scale)), out.shape[0] - y0)
        if w <= 0 or h <= 0:
            continue
        big = cv2.resize(ids, (w, h), interpolation=cv2.INTER_NEAREST)
        on = big > 0
        region = out[y0 : y0 + h, x0 : x0 + w]
        region[on] = (0.4 * region[on] + 0.6 * pal[big[on]]).astype(np.uint8)
    if result.found:
        uv = camera.project(result.joints)
        for a, b in BONES:
            pa, pb = uv[JOINT_INDEX[a]], uv[JOINT_INDEX[b]]
            if np.all(np.isfinite(pa)) and np.all(np.isfinite(pb)):
                cv2.line(out, tuple(int(v) for v in pa), tuple(int(v) for v in pb),
                         (255, 255, 255), 2, cv2.LINE_AA)
        for j, s in enumerate(result.state):
            if s != "lost" and np.all(np.isfinite(uv[j])):
                col = (0, 255, 0) if s == "tracked" else (255, 200, 0)
                cv2.circle(out, tuple(int(v) for v in uv[j]), 4, col, -1, cv2.LINE_AA)
    else:
        cv2.putText(out, "lost", (10, 30), cv2.FONT_HERSHEY_SIMPLEX, 1.0, (255, 0, 0), 2)
    for idx, feet in result.extras.get("feet", []):
        if idx == camera_index:  # where the floor cue saw the feet touch the floor
            for f in feet:
                cv2.drawMarker(out, (int(f.u), int(f.v)), (255, 0, 255), cv2.MARKER_TILTED_CROSS,
                               12, 2, cv2.LINE_AA)
    for idx, head in result.extras.get("heads", []):
        if idx == camera_index:  # where the head cue found the head above the collar
            cv2.circle(out, (int(head.u), int(head.v)), max(2, int(head.radius)), (255, 0, 255),
                       1, cv2.LINE_AA)
    return out


def _draw_silhouette(out: NDArray[np.uint8], result: Any) -> None:
    """The silhouette tracker's observed silhouette (tinted) and chosen template
    (outlined), drawn in place."""
    sil = result.extras.get("silhouette")
    if sil is None:
        return
    h, w = out.shape[:2]
    big = cv2.resize(np.asarray(sil, np.uint8), (w, h), interpolation=cv2.INTER_NEAREST) > 0
    out[big] = (0.55 * out[big] + 0.45 * np.array([60, 200, 90])).astype(np.uint8)
    tpl = result.extras.get("template")
    if tpl is not None:
        t = cv2.resize(np.asarray(tpl, np.uint8), (w, h), interpolation=cv2.INTER_NEAREST)
        contours, _ = cv2.findContours(t, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
        cv2.drawContours(out, contours, -1, (255, 80, 60), 2, cv2.LINE_AA)


def run(args: argparse.Namespace) -> int:
    """Track every frame set, write poses.jsonl (and the overlay); print a summary."""
    from bodyplay.capture.sources import open_source
    from bodyplay.plugins import PluginRegistry

    plugins = PluginRegistry()
    installed = plugins.names("trackers")
    if args.tracker not in installed:
        raise ConfigError(f"unknown tracker {args.tracker!r}; installed trackers: "
                          f"{', '.join(installed)}")
    camera = None
    if getattr(args, "calib", None):
        from bodyplay.capture.camera import read_calib

        camera = read_calib(args.calib)[0]
    src = open_source(args.input, camera=camera)
    if src.cameras is None:
        raise ConfigError(f"{args.input}: no calibration; the tracker needs a calibrated "
                          f"camera: pass --calib calib.json (made by `bodyplay calibrate`)")
    cams = tuple(src.cameras[: args.cameras] if args.cameras else src.cameras)
    tracker = _make_tracker(args, cams, plugins)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    ms: list[float] = []
    writer_box: list[Any] = [None]
    try:
        n, found, used = _track_all(args, src, cams, tracker, ms, writer_box)
    finally:
        # the overlay is playable up to the last frame even if tracking failed
        if writer_box[0] is not None:
            writer_box[0].release()
    med = float(np.median(ms)) if ms else float("nan")
    print(f"tracked {n} frame sets with {args.tracker}: pose found in {found}, "
          f"median {med:.1f} ms per frame set; wrote {args.out}")
    body = getattr(tracker, "body_name", None)
    if body is not None:
        requested = getattr(getattr(tracker, "options", None), "body", args.body)
        how = "chosen on the first frames" if requested == "auto" else "as requested"
        print(f"body preset: {body} ({how})")
    options = getattr(tracker, "options", None)
    floor, heads, arms = used["floor_cue"], used["heads"], used["arms"]
    if getattr(options, "floor_cue", False) and found:
        hint = ("" if floor else " (it serves frames that one camera alone sees)" if heads
                else " (it needs a background plate: start the capture with a second of the "
                     "empty room)")
        print(f"floor cue: feet seen on the floor in {floor} of the {found} frame sets with a "
              f"pose{hint}")
    if getattr(options, "head_cue", False) and found:
        print(f"head cue: head seen above the collar in {heads} of the {found} frame sets with "
              "a pose" + ("" if heads else " (it needs a background plate: start the capture "
                                          "with a second of the empty room)"))
    if getattr(options, "arm_search", False) and found:
        print(f"arm search: arms chosen from the arm library in {arms} of the {found} frame "
              "sets with a pose" + ("" if arms else " (with one camera it starts once the "
                                                    "body is chosen)"))
    return 0


def _track_all(args: argparse.Namespace, src: Any, cams: tuple[Any, ...], tracker: Any,
               ms: list[float], writer_box: list[Any]) -> tuple[int, int, dict[str, int]]:
    """The tracking loop of :func:`run`: poses to ``args.out`` (flushed per record),
    overlay frames to the writer it opens in ``writer_box``. Returns the frame sets
    read, those with a pose, and per step beyond the paper (the result's extras
    ``floor_cue``, ``heads``, ``arms``) how many of those used it."""
    from bodyplay.capture.frames import FrameSet
    from bodyplay.capture.jsonl import PoseJsonlWriter

    n = found = 0
    used = dict.fromkeys(("floor_cue", "heads", "arms"), 0)
    with src, PoseJsonlWriter(args.out) as out:
        for fs in src:
            if args.frames is not None and n >= args.frames:
                break
            fs = FrameSet(fs.frames[: len(cams)], fs.t, fs.index)
            result = tracker.process(fs)
            out.write(result.to_json())
            n += 1
            found += int(result.found)
            for key in used:
                used[key] += int(result.found and bool(result.extras.get(key)))
            ms.append(result.ms)
            if args.overlay:
                img = draw_overlay(fs.frames[0].image, result, cams[0])
                if writer_box[0] is None:
                    h, w = img.shape[:2]
                    writer_box[0] = cv2.VideoWriter(
                        args.overlay, cv2.VideoWriter.fourcc(*"mp4v"), src.fps, (w, h)
                    )
                writer_box[0].write(cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
    return n, found, used
