"""Specifications of the virtual player sources (pose level, and filmed: needs EGL)."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.errors import CaptureError, ConfigError
from bodyplay.runtime.clock import FixedClock
from bodyplay.runtime.session import create_session
from bodyplay.testing import Timeline
from bodyplay.virtual import (
    PoseController,
    ReachController,
    TimelineController,
    VirtualPlayerSource,
    VirtualPoseSource,
)


@pytest.fixture(scope="module")
def keeper_factory():  # type: ignore[no-untyped-def]
    from bodyplay.body.actor import load_actor
    from bodyplay.virtual import IdleMotion

    sk = load_actor("m").skeleton
    idle = IdleMotion(sk)
    return lambda: ReachController(sk, idle=idle)


def test_timeline_controller_poses_like_its_timeline() -> None:
    tl = Timeline().hold("idle", 0.5).gesture("raise_right_hand")
    ctrl = TimelineController(tl)
    assert isinstance(ctrl, PoseController)
    np.testing.assert_array_equal(ctrl.pose_at(1.0), tl.pose_at(1.0))
    assert ctrl.duration == tl.duration
    assert ctrl.frame_joints().shape[1:] == (17, 3)
    with pytest.raises(ConfigError, match="Timeline"):
        TimelineController("raise_right_hand")  # type: ignore[arg-type]


def test_pose_source_feeds_a_session_in_closed_loop(keeper_factory) -> None:
    ctrl = keeper_factory()
    src = VirtualPoseSource(ctrl, fps=30, seconds=1.5)
    assert len(src) == 46
    session = create_session(source=src, clock=FixedClock(1 / 30))
    hand = []
    while (ev := session.step()) is not None:
        if ev.frame == 6:  # the game sees a ball between frames and tells the keeper
            ctrl.set_target(1.0, (0.5, 1.3, 0.3))
        assert src.truth is not None
        np.testing.assert_array_equal(ev.joints, src.truth)
        hand.append(ev.joints[7])
    assert session.frames == 46
    assert np.linalg.norm(hand[30] - (0.5, 1.3, 0.3)) < 0.1  # the wrist, by the palm
    assert np.linalg.norm(hand[5] - hand[0]) < 0.05


def test_pose_source_reports_legs_lost_when_upper_body_only(keeper_factory) -> None:
    src = VirtualPoseSource(keeper_factory(), seconds=0.1, upper_body_only=True, noise=0.01)
    s = next(iter(src))
    assert s.state[11:] == ("lost",) * 6 and s.state[0] == "tracked"
    assert s.pose is not None and src.truth is not None
    assert 0 < np.linalg.norm(s.joints[:11] - src.truth[:11], axis=1).max() < 0.06


def test_sources_reject_what_is_not_a_controller() -> None:
    with pytest.raises(ConfigError, match="PoseController"):
        VirtualPoseSource(object())  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="PoseController"):
        VirtualPlayerSource(object())  # type: ignore[arg-type]


@pytest.mark.gl
def test_player_source_films_the_controller_with_calibrated_cameras(synth_gl,
                                                                     keeper_factory) -> None:
    ctrl = keeper_factory()
    with VirtualPlayerSource(ctrl, cameras=2, seconds=0.2, size=(320, 240)) as src:
        assert src.cameras is not None and len(src.cameras) == 2
        sets = []
        for fs in src:
            assert src.truth is not None
            np.testing.assert_allclose(src.truth, ctrl.joints_at(fs.t), atol=1e-9)
            # the true wrists project inside the picture of both cameras
            for cam in src.cameras:
                uv = cam.project(src.truth[[7, 10]])
                assert np.all((uv >= 0) & (uv < (320, 240)))
            sets.append(fs)
        assert [fs.index for fs in sets] == list(range(7))
        assert sets[0].frames[0].image.shape == (240, 320, 3)
        with pytest.raises(CaptureError, match="plays once"):
            next(iter(src))


@pytest.mark.gl
def test_player_source_can_start_with_the_empty_room(synth_gl, keeper_factory) -> None:
    with VirtualPlayerSource(keeper_factory(), seconds=0.2, size=(320, 240),
                             empty_room_seconds=0.1) as src:
        truths, images = [], []
        for fs in src:
            assert src.truth is not None
            truths.append(src.truth.copy())
            images.append(fs.frames[0].image.astype(float))
    assert np.isnan(truths[0]).all() and np.isnan(truths[2]).all()
    assert np.isfinite(truths[3]).all()
    assert np.abs(images[3] - images[0]).mean() > 3 * np.abs(images[1] - images[0]).mean()


@pytest.mark.gl
def test_lookahead_renders_the_same_frames_in_a_closed_loop(synth_gl, keeper_factory) -> None:
    import threading

    def play(lookahead: bool) -> tuple[np.ndarray, np.ndarray]:
        ctrl = keeper_factory()
        images, truths = [], []
        with VirtualPlayerSource(ctrl, seconds=0.8, size=(160, 120),
                                 lookahead=lookahead) as src:
            for fs in src:
                if fs.index == 3:  # the game reacts to a frame: a ball is coming
                    ctrl.set_target(0.7, (0.5, 1.3, 0.3), now=fs.t)
                assert src.truth is not None
                images.append(fs.frames[0].image)
                truths.append(src.truth.copy())
        return np.stack(images), np.stack(truths)

    sync, ahead = play(False), play(True)
    np.testing.assert_array_equal(sync[1], ahead[1])
    np.testing.assert_array_equal(sync[0], ahead[0])
    assert np.abs(sync[1][-1] - sync[1][0]).max() > 0.2  # the keeper did reach
    assert not [t for t in threading.enumerate() if t.name.startswith("virtual-player")]


@pytest.mark.gl
def test_lookahead_source_closes_cleanly_mid_stream(synth_gl, keeper_factory) -> None:
    import threading

    src = VirtualPlayerSource(keeper_factory(), size=(160, 120), lookahead=True)
    it = iter(src)
    for _ in range(3):
        next(it)
    src.close()
    assert not [t for t in threading.enumerate() if t.name.startswith("virtual-player")]
    with pytest.raises(CaptureError, match="closed"):
        next(iter(src))


class _Flaky:
    """A controller whose pose fails once, at 0.1 s (frame 3 at 30 fps)."""

    def __init__(self, inner: ReachController) -> None:
        self.inner = inner
        self.skeleton = inner.skeleton

    def pose_at(self, t: float) -> np.ndarray:
        if abs(t - 0.1) < 1e-9:
            raise RuntimeError("game bug")
        return self.inner.pose_at(t)


@pytest.mark.gl
@pytest.mark.parametrize("lookahead", [False, True])
def test_a_failing_frame_is_reported_and_the_stream_goes_on(synth_gl, keeper_factory,
                                                            lookahead) -> None:
    src = VirtualPlayerSource(_Flaky(keeper_factory()), seconds=0.2, size=(160, 120),
                              lookahead=lookahead)
    session = create_session(source=src, tracker=_CountingTracker())
    errors = []
    session.on("frame_error")(errors.append)
    with session:
        session.run()
    assert session.frames == 6 and len(errors) == 1 and errors[0].stage == "source"
    assert "frame 3" in errors[0].error and "game bug" in errors[0].error


class _CountingTracker:
    """A stand-in tracker: reports every joint lost (the source is under test)."""

    def process(self, frames):  # type: ignore[no-untyped-def]
        from bodyplay.trackers.base import TrackResult

        return TrackResult(frame=frames.index, t=frames.t, joints=np.full((17, 3), np.nan),
                           state=("lost",) * 17, confidence=np.zeros(17), ms=0.0)


def test_pose_source_reports_a_failing_sample_and_goes_on(keeper_factory) -> None:
    src = VirtualPoseSource(_Flaky(keeper_factory()), seconds=0.2)
    session = create_session(source=src, clock=FixedClock(1 / 30))
    errors = []
    session.on("frame_error")(errors.append)
    session.run()
    assert session.frames == 6 and len(errors) == 1 and "sample 3" in errors[0].error


class _Still:
    """A controller without frame_joints: the rest pose, 2 m to the side."""

    def __init__(self) -> None:
        from bodyplay.body.actor import load_actor

        self.skeleton = load_actor("m").skeleton

    def pose_at(self, t: float) -> np.ndarray:
        q = self.skeleton.rest_pose()
        q[0] = 2.0
        return q


def test_player_source_frames_a_controller_without_frame_joints_where_it_stands() -> None:
    src = VirtualPlayerSource(_Still(), size=(320, 240))  # no frame rendered: no GL
    assert src.cameras is not None
    j = src.controller.skeleton.joint_positions(src.controller.pose_at(0.0))
    uv = src.cameras[0].project(j)
    assert np.all((uv > 0) & (uv < (320, 240)))  # framed where it stands, not at 0
