"""Benchmark of the silhouette tracker (papers/single-camera-silhouette-mocap.txt).

One camera, 640x480, synthetic captures of real clips rendered once into --work
(no empty-room lead-in: the player is in view from the first frame):

* clips the hierarchy is built from (the vendored CMU clips) and clips it is not
  built from (Bandai Namco, read from ../shared only); the settings were chosen on
  the CMU clips and the Bandai *validation* clips, the Bandai *test* clips are
  reported: MPJPE over all 17 joints (median over frames, mean, worst clip),
  share of frames with joints;
* recovery: a Bandai clip with ``--occlude`` hiding the body for one second;
  frames after it reappears until the error is back within 1.2x the clip's
  median;
* speed: median ms per frame and each stage's share, peak memory, the hierarchy's
  build time, poses and size;
* the color-shirt tracker on the same captures (upper body, its own figures);
* real footage: camera 1 of ../shared/data/video/pose2sim_single (the person is
  in view from the first frame): median IoU of the estimated pose's silhouette
  and the observed one; ``--overlays DIR`` writes short overlay videos of it and
  of the Sports2D clip.

* ``--tune``: instead, the nine tune captures (:data:`TUNE`) the settings are chosen
  on, median / worst / mean of their clip medians; ``--set NAME=VALUE`` tries an
  option (as ``bodyplay track --set``).
* ``--poses FILE.npz`` saves every capture's joints per frame, ``--compare BASE.npz``
  prints the largest joint difference against such a file of another commit (0 m and
  0 frames: a speed change left the output identical to the bit).

    .venv/bin/python benchmarks/silhouette_bench.py [--quick] [--overlays docs/media]
    nice .venv/bin/python benchmarks/silhouette_bench.py --tune --set arm_stay=1
"""

from __future__ import annotations

import argparse
import datetime
import resource
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.capture.frames import FrameSet
from bodyplay.capture.jsonl import read_pose_jsonl
from bodyplay.capture.sources import open_source
from bodyplay.overrides import options_with_overrides
from bodyplay.trackers.silhouette import (
    SilhouetteOptions,
    create_silhouette_tracker,
    load_or_build_tree,
)
from bodyplay.trackers.silhouette.hierarchy import tree_cache_path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _identity import compare_poses  # noqa: E402
from _machine import machine  # noqa: E402

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
BANDAI = DATA / "mocap" / "bandai_namco"
BUILT_FROM = (("13_29", 2.0), ("131_03", 0.0))
VALIDATION = ("dataset-1_bow_normal_001", "dataset-2_raise-up-left-hand_normal_001")
TEST = ("dataset-2_wave-both-hands_normal_001", "dataset-1_punch_normal_001",
        "dataset-2_raise-up-both-hands_normal_001", "dataset-1_dance-short_normal_001")
TUNE = (("13_29", 10.0, "m"), ("dataset-1_bow_normal_001", 0.0, "m"),
        ("dataset-2_raise-up-left-hand_normal_001", 0.0, "m"),
        ("dataset-2_wave-right-hand_normal_001", 0.0, "m"), ("dataset-1_kick_normal_001", 0.0, "m"),
        ("13_29", 10.0, "xs"), ("dataset-1_bow_normal_001", 0.0, "xl"),
        ("dataset-2_raise-up-left-hand_normal_001", 0.0, "s"),
        ("dataset-2_wave-right-hand_normal_001", 0.0, "l"))
"""The tune clips (clip, start in seconds, the actor's body preset): settings are
chosen on these (``--tune``), never on the built-from and Bandai test clips reported."""


def capture(work: Path, clip: str, start: float, seconds: float, occlude: str | None = None,
            body: str = "m") -> Path:
    """The synthetic one-camera capture of a clip (rendered once) by the actor ``body``."""
    tag = f"_occ{occlude.replace(':', '-')}" if occlude else ""
    tag += f"_{body}" if body != "m" else ""
    out = work / f"{clip}_{start:g}_{seconds:g}s{tag}"
    if not (out / "truth.jsonl").exists():
        src = str(BANDAI / f"{clip}.bvh") if clip.startswith("dataset") else clip
        cmd = [sys.executable, "-m", "bodyplay.cli", "synth", "--clip", src, "--out", str(out),
               "--seconds", str(seconds), "--start", str(start)]
        if occlude:
            cmd += ["--occlude", occlude]
        if body != "m":
            cmd += ["--body", body]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return out


