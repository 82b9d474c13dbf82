"""The silhouette tracker on real footage: the four cameras of Pose2Sim's recording.

Each camera of ../shared/data/video/pose2sim_single (1080x1920 portrait, 60 fps,
100 frames; the person on a treadmill from the first frame, a second person at
the side) is tracked on its own, with the tracker's defaults (or ``--set``), from
its first frame. Per camera:

* **IoU with the observed silhouette**: the chosen template mapped back into the
  image against the tracker's own observed silhouette (the foreground components
  it follows) -- what the tracker saw, ghosts of the first frame and all;
* **IoU of the reported pose**: the pose vector the tracker reports (the MAP leaf's,
  the arms refined, the depth cues applied: what a game receives; the joints are the
  blend of the best leaves, smoothed), the mesh of the body shape it reports
  (``extras["shape"]``: the chosen preset, its girth measured) rendered by the
  camera at the observed silhouette's size, against the
  observed silhouette and against the reference below -- the issue's "silhouette of
  the estimated pose", where the two columns before are the chosen template's;
* **IoU with a reference silhouette**: against MediaPipe's person segmentation of
  the same frame (``benchmarks/data/pose2sim_mediapipe.npz``, made by
  ``benchmarks/make_pose2sim_reference.py``; it knows nothing of this tracker and
  holds the main person only, without the treadmill, the second person or the
  first frame's ghost), undistorted like the tracker's image;
* **3-D proxy**: MediaPipe's 2-D landmarks of all four cameras triangulated with
  the calibration give a multi-view 3-D reference of 15 of the 17 joints
  (hips, knees, ankles, shoulders, elbows, wrists, pelvis, neck, head from the
  ears); the tracker's joints from ONE camera against it (median over frames of
  the mean error). It is a proxy, not the hidden Qualisys reference: MediaPipe's
  landmarks are not joint centres (its reprojection error is printed); beside it,
  where it comes from: the error with both skeletons moved to their hips'
  midpoint (the pose without its placement) and the heading error, the angle
  between the two hip lines seen from above (near 180 degrees: a player seen from
  behind reported as seen from the front, mirrored; the tree holds poses turned
  up to 80 degrees from the camera);
* frames with a pose, median ms per frame (wall) and CPU ms per frame.

Tune on cam01-cam02, report cam03-cam04 beside them. ``--away cam03,cam04``
tracks those cameras (which film the player from behind) with ``facing="away"``
(the front track reported reflected; docs/silhouette.md, step 9).

    .venv/bin/python benchmarks/silhouette_real.py [--cams cam01,cam02] [--set NAME=VALUE]
                                                   [--away cam03,cam04]
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import itertools
import sys
import time
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.mesh import body_mesh
from bodyplay.body.shapes import BodyShape
from bodyplay.body.skeleton import Skeleton
from bodyplay.body.skinning import SkinnedMesh
from bodyplay.capture.camera import Camera
from bodyplay.capture.external import import_capture
from bodyplay.capture.frames import FrameSet
from bodyplay.capture.sources import open_source
from bodyplay.commands.track import _silhouette_options
from bodyplay.render.idmap import silhouettes
from bodyplay.trackers.silhouette import (
    SilhouetteOptions,
    create_silhouette_tracker,
    load_or_build_tree,
)

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine  # noqa: E402

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
P2S = DATA / "video" / "pose2sim_single"
REFERENCE = Path(__file__).resolve().parent / "data" / "pose2sim_mediapipe.npz"
CAMS = ("cam01", "cam02", "cam03", "cam04")

# MediaPipe Pose landmark indices -> bodyplay joints (pelvis, neck: midpoints; head: ears)
_MP = {"l_shoulder": 11, "r_shoulder": 12, "l_elbow": 13, "r_elbow": 14, "l_wrist": 15,
       "r_wrist": 16, "l_hip": 23, "r_hip": 24, "l_knee": 25, "r_knee": 26, "l_ankle": 27,
       "r_ankle": 28}


def reference_masks(ref: Any, cam: str) -> NDArray[np.bool_]:
    """(frames, H/4, W/4) MediaPipe person masks of one camera."""
    n, h, w = (int(v) for v in ref[f"{cam}_shape"])
    return np.unpackbits(ref[f"{cam}_mask"], axis=-1)[..., :w].astype(bool).reshape(n, h, w)


def _dlt(P: list[NDArray[np.float64]], uv: list[NDArray[np.float64]]) -> NDArray[np.float64]:
    rows = []
    for Pc, (u, v) in zip(P, uv, strict=True):
        rows += [u * Pc[2] - Pc[0], v * Pc[2] - Pc[1]]
    _, _, vt = np.linalg.svd(np.array(rows))
    return np.asarray(vt[-1, :3] / vt[-1, 3])


def triangulate(cameras: dict[str, Camera], landmarks: dict[str, NDArray[np.float32]],
                min_visibility: float = 0.5, max_px: float = 25.0
                ) -> tuple[NDArray[np.float64], float]:
    """(frames, 17, 3) multi-view reference and the median reprojection error (px).

    Per landmark and frame: the views that see it (MediaPipe visibility at least
    ``min_visibility``) are triangulated (DLT on undistorted points); the largest
    subset of at least two views whose reprojection errors are all under
    ``max_px`` is kept (MediaPipe swaps left and right now and then, mostly from
    behind); NaN when there is none.
    """
    names = list(cameras)
    n = min(len(landmarks[c]) for c in names)
    P = {c: cameras[c].K @ np.hstack([cameras[c].R, cameras[c].t.reshape(3, 1)]) for c in names}
    pts = np.full((n, 33, 3), np.nan)
    errs: list[float] = []
    for f in range(n):
        for k in range(33):
            seen = {}
            for c in names:
                u, v, vis = landmarks[c][f, k]
                if np.isfinite(u) and vis >= min_visibility:
                    cam = cameras[c]
                    seen[c] = cv2.undistortPoints(np.array([[[u, v]]], np.float64), cam.K,
                                                  cam.dist, P=cam.K).reshape(2)
            for size in range(len(seen), 1, -1):
                best = None
                for sub in itertools.combinations(seen, size):
                    X = _dlt([P[c] for c in sub], [seen[c] for c in sub])
                    e = [float(np.linalg.norm(cameras[c].project(X[None], distort=False)[0]
                                              - seen[c])) for c in sub]
                    if max(e) < max_px and (best is None or max(e) < best[0]):
                        best = (max(e), X, e)
                if best is not None:
                    pts[f, k] = best[1]
                    errs += best[2]
                    break
    J = np.full((n, 17, 3), np.nan)
    for name, k in _MP.items():
        J[:, JOINT_INDEX[name]] = pts[:, k]
    J[:, JOINT_INDEX["pelvis"]] = 0.5 * (pts[:, 23] + pts[:, 24])
    J[:, JOINT_INDEX["neck"]] = 0.5 * (pts[:, 11] + pts[:, 12])
    J[:, JOINT_INDEX["head"]] = 0.5 * (pts[:, 7] + pts[:, 8])
    return J, float(np.median(errs)) if errs else float("nan")


def iou(a: NDArray[np.bool_], b: NDArray[np.bool_]) -> float:
    """Intersection over union of two masks (NaN when both are empty)."""
    u = (a | b).sum()
    return float((a & b).sum() / u) if u else float("nan")


class Overlay:
    """A short, small overlay video (every ``step``-th frame, long side ``size``
    pixels, written at the source rate / ``step``) and a PNG still of one frame."""

    def __init__(self, path: Path, fps: float, step: int = 2, size: int = 360,
                 still: int | None = None) -> None:
        self.path, self.fps, self.step, self.size, self.still = path, fps, step, size, still
        self.writer: Any = None

    def add(self, i: int, image: NDArray[np.uint8], result: Any, camera: Camera) -> None:
        """Draw and write frame ``i`` (when it is one of the kept frames)."""
        from bodyplay.commands.track import draw_overlay

        if i % self.step and i != self.still:
            return
        img = draw_overlay(image, result, camera)
        if i == self.still:
            h, w = img.shape[:2]
            s = 480 / max(h, w)
            cv2.imwrite(str(self.path.with_suffix(".png")), cv2.cvtColor(
                cv2.resize(img, (int(w * s), int(h * s)), interpolation=cv2.INTER_AREA),
                cv2.COLOR_RGB2BGR))
        if i % self.step:
            return
        h, w = img.shape[:2]
        s = self.size / max(h, w)
        img = cv2.resize(img, (int(w * s) // 2 * 2, int(h * s) // 2 * 2),
                         interpolation=cv2.INTER_AREA)
        if self.writer is None:
            self.writer = cv2.VideoWriter(str(self.path), cv2.VideoWriter.fourcc(*"mp4v"),
                                          self.fps / self.step, img.shape[1::-1])
        self.writer.write(cv2.cvtColor(img, cv2.COLOR_RGB2BGR))

    def close(self) -> None:
        """Finish the video."""
        if self.writer is not None:
            self.writer.release()


class PoseSilhouette:
    """The silhouette of a reported pose: the tracker's body mesh of the body shape
    it reports (``extras["shape"]``: the preset it chose, its girth measured; the
    preset itself when only ``extras["body"]`` is given), in that pose, rendered by
    the (undistorted) camera at a mask's size."""

    def __init__(self, camera: Camera) -> None:
        self.camera = camera
        self._bodies: dict[str | BodyShape, tuple[Skeleton, SkinnedMesh]] = {}

    def __call__(self, body: str | BodyShape, pose: NDArray[np.float64],
                 shape: tuple[int, int]) -> NDArray[np.bool_]:
        if body not in self._bodies:
            sk = Skeleton.from_shape(body)
            self._bodies[body] = (sk, body_mesh(sk))
        sk, mesh = self._bodies[body]
        verts = mesh.pose(sk, np.asarray(pose, np.float64)[None])
        return silhouettes(verts, mesh.faces, self.camera.with_size(shape[1], shape[0]))[0]


