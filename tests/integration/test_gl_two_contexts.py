"""Two standalone GL contexts in one thread: the synthetic camera's and a game's scene."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.mark.gl
def test_synthetic_camera_and_scene_renderer_take_turns_in_one_thread(synth_gl):
    from bodyplay.app import Scene, SceneRenderer
    from bodyplay.synth import SyntheticCamera

    with SyntheticCamera() as cam, SceneRenderer(160, 120) as view:
        q = cam.skeleton.rest_pose()
        pictures = []
        for i in range(3):
            shot = cam.capture(i / 30.0, q)
            scene = Scene(width=160, height=120)
            scene.look((0, 1.5, 4), (0, 1, 0))
            scene.floor()
            scene.sphere((0, 1, 0), 0.5, (1, 0, 0))
            pictures.append(view.render(scene))
            assert shot.frames.frames[0].image.std() > 5
        assert np.array_equal(pictures[0], pictures[2])
        assert (pictures[0][60, 80] == pictures[0].max(axis=(0, 1))).any()