def track(folder: Path, tracker: Any) -> dict[str, Any]:
    """Run a tracker over a capture: per-frame errors (all 17 joints), ms, stages."""
    truth = read_pose_jsonl(folder / "truth.jsonl")
    src = open_source(folder)
    errs, upper, ms, found, n = [], [], [], 0, 0
    joints: list[NDArray[np.float64]] = []
    stages: dict[str, list[float]] = {}
    with src:
        for fs in src:
            r = tracker.process(FrameSet(fs.frames[:1], fs.t, fs.index))
            ms.append(r.ms)
            joints.append(np.where(r.found, np.asarray(r.joints, np.float64), np.nan))
            for k, v in r.extras.get("stages", {}).items():
                stages.setdefault(k, []).append(1000 * v)
            T = truth.joints[fs.index]
            if not np.isfinite(T).all():
                continue
            n += 1
            e = np.linalg.norm(r.joints - T, axis=1)
            if r.found and np.isfinite(e[:11]).all():
                found += 1
                errs.append(e if np.isfinite(e).all() else np.full(17, np.nan))
                upper.append(e[:11])
            else:
                errs.append(np.full(17, np.nan))
    E = np.array(errs)
    frame_err = np.nanmean(E, axis=1)
    return {"frame_err": frame_err, "upper": np.array(upper), "ms": np.array(ms),
            "found": found / max(n, 1), "stages": stages, "frames": n,
            "joints": np.array(joints, np.float64)}


def silhouette_tracker(folder: Path, tree: Any, options: SilhouetteOptions | None = None) -> Any:
    src = open_source(folder)
    assert src.cameras is not None
    return create_silhouette_tracker(options or SilhouetteOptions(), src.cameras[:1], tree=tree)


def colorshirt_tracker(folder: Path) -> Any:
    from bodyplay.trackers.colorshirt import create_colorshirt_tracker

    src = open_source(folder)
    assert src.cameras is not None
    return create_colorshirt_tracker(None, src.cameras[:1])


def recovery(res: dict[str, Any], start: float, seconds: float, fps: float = 30.0) -> int:
    """Frames after the occluder leaves until the error is within 1.2x the median."""
    fe = res["frame_err"]
    ok = np.nanmedian(fe) * 1.2
    back = int(round((start + seconds) * fps))
    for k in range(back, len(fe)):
        if np.isfinite(fe[k]) and fe[k] <= ok:
            return k - back
    return -1