def run_camera(cap: Path, tree: Any, options: SilhouetteOptions, ref_masks: Any,
               truth: NDArray[np.float64] | None, overlay: Overlay | None = None
               ) -> dict[str, Any]:
    """Track one camera; per-frame IoUs, joint errors, ms and CPU ms."""
    src = open_source(cap)
    assert src.cameras is not None
    cam = src.cameras[0]
    maps = cam.undistort_maps()
    tracker = create_silhouette_tracker(options, src.cameras[:1], tree=tree)
    posed = PoseSilhouette(cam)
    obs, ref, err, ms, cpu, found, n = [], [], [], [], [], 0, 0
    pose_obs: list[float] = []
    pose_ref: list[float] = []
    aligned, heading = [], []
    with src:
        for i, fs in enumerate(src):
            n += 1
            c0 = time.process_time()
            r = tracker.process(FrameSet(fs.frames[:1], fs.t, fs.index))
            cpu.append(1000 * (time.process_time() - c0))
            ms.append(r.ms)
            found += bool(r.found)
            if overlay is not None:
                overlay.add(i, fs.frames[0].image, r, cam)
            sil, tpl = r.extras.get("silhouette"), r.extras.get("template")
            if sil is None:
                continue
            shape = np.asarray(sil).shape
            if tpl is not None:
                obs.append(iou(np.asarray(sil) > 0, np.asarray(tpl) > 0))
            body = r.extras.get("shape") or r.extras.get("body")
            shown = (posed(body, r.pose, shape) if r.found and r.pose is not None
                     and isinstance(body, str | BodyShape) else None)
            if shown is not None:
                pose_obs.append(iou(np.asarray(sil) > 0, shown))
            if ref_masks is not None and i < len(ref_masks):
                m = cv2.resize(ref_masks[i].astype(np.uint8) * 255, (cam.width, cam.height),
                               interpolation=cv2.INTER_LINEAR)
                if maps is not None:
                    m = cv2.remap(m, maps[0], maps[1], cv2.INTER_LINEAR)
                m = cv2.resize(m, shape[::-1], interpolation=cv2.INTER_AREA) >= 128
                t = np.asarray(tpl) > 0 if tpl is not None else np.zeros(shape, bool)
                ref.append(iou(m, t))
                if shown is not None:
                    pose_ref.append(iou(m, shown))
            if truth is not None and r.found and i < len(truth):
                e = np.linalg.norm(r.joints - truth[i], axis=1)
                if np.isfinite(e).sum() >= 10:
                    err.append(float(np.nanmean(e)))
                    a, h = _aligned_and_heading(r.joints, truth[i])
                    aligned.append(a)
                    heading.append(h)
    if overlay is not None:
        overlay.close()
    return {"obs": np.array(obs), "ref": np.array(ref), "pose_obs": np.array(pose_obs),
            "pose_ref": np.array(pose_ref), "err": np.array(err), "ms": np.array(ms),
            "cpu": np.array(cpu), "found": found, "frames": n, "body": tracker.body_name,
            "aligned": np.array(aligned), "heading": np.array(heading)}


