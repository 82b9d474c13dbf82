"""What the other cameras tell about the room: stereo background (beyond the paper).

The room's dominant surface maps one camera's image onto another's by a homography
``H`` (ORB features, RANSAC, estimated once). Where camera ``a``'s pixel ``p`` and
camera ``b``'s pixel at ``H p`` look alike, ``p`` shows that surface; a player in
front of it is seen by ``b`` elsewhere. This is Ivanov, Bobick and Liu's
disparity-verified background subtraction (IJCV 2000). A camera where much of the
player's last torso box looks alike (a player against the wall) gets no answer.
"""

from __future__ import annotations

import cv2
import numba
import numpy as np
from numpy.typing import NDArray

from bodyplay.trackers.colorshirt.plate import column_median

__all__ = ["CrossView"]

Box = tuple[int, int, int, int]


@numba.njit(cache=True, nogil=True)
def _alike(fa: NDArray[np.float32], warped: NDArray[np.float32], gain: NDArray[np.float32],
           threshold: np.float32, same: NDArray[np.bool_]) -> None:  # pragma: no cover
    """``same |= valid & (sum |fa - warped * gain| < threshold)``, ``valid`` where the
    warp reached (``warped`` >= 0)."""
    h, w = same.shape
    for y in range(h):
        for x in range(w):
            if warped[y, x, 0] < 0:
                continue
            d0 = abs(fa[y, x, 0] - warped[y, x, 0] * gain[0])
            d1 = abs(fa[y, x, 1] - warped[y, x, 1] * gain[1])
            d2 = abs(fa[y, x, 2] - warped[y, x, 2] * gain[2])
            if (d0 + d1) + d2 < threshold:
                same[y, x] = True


@numba.njit(cache=True, nogil=True)
def _samples(fa: NDArray[np.float32], warped: NDArray[np.float32], step: int
             ) -> tuple[NDArray[np.float32], NDArray[np.float32]]:  # pragma: no cover
    """Both images' colours at every ``step``-th row and column where the warp reached
    (``warped`` >= 0), in row order."""
    h, w = fa.shape[:2]
    n_max = ((h + step - 1) // step) * ((w + step - 1) // step)
    sa = np.empty((n_max, 3), np.float32)
    sb = np.empty((n_max, 3), np.float32)
    n = 0
    for y in range(0, h, step):
        for x in range(0, w, step):
            if warped[y, x, 0] >= 0:
                for k in range(3):
                    sa[n, k] = fa[y, x, k]
                    sb[n, k] = warped[y, x, k]
                n += 1
    return sa[:n], sb[:n]


class CrossView:
    """The room seen alike by two cameras (see the module docstring), per camera pair.

    ``threshold``, ``contrast_level``: as the plates' (smoothed images, one gain per
    channel between the cameras); ``min_inliers``: matches the homography must
    explain; ``retry``: frames between attempts without one; ``max_body_share``:
    share of the last torso box that may look alike before the camera gets no answer.
    """

    def __init__(self, cameras: int, threshold: float = 25.0, contrast_level: float = 330.0,
                 min_inliers: int = 40, retry: int = 15, max_body_share: float = 0.4) -> None:
        self.cameras = int(cameras)
        self.threshold = float(threshold)
        self.contrast_level = float(contrast_level)
        self.min_inliers = int(min_inliers)
        self.retry = int(retry)
        self.max_body_share = float(max_body_share)
        self._H: dict[tuple[int, int], NDArray[np.float64]] = {}
        """Per ordered pair ``(a, b)``: the homography from ``a``'s pixels to ``b``'s."""
        self._wait = 0

    def _estimate(self, smalls: list[NDArray[np.uint8]]) -> None:
        orb = cv2.ORB.create(nfeatures=1500)
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
                pa = np.array([ka[m.queryIdx].pt for m in good], np.float32)
                pb = np.array([kb[m.trainIdx].pt for m in good], np.float32)
                H, inl = cv2.findHomography(pa, pb, cv2.RANSAC, 2.0)
                if H is None or int(inl.sum()) < self.min_inliers:
                    continue
                self._H[(a, b)] = np.asarray(H, np.float64)
                self._H[(b, a)] = np.asarray(np.linalg.inv(H), np.float64)

    def room(self, smalls: list[NDArray[np.uint8]], torso: list[Box | None],
             downscale: int, needed: list[bool] | None = None
             ) -> list[NDArray[np.bool_] | None]:
        """Per camera, its pixels (of ``smalls``, the frames reduced by ``downscale``)
        that another camera shows as the same room; None where no camera can tell.
        ``torso``: each camera's last torso box (full-resolution px, or None);
        ``needed``: the cameras whose answer is wanted (default all).
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
        if needed is not None and not any(needed):
            return out
        blurred = [cv2.blur(s, (3, 3)).astype(np.float32) for s in smalls]
        for a, fa in enumerate(blurred):
            if needed is not None and not needed[a]:
                continue
            h, w = fa.shape[:2]
            same = np.zeros((h, w), bool)
            for b, fb in enumerate(blurred):
                H = self._H.get((a, b))
                if H is None:
                    continue
                warped = np.asarray(cv2.warpPerspective(
                    fb, H, (w, h), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                    borderMode=cv2.BORDER_CONSTANT, borderValue=(-1e4,) * 3), np.float32)
                sa, sb = _samples(fa, warped, 4)
                if len(sa) < 100:
                    continue
                gain = column_median(sa + 1.0) / column_median(sb + 1.0)
                level = float(column_median(sa).sum())
                th = self.threshold * min(1.0, max(0.3, level / self.contrast_level))
                _alike(fa, warped, gain.astype(np.float32), np.float32(th), same)
            same = cv2.morphologyEx(same.astype(np.uint8), cv2.MORPH_OPEN,
                                    np.ones((3, 3), np.uint8)) > 0
            box = torso[a]
            if box is not None:
                x0, y0, x1, y1 = (max(c // downscale, 0) for c in box)
                inside = same[y0:y1, x0:x1]
                if inside.size and float(inside.mean()) > self.max_body_share:
                    continue  # the player maps like the room here: the cue cannot tell
            out[a] = same
        return out
