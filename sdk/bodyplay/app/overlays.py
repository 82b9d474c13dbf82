"""HUD pieces every game may show: the camera picture with the tracked skeleton."""

from __future__ import annotations

import cv2
import numpy as np

from bodyplay.app.game import GameContext
from bodyplay.app.scene import Scene
from bodyplay.body.joints import BONES, JOINT_INDEX

__all__ = ["camera_inset"]


def camera_inset(ctx: GameContext, scene: Scene, width: int = 160,
                 label: str | None = "camera + tracker") -> None:
    """Show the first camera's latest picture, top right, with the tracked skeleton
    drawn over it (nothing for pose-level input, which has no pictures)."""
    fs = ctx.frame
    cams = ctx.session.cameras
    if fs is None or not cams:
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
                         (255, 220, 0), 2, cv2.LINE_AA)
    scene.inset(small, (scene.width - width - 10, 10, width, height))
    if label:
        scene.text(label, (scene.width - width - 10, height + 30), 0.5)