_HIPS = (JOINT_INDEX["l_hip"], JOINT_INDEX["r_hip"])


def _aligned_and_heading(joints: NDArray[np.float64], truth: NDArray[np.float64]
                         ) -> tuple[float, float]:
    """Where a frame's proxy error comes from: the mean joint error with both
    skeletons moved to their hips' midpoint (the pose without the placement), and
    the angle (degrees, 0..180) between their left-to-right hip directions seen
    from above (the heading; near 180: the back reported as the front, mirrored).
    NaN when the proxy has no hips this frame."""
    th = truth[list(_HIPS)]
    if not np.isfinite(th).all():
        return float("nan"), float("nan")
    jh = joints[list(_HIPS)]
    e = np.linalg.norm((joints - jh.mean(axis=0)) - (truth - th.mean(axis=0)), axis=1)
    a, b = (jh[0] - jh[1])[[0, 2]], (th[0] - th[1])[[0, 2]]
    ang = np.degrees(np.arctan2(a[0] * b[1] - a[1] * b[0], float(a @ b)))
    return float(np.nanmean(e)), float(abs(ang))


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--work", default="/tmp/bodyplay_silhouette_real")
    p.add_argument("--cams", default=",".join(CAMS))
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="a SilhouetteOptions field, as for `bodyplay track --set`")
    p.add_argument("--away", default="", help="cameras that film the player from behind, "
                   "tracked with facing=away (comma-separated)")
    p.add_argument("--overlays", help="folder for the overlay videos and stills (cam01 and "
                   "the Sports2D clip): silhouette_pose2sim.mp4/.png, silhouette_sports2d.mp4/.png")
    args = p.parse_args(argv)
    out = Path(args.overlays) if args.overlays else None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
    if not P2S.is_dir():
        print(f"no Pose2Sim recording at {P2S}")
        return 1
    options = _silhouette_options(args.set) if args.set else SilhouetteOptions()
    away = {c for c in args.away.split(",") if c}
    if away - set(CAMS):
        p.error(f"--away: unknown cameras {sorted(away - set(CAMS))}, known: {', '.join(CAMS)}")
    print(f"# silhouette tracker on Pose2Sim, {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M}"
          f" UTC, {machine()}; options: {' '.join(args.set) or 'defaults'}"
          + (f"; facing=away on {', '.join(sorted(away))}" if away else ""))
    tree = load_or_build_tree(options.hierarchy, progress=False)
    work = Path(args.work)
    caps = {c: Path(import_capture(P2S, work / c, cameras=[c])) for c in CAMS}
    ref = np.load(REFERENCE) if REFERENCE.exists() else None
    truth, rms = None, float("nan")
    if ref is not None:
        cams = {}
        for c, cap in caps.items():
            src = open_source(cap)
            assert src.cameras is not None
            cams[c] = src.cameras[0]
        truth, rms = triangulate(cams, {c: ref[f"{c}_landmarks"] for c in CAMS})
        share = 100 * np.isfinite(truth[..., 0]).mean()
        print(f"3-D proxy: MediaPipe landmarks of {len(CAMS)} cameras triangulated, "
              f"median reprojection {rms:.1f} px, {share:.0f}% of joint-frames")
    print("\n| camera | frames with a pose | IoU observed median / worst | IoU reference "
          "median / worst | reported pose's IoU observed / reference, median | "
          "3-D proxy error median / worst (cm) | hips aligned (cm) | "
          "heading error (deg), frames over 90 | ms/frame wall / CPU | body |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for c in args.cams.split(","):
        masks = reference_masks(ref, c) if ref is not None else None
        ov = (Overlay(out / "silhouette_pose2sim.mp4", 60.0, still=60)
              if out is not None and c == "cam01" else None)
        opts = dataclasses.replace(options, facing="away") if c in away else options
        res = run_camera(caps[c], tree, opts, masks, truth, ov)

        def mw(a: NDArray[np.float64], scale: float = 1.0, worst: str = "min") -> str:
            a = a[np.isfinite(a)]
            if not len(a):
                return "-"
            w = a.min() if worst == "min" else a.max()
            return f"{scale * np.median(a):.2f} / {scale * w:.2f}"

        label = f"{c} (away)" if c in away else c
        med = {k: np.nanmedian(res[k]) if len(res[k]) else float("nan")
               for k in ("pose_obs", "pose_ref")}
        print(f"| {label} | {res['found']}/{res['frames']} | {mw(res['obs'])} | {mw(res['ref'])} | "
              f"{med['pose_obs']:.2f} / {med['pose_ref']:.2f} | "
              f"{mw(res['err'], 100, 'max')} | {100 * np.nanmedian(res['aligned']):.1f} | "
              f"{np.nanmedian(res['heading']):.0f}, "
              f"{100 * np.mean(res['heading'][np.isfinite(res['heading'])] > 90):.0f}% | "
              f"{np.median(res['ms'][1:]):.0f} / "
              f"{np.median(res['cpu'][1:]):.0f} | {res['body']} |", flush=True)
    s2d = DATA / "video" / "sports2d"
    if s2d.is_dir():
        cap = Path(import_capture(s2d, work / "sports2d", cameras=None))
        ov = Overlay(out / "silhouette_sports2d.mp4", 30.0, still=150) if out else None
        res = run_camera(cap, tree, options, None, None, ov)
        print(f"\nSports2D (1768x994, 230 frames, walker about 10 m away): a pose in "
              f"{res['found']}/{res['frames']} frames, IoU with the observed silhouette "
              f"median {np.nanmedian(res['obs']) if len(res['obs']) else float('nan'):.2f} "
              f"(the reported pose's "
              f"{np.nanmedian(res['pose_obs']) if len(res['pose_obs']) else float('nan'):.2f}), "
              f"{np.median(res['ms'][1:]):.0f} ms / {np.median(res['cpu'][1:]):.0f} ms CPU "
              f"per frame, body {res['body']}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
