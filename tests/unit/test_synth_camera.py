"""Specifications of the synthetic camera's rendering (needs EGL; skipped without it)."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.body.actor import load_actor
from bodyplay.capture.frames import FrameSet
from bodyplay.errors import ConfigError
from bodyplay.synth.camera import SyntheticCamera
from bodyplay.synth.options import make_synthetic_camera_options

pytestmark = pytest.mark.gl


@pytest.fixture(scope="module")
def actor():  # type: ignore[no-untyped-def]
    return load_actor("m")


def _wave(actor, n=6):  # type: ignore[no-untyped-def]
    sk = actor.skeleton
    poses = []
    for i in range(n):
        a = 1.2 * i / max(1, n - 1)
        poses.append(sk.pose(rotations={"l_shoulder": (0, 0, a), "r_elbow": (0, a, 0)}))
    return np.stack(poses)


def test_truth_joints_project_onto_the_actor_silhouette(synth_gl, actor):
    opts = make_synthetic_camera_options(size="320x240", background="plain", noise="none",
                                         cameras=2, seed=1)
    poses = _wave(actor)
    with SyntheticCamera(opts, frame_joints=actor.skeleton.joint_positions(poses),
                         actor=actor) as cam:
        shots = cam.render(poses[[0, 5]])
        for shot in shots:
            masks = cam.silhouettes(shot.pose)
            for cam_i, (frame, mask, calib) in enumerate(
                zip(shot.frames, masks, cam.cameras, strict=True)
            ):
                uv = np.round(calib.project(shot.joints)).astype(int)
                assert np.all(mask[uv[:, 1], uv[:, 0]]), f"camera {cam_i}"
                # the rendered picture differs from the plain wall exactly there too
                diff = np.abs(frame.image.astype(int) - 128).sum(axis=2)
                assert np.mean(diff[uv[:, 1], uv[:, 0]] > 12) > 0.9
                assert np.mean(diff[~mask] > 12) < 0.02
                assert mask.mean() > 0.02


def test_same_seed_gives_the_same_pixels_and_other_seed_other_noise(synth_gl, actor):
    poses = _wave(actor, 2)
    imgs = []
    for seed in (4, 4, 5):
        opts = make_synthetic_camera_options(size="160x120", noise="high", seed=seed,
                                             distance=3.0)
        with SyntheticCamera(opts, actor=actor) as cam:
            imgs.append(cam.render(poses)[1].frames[0].image)
    assert np.array_equal(imgs[0], imgs[1])
    assert not np.array_equal(imgs[0], imgs[2])


def test_live_capture_gives_truth_and_blurs_fast_motion(synth_gl, actor):
    sk = actor.skeleton
    opts = make_synthetic_camera_options(size="320x240", noise="none", background="plain",
                                         lighting="dim", max_subframes=6)
    with SyntheticCamera(opts, actor=actor) as cam:
        still = sk.pose(rotations={"l_shoulder": (0, 0, 0.0)})
        moved = sk.pose(rotations={"l_shoulder": (0, 0, 1.2)})
        a = cam.capture(0.0, still)
        b = cam.capture(1 / 30, moved)
        c = cam.capture(2 / 30, moved)
        assert isinstance(b.frames, FrameSet) and b.index == 1 and b.t == pytest.approx(1 / 30)
        assert np.allclose(b.joints, sk.joint_positions(moved))
        # blurred frame b has partly covered pixels (intermediate values) that c lacks
        def partial(img):  # type: ignore[no-untyped-def]
            wall = img[0, 0].astype(int)
            body = np.abs(img.astype(int) - wall).sum(axis=2)
            return int(((body > 20) & (body < 0.6 * body.max())).sum())
        assert partial(b.frames[0].image) > partial(c.frames[0].image) + 100
        assert a.frames[0].image.shape == (240, 320, 3)
        with pytest.raises(ConfigError, match="not after"):
            cam.capture(0.01, moved)


def test_camera_is_a_frame_source_when_given_a_clip(synth_gl, actor):
    from bodyplay.capture.sources import FrameSource
    from bodyplay.motion.clip import MotionClip

    clip = MotionClip(actor.skeleton, _wave(actor, 9), fps=30.0)
    opts = make_synthetic_camera_options(size="160x120", cameras=2)
    with SyntheticCamera(opts, clip, actor=actor) as cam:
        assert isinstance(cam, FrameSource)
        sets = list(cam)
    assert len(sets) == 9 and cam.fps == 30.0 and len(cam.cameras) == 2
    assert [s.index for s in sets] == list(range(9))
    assert sets[3].t == pytest.approx(0.1) and sets[3][1].camera == "cam1"
