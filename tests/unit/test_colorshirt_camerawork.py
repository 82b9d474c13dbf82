"""Specifications of the color-shirt tracker's per-camera image steps (camerawork.py)."""

from __future__ import annotations

import cv2
import numpy as np
from colorshirt_paint import clutter, webcam_rig

from bodyplay.body import Skeleton
from bodyplay.trackers.colorshirt import ColorShirtOptions
from bodyplay.trackers.colorshirt.camerawork import CameraWork
from bodyplay.trackers.colorshirt.colors import default_color_model
from bodyplay.trackers.colorshirt.prediction import PoseRenderer

SK = Skeleton()


class _NoDatabase:
    """CameraWork only queries the database in :meth:`CameraWork.view`."""


def _work(ncam: int = 2) -> CameraWork:
    return CameraWork(ColorShirtOptions(), webcam_rig(ncam), _NoDatabase(),  # type: ignore[arg-type]
                      default_color_model())


def test_remember_shirt_keeps_only_the_torso_box_foreground_not_the_arms() -> None:
    """The box kept as foreground while tracking is the torso's: a still torso fades
    from the background model, but room clutter beside an arm must not be kept (a
    wrong first fit of an arm into a poster kept the poster)."""
    work = _work()
    states = work.new_states()
    renderer = PoseRenderer(SK)
    q = SK.rest_pose()  # the T-pose: both arms straight out to the sides
    work.remember_shirt(states, renderer, q, t=0.0)
    for st in states:
        assert st.last_box is not None and st.torso_box is not None
        tx0, ty0, tx1, ty1 = st.torso_box
        bx0, by0, bx1, by1 = st.last_box
        assert bx0 <= tx0 < tx1 <= bx1 and by0 <= ty0 < ty1 <= by1
        # the T-pose's arms stretch the shirt's box sideways; the torso's stays narrow
        assert (tx1 - tx0) < 0.5 * (bx1 - bx0)


def test_the_background_model_masks_what_never_moved_from_the_second_frame() -> None:
    """From the second frame on, the motion mask is used: a square that moved is
    foreground, the still room (and clutter in it) is not."""
    work = _work(1)
    st = work.new_states()[0]
    rng = np.random.default_rng(0)
    room = clutter(480, 640, rng)
    first = room.copy()
    first[200:260, 100:160] = (230, 40, 40)
    second = room.copy()
    second[200:260, 300:360] = (230, 40, 40)
    assert st.background.apply(first) is None  # the first frame only teaches
    mask = st.background.apply(second)
    assert mask is not None
    assert mask[230, 330] and not mask[50, 600]


def test_the_floor_plate_learns_every_frame_before_the_first_pose_even_where_clutter_is_found(
) -> None:
    """An empty room full of colour: the histogram search finds shirt-like regions
    that the colour test then rejects. The floor cue's plate must still learn those
    frames (it learned only frames where nothing was found, and in such a room it
    was never ready: no floor or head cue after an empty-room start)."""
    work = _work(1)
    st = work.new_states()[0]
    room = clutter(480, 640, np.random.default_rng(3))
    rng = np.random.default_rng(1)
    for i in range(4):  # a poster of 20 muted colours: shirt-like, but not the shirt's
        for j in range(5):
            hsv = np.uint8([[[rng.uniform(0, 180), 90, rng.uniform(120, 230)]]])
            room[150 + 30 * j: 180 + 30 * j, 260 + 30 * i: 290 + 30 * i] = cv2.cvtColor(
                hsv, cv2.COLOR_HSV2RGB)[0, 0]
    located = 0
    for k in range(10):
        work.prepare([st], [room])
        assert work.views(0, st, k / 30.0, False, 1) == []
        located += st.located
    assert located > 0  # the search did take clutter for a shirt
    assert st.floor.plate.ready
