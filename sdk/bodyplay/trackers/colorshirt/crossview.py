"""What the other cameras tell about the room: stereo background (beyond the paper).

With the player in view from the first frame nothing shows the room behind a player
who stands still, and clutter in shirt colours touching them is classified as the
shirt. A second camera sees that clutter too, from elsewhere: the room's dominant
surface (the back wall, or the floor) maps one camera's image onto the other's by
a homography ``H``, estimated once from features matched between the two views
(RANSAC keeps the surface most of the frame shows). Where a pixel ``p`` of camera
``a`` and camera ``b``'s pixel at ``H p`` show the same colour, ``p`` shows that
surface: a player standing in front of it is seen by ``b`` elsewhere (the ray
through ``p`` meets the player, not the wall, and ``b`` sees that point at another
place), so the colours differ. This is Ivanov, Bobick and Liu's disparity-verified
background subtraction (IJCV 2000) with the background's disparity a homography.

The player can look alike too: inside a large patch of one colour, camera ``b``
may show the same colour at ``H p`` because the player's own image there is
shifted by little (a player who stands about as far as the room's surface seems
to). So a pixel counts as the room only where the player, once a pose is known,
does *not* explain it as well: the homography of the plane through the last
pose's root, facing camera ``a``, maps ``p`` to where ``b`` would see the player's
surface, and a pixel of the last pose's silhouette alike there too is left to the
other masks (outside it, a patch of clutter in one colour looks alike under any
shift, and would always be left).
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.capture.camera import Camera

__all__ = ["CrossView"]


class CrossView:
    """The room seen alike by two cameras (see the module docstring), per camera pair.

    ``cameras``: the rig (undistorted images); ``downscale``: of the images given to
    :meth:`room`. ``threshold``: the summed R + G + B difference (of the smoothed
    images, after one gain per channel between the cameras) under which two pixels
    look alike, in a room at least as bright as ``contrast_level`` (dimmer rooms
    shrink it in proportion, down to 30%, as the plates do); ``min_inliers``:
    feature matches the room's homography must explain to be used; ``retry``:
    frames between attempts while none was found.
    """

    def __init__(self, cameras: tuple[Camera, ...], downscale: int, threshold: float = 25.0,
                 contrast_level: float = 330.0, min_inliers: int = 40, retry: int = 15) -> None:
        self.cameras = cameras
        self.threshold = float(threshold)
        self.contrast_level = float(contrast_level)
        self.min_inliers = int(min_inliers)
        self.retry = int(retry)
        s = 1.0 / downscale  # full-resolution pixels to reduced ones (pixel centres kept)
        self._scale = np.array([[s, 0.0, 0.5 * s - 0.5], [0.0, s, 0.5 * s - 0.5], [0, 0, 1]])
        self._H: dict[tuple[int, int], NDArray[np.float64]] = {}
        """Per ordered pair ``(a, b)``: the room's homography from ``a``'s pixels to ``b``'s."""
        self._wait = 0

    def _estimate(self, smalls: list[NDArray[np.uint8]]) -> None:
        orb = cv2.ORB_create(nfeatures=1500)
        feats = [orb.detectAndCompute(cv2.cvtColor(s, cv2.COLOR_RGB2GRAY), None)
                 for s in smalls]
        matcher = cv2.BFMatcher(cv2.NORM_HAMMING)
        for a in range(len(smalls)):
            for b in range(a + 1, len(smalls)):
                (ka, da), (kb, db) = feats[a], feats[b]
                if da is None or db is None or len(ka) < 8 or len(kb) < 8:
                    continue
                pairs = matcher.knnMatch(da, db, k=2)
                good = [m[0] for m in pairs if len(m) == 2 and m[0].distance < 0.75 * m[1].distance]
                if len(good) < self.min_inliers:
                    continue
                pa = np.float32([ka[m.queryIdx].pt for m in good])
                pb = np.float32([kb[m.trainIdx].pt for m in good])
                H, inl = cv2.findHomography(pa, pb, cv2.RANSAC, 2.0)
                if H is None or int(inl.sum()) < self.min_inliers:
                    continue
                self._H[(a, b)] = H
                self._H[(b, a)] = np.linalg.inv(H)

    def _player_homography(self, a: int, b: int, root: NDArray[np.float64]
                           ) -> NDArray[np.float64] | None:
        """Reduced pixels of camera ``a`` to ``b``'s through the plane at ``root``'s depth
        facing ``a`` (None: the root is not in front of ``a``)."""
        ca, cb = self.cameras[a], self.cameras[b]
        depth = float(ca.world_to_camera(root)[2])
        if depth <= 0.3:
            return None
        R = cb.R @ ca.R.T
        t = cb.t - R @ ca.t
        n = np.array([0.0, 0.0, 1.0])
        full = cb.K @ (R + np.outer(t, n) / depth) @ np.linalg.inv(ca.K)
        return np.asarray(self._scale @ full @ np.linalg.inv(self._scale), np.float64)

    @staticmethod
    def _alike(fa: NDArray[np.float32], fb: NDArray[np.float32], H: NDArray[np.float64],
               threshold: float, contrast_level: float) -> NDArray[np.bool_] | None:
        """Where ``fa`` looks like ``fb`` seen through ``H`` (``a``'s pixels to ``b``'s),
        after one gain per channel; None when they share too little of the frame."""
        h, w = fa.shape[:2]
        warped = cv2.warpPerspective(fb, H, (w, h), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                                     borderMode=cv2.BORDER_CONSTANT, borderValue=(-1e4,) * 3)
        valid = warped[..., 0] >= 0
        sa, sb = fa[::4, ::4][valid[::4, ::4]], warped[::4, ::4][valid[::4, ::4]]
        if len(sa) < 100:
            return None
        gain = np.median(sa + 1.0, axis=0) / np.median(sb + 1.0, axis=0)
        level = float(np.median(sa, axis=0).sum())
        th = threshold * min(1.0, max(0.3, level / contrast_level))
        diff = cv2.transform(cv2.absdiff(fa, warped * gain.astype(np.float32)),
                             np.ones((1, 3), np.float32))
        return np.asarray(valid & (diff < th), bool)

    def room(self, smalls: list[NDArray[np.uint8]], root: NDArray[np.float64] | None,
             bodies: list[NDArray[np.bool_] | None]) -> list[NDArray[np.bool_] | None]:
        """Per camera, its pixels (reduced images ``smalls`` of every camera) that
        another camera shows as the same room and, with ``root`` (the last pose's,
        world metres), not as the player's surface within ``bodies`` (each camera's
        silhouette of that pose, reduced; None: anywhere); None where no camera can
        tell.
        """
        out: list[NDArray[np.bool_] | None] = [None] * len(smalls)
        if len(smalls) < 2:
            return out
        if not self._H:
            if self._wait > 0:
                self._wait -= 1
                return out
            self._estimate(smalls)
            if not self._H:
                self._wait = self.retry
                return out
        blurred = [cv2.blur(s, (3, 3)).astype(np.float32) for s in smalls]
        for a, fa in enumerate(blurred):
            same: NDArray[np.bool_] | None = None
            for b, fb in enumerate(blurred):
                H = self._H.get((a, b))
                if H is None:
                    continue
                alike = self._alike(fa, fb, H, self.threshold, self.contrast_level)
                if alike is None:
                    continue
                P = None if root is None else self._player_homography(a, b, root)
                if P is not None:
                    player = self._alike(fa, fb, P, self.threshold, self.contrast_level)
                    if player is not None:
                        if bodies[a] is not None:
                            player &= cv2.dilate(bodies[a].astype(np.uint8),  # type: ignore[union-attr]
                                                 np.ones((5, 5), np.uint8)) > 0
                        alike &= ~player
                same = alike if same is None else same | alike
            if same is not None:
                out[a] = cv2.morphologyEx(same.astype(np.uint8), cv2.MORPH_OPEN,
                                          np.ones((3, 3), np.uint8)) > 0
        return out