def real_iou(tree: Any, folder: Path, frames: int, overlay: Path | None) -> tuple[float, int]:
    """Median IoU of the chosen template and the observed silhouette on a real capture,
    and the number of frames read (the Pose2Sim videos hold 100). The fuller real-footage
    figures (four cameras, a reference mask, a 3-D proxy) are benchmarks/silhouette_real.py's."""
    from bodyplay.commands.track import draw_overlay

    src = open_source(folder)
    assert src.cameras is not None
    tracker = create_silhouette_tracker(SilhouetteOptions(), src.cameras[:1], tree=tree)
    ious, writer, read = [], None, 0
    with src:
        for i, fs in enumerate(src):
            if i >= frames:
                break
            read += 1
            r = tracker.process(FrameSet(fs.frames[:1], fs.t, fs.index))
            sil, tpl = r.extras.get("silhouette"), r.extras.get("template")
            if sil is not None and tpl is not None:
                a, b = np.asarray(sil) > 0, np.asarray(tpl) > 0
                ious.append((a & b).sum() / max((a | b).sum(), 1))
            if overlay is not None and i % 2 == 0:
                img = draw_overlay(fs.frames[0].image, r, src.cameras[0])
                h, w = img.shape[:2]
                s = 360 / max(h, w)
                img = cv2.resize(img, (int(w * s) // 2 * 2, int(h * s) // 2 * 2))
                if writer is None:
                    writer = cv2.VideoWriter(str(overlay), cv2.VideoWriter.fourcc(*"mp4v"),
                                             src.fps / 2, img.shape[1::-1])
                writer.write(cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
    if writer is not None:
        writer.release()
    return (float(np.median(ious)) if ious else float("nan")), read


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--work", default="/tmp/bodyplay_silhouette_bench")
    p.add_argument("--seconds", type=float, default=5.0)
    p.add_argument("--quick", action="store_true", help="one clip of each kind, no color shirt")
    p.add_argument("--no-colorshirt", action="store_true")
    p.add_argument("--validation", action="store_true", help="report the validation clips")
    p.add_argument("--tune", action="store_true",
                   help="the nine tune clips only (TUNE: five clips, four of them also by "
                        "other actor bodies; no colour shirt): median / worst / mean of clip "
                        "medians")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="a silhouette option, as `bodyplay track --set` (repeatable)")
    p.add_argument("--real-frames", type=int, default=300)
    p.add_argument("--overlays", help="folder for the real-footage overlay videos")
    p.add_argument("--poses", help="write every capture's joints per frame to this .npz, "
                   "to check that a speed change left them identical")
    p.add_argument("--compare", help="a --poses .npz of another commit: print the largest "
                   "joint difference of every capture against it")
    args = p.parse_args(argv)
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    print(f"# silhouette tracker benchmark, {datetime.date.today()}, {machine()}")
    opts = options_with_overrides(SilhouetteOptions(), args.set)
    if args.set:
        print(f"options: {', '.join(args.set)}")
    t0 = time.perf_counter()
    tree = load_or_build_tree(opts.hierarchy, progress=False)
    path = tree_cache_path(opts.hierarchy)
    print(f"hierarchy: {len(tree.poses)} poses from {tree.frames} frames "
          f"({tree.dedup_deg:.1f}-degree rule), nodes {tree.level_sizes}, "
          f"{len(tree.bodies)} bodies, {tree.nbytes / 1e6:.1f} MB in memory, "
          f"{path.stat().st_size / 1e6:.1f} MB on disk, built in {tree.build_seconds:.0f} s, "
          f"loaded in {time.perf_counter() - t0:.1f} s")
    groups: dict[str, list[tuple[str, float, str]]] = {
        "built-from (CMU)": [(c, t, "m") for c, t in BUILT_FROM]}
    if BANDAI.is_dir():
        bandai = VALIDATION if args.validation else TEST
        groups["not built-from (Bandai)"] = [(c, 0.0, "m") for c in bandai]
    if args.tune:
        if not BANDAI.is_dir():
            raise SystemExit(f"the tune clips need the Bandai clips in {BANDAI}")
        groups = {"tune": list(TUNE)}
    if args.quick:
        groups = {k: v[:1] for k, v in groups.items()}
    all_ms: list[float] = []
    stages: dict[str, list[float]] = {}
    poses: dict[str, NDArray[np.float64]] = {}
    print("\n| clips | clip | MPJPE 17 joints median / mean (cm) | frames with joints | "
          "color shirt upper body (cm) | silhouette upper body (cm) |")
    print("|---|---|---|---|---|---|")
    for group, clips in groups.items():
        meds = []
        for clip, start, body in clips:
            folder = capture(work, clip, start, args.seconds, body=body)
            res = track(folder, silhouette_tracker(folder, tree, opts))
            poses[folder.name] = res["joints"]
            all_ms += list(res["ms"][1:])
            for k, v in res["stages"].items():
                stages.setdefault(k, []).extend(v)
            med = float(100 * np.nanmedian(res["frame_err"]))
            meds.append(med)
            cs = "-"
            if not (args.quick or args.no_colorshirt or args.tune):
                cres = track(folder, colorshirt_tracker(folder))
                cs = f"{100 * np.nanmean(cres['upper']):.1f}"
            up = 100 * np.nanmean(res["upper"]) if len(res["upper"]) else float("nan")
            name = clip if body == "m" else f"{clip} (actor {body})"
            print(f"| {group} | {name} | {med:.1f} / {100 * np.nanmean(res['frame_err']):.1f} "
                  f"| {100 * res['found']:.0f}% | {cs} | {up:.1f} |")
        print(f"| {group} | **median of clips / worst / mean** | {np.median(meds):.1f} / "
              f"{max(meds):.1f} / {np.mean(meds):.1f} | | | |")
    if BANDAI.is_dir() and not args.tune:
        occ_clip = TEST[0]
        folder = capture(work, occ_clip, 0.0, args.seconds, occlude="2:1")
        res = track(folder, silhouette_tracker(folder, tree, opts))
        poses[folder.name] = res["joints"]
        k = recovery(res, 2.0, 1.0)
        print(f"\nrecovery: {occ_clip} with --occlude 2:1: error within 1.2x its median "
              f"({100 * np.nanmedian(res['frame_err']) * 1.2:.1f} cm) {k} frames after the "
              "body reappears" if k >= 0 else "\nrecovery: not within the clip")
    ms = np.array(all_ms)
    share = {k: np.median(v) for k, v in stages.items()}
    total = sum(share.values())
    print(f"\nspeed: median {np.median(ms):.1f} ms per frame (90th percentile "
          f"{np.percentile(ms, 90):.1f}); stages (median ms, share): " + ", ".join(
              f"{k} {v:.1f} ({100 * v / total:.0f}%)" for k, v in share.items()))
    print(f"peak memory (this process, all trackers): "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")
    if args.poses:
        np.savez_compressed(args.poses, **poses)
    if args.compare:
        print("\nidentity against " + args.compare + ":\n"
              + compare_poses(poses, dict(np.load(args.compare))))
    p2s = DATA / "video" / "pose2sim_single"
    if p2s.is_dir() and args.real_frames > 0 and not args.tune:
        from bodyplay.capture.external import import_capture

        out = Path(args.overlays) if args.overlays else None
        if out:
            out.mkdir(parents=True, exist_ok=True)
        cap = import_capture(p2s, work / "pose2sim_cam01", cameras=["cam01"])
        iou, n = real_iou(tree, Path(cap), args.real_frames,
                          out / "silhouette_pose2sim.mp4" if out else None)
        print(f"real footage: pose2sim cam01, first {n} frames: median IoU of "
              f"the estimated pose's silhouette and the observed one {iou:.2f}")
        s2d = DATA / "video" / "sports2d"
        if s2d.is_dir():
            cap2 = import_capture(s2d, work / "sports2d", cameras=None)
            iou2, n2 = real_iou(tree, Path(cap2), args.real_frames,
                                out / "silhouette_sports2d.mp4" if out else None)
            print(f"real footage: sports2d, first {n2} frames: median IoU {iou2:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
