"""How much of the colour-shirt fit lies on the room: clutter the tracker takes for the shirt.

The validation set's captures (``colorshirt_validation.py``: the same cache, clips,
halves and settings) begin with one second of the empty room; under steady light its
median frame is the truth's background. This script tracks a capture and, on every
frame with a pose, takes the classified pixels the final fit used (the tracker's
``diagnostics["observed"]`` views) back to the camera image: a pixel whose colour
differs from the empty room by less than ``--threshold`` (summed RGB) lies on the
room, not on the player. Per clip it prints the MPJPE (the validation's upper-body
figure), the share of used pixels that lie on the room, and the median distance of
those pixels from the player's silhouette (full-resolution pixels). With the player
in view (``steady-2-view``) the share measures what the start without an empty room
costs; after the empty room (``steady-2-empty``) it is about 0.5%.

    nice .venv/bin/python benchmarks/colorshirt_clutter.py --half tune --setting steady-2-view
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

import colorshirt_validation as validation
from _machine import machine
from bodyplay.capture.frames import FrameSet
from bodyplay.capture.jsonl import read_pose_jsonl
from bodyplay.capture.sources import open_source
from bodyplay.trackers.colorshirt import ColorShirtOptions, create_colorshirt_tracker


def room_pixels(image: NDArray[np.uint8], room: NDArray[np.float32],
                uv: NDArray[np.float64], threshold: float) -> tuple[NDArray[np.bool_],
                                                                     NDArray[np.float32]]:
    """For image points ``uv`` (N, 2): which lie on the room (their colour within
    ``threshold``, summed RGB, of the empty ``room`` image), and each point's distance
    (pixels) from the nearest pixel unlike the room (0 on the player)."""
    player = np.abs(image.astype(np.float32) - room).sum(axis=2) > threshold
    h, w = player.shape
    u = np.clip(uv[:, 0].astype(int), 0, w - 1)
    v = np.clip(uv[:, 1].astype(int), 0, h - 1)
    distance = cv2.distanceTransform((~player).astype(np.uint8), cv2.DIST_L2, 3)
    return ~player[v, u], distance[v, u]


def track_clutter(folder: Path, setting: validation.Setting, options: ColorShirtOptions,
                  db: object, threshold: float) -> tuple[float, float, float, str]:
    """Track one capture: (MPJPE cm, share of used pixels on the room, their median
    distance from the player in pixels, the body chosen)."""
    truth = read_pose_jsonl(folder / "truth.jsonl")
    src = open_source(folder)
    assert src.cameras is not None
    tracker = create_colorshirt_tracker(options, src.cameras[: setting.cameras],
                                        database=db)  # type: ignore[arg-type]
    empty: list[list[NDArray[np.uint8]]] = [[] for _ in range(setting.cameras)]
    rooms: list[NDArray[np.float32]] | None = None
    errors: list[float] = []
    used = on_room = 0
    distances: list[NDArray[np.float32]] = []
    with src:
        for fs in src:
            frames = fs.frames[: setting.cameras]
            has = bool(np.isfinite(truth.joints[fs.index][0]).all())
            if not has:
                for i, f in enumerate(frames):
                    empty[i].append(f.image)
                if setting.start == "view":
                    continue
            r = tracker.process(FrameSet(frames, fs.t, fs.index))
            if not has or not r.found:
                continue
            if rooms is None:
                rooms = [np.median(np.stack(e), axis=0).astype(np.float32) for e in empty]
            errors.append(float(np.linalg.norm(
                r.joints[:11] - truth.joints[fs.index][:11], axis=1).mean()))
            for view, _counts, _centres in tracker.diagnostics.get("observed", []):
                ys, xs = np.nonzero(view.ids)
                uv = view.window.to_image(np.stack([xs + 0.5, ys + 0.5], axis=1))
                room, distance = room_pixels(frames[view.index].image, rooms[view.index],
                                             uv, threshold)
                used += len(xs)
                on_room += int(room.sum())
                distances.append(distance[room])
    far = np.concatenate(distances) if distances else np.zeros(0, np.float32)
    return (100 * float(np.mean(errors)) if errors else float("nan"),
            on_room / max(used, 1), float(np.median(far)) if len(far) else 0.0,
            tracker.body_name)


def main(argv: list[str] | None = None) -> int:
    """Track a half's clips in one steady setting and print the fit's share on the room."""
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    validation.add_capture_arguments(ap, "steady-2-view")
    ap.add_argument("--threshold", type=float, default=40.0,
                    help="summed RGB difference from the empty room that counts as the player")
    args = ap.parse_args(argv)
    if not (validation.MOCAP / "bandai_namco").exists():
        print("shared data not found (../shared/data/mocap); nothing to measure")
        return 1
    setting = {s.name: s for s in validation.SETTINGS}[args.setting]
    if setting.lighting != "steady":
        print(f"{args.setting}: only steady light has its empty room as the background truth")
        return 1
    options = validation.options_from(args)
    print(f"# colorshirt clutter, half {args.half}, {args.setting}, {machine()}, "
          f"options {' '.join(args.set) or 'default'}", flush=True)
    print("| clip | body | MPJPE (cm) | used pixels on the room | their median distance "
          "from the player (px) |\n|---|---|---|---|---|")
    shares = []
    for clip, folder, db in validation.half_captures(args, setting):
        mpjpe, share, distance, body = track_clutter(folder, setting, options, db,
                                                     args.threshold)
        shares.append(share)
        print(f"| {clip.name} | {body} | {mpjpe:.2f} | {100 * share:.1f}% | {distance:.1f} |",
              flush=True)
    if not shares:
        return 1
    print(f"used pixels on the room, median / worst clip: {100 * np.median(shares):.1f}% / "
          f"{100 * np.max(shares):.1f}%")
    return 0


if __name__ == "__main__":
    sys.exit(main())
