"""HUD pieces games share: the camera's picture with the tracked skeleton on it."""

from __future__ import annotations

import cv2
import numpy as np

from bodyplay.app.game import GameContext
from bodyplay.app.scene import Scene
from bodyplay.body.joints import BONES, JOINT_INDEX

__all__ = ["camera_inset"]


def camera_inset(ctx: GameContext, scene: Scene, width: int = 160, *,
                 pos: tuple[int, int] | None = None, label: str = "camera + tracker") -> None:
    """Show the first camera's picture (what the tracker sees) with the tracked
    skeleton drawn on it, ``width`` pixels wide at ``pos`` (default: top right).
    Nothing is drawn for pose-level input (no picture)."""
    fs = ctx.frame
    cams = ctx.session.cameras
    if fs is None or not cams or width < 16:
        return
    img = fs.frames[0].image
    h0, w0 = img.shape[:2]
    height = int(round(width * h0 / w0))
    small = cv2.resize(img, (width, height), interpolation=cv2.INTER_AREA)
    pose = ctx.pose
    if pose is not None:
        uv = cams[0].project(pose.joints) * (width / w0)
        for a, b in BONES:
            pa, pb = uv[JOINT_INDEX[a]], uv[JOINT_INDEX[b]]
            if np.all(np.isfinite(pa)) and np.all(np.isfinite(pb)):
                cv2.line(small, (int(pa[0]), int(pa[1])), (int(pb[0]), int(pb[1])),
                         (255, 200, 0), 1, cv2.LINE_AA)
    x, y = pos if pos is not None else (scene.width - width - 10, 10)
    scene.inset(small, (x, y, width, height))
    if label:
        scene.text(label, (x, y + height + 18), 0.5)
