"""Specifications of the session: events per frame, clocks, bad frames, threads."""

from __future__ import annotations

import time
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np
import pytest

from bodyplay.body import Skeleton
from bodyplay.capture.frames import Frame, FrameSet
from bodyplay.errors import CaptureError, ConfigError, TimestampError
from bodyplay.events import Event, GestureEvent, PoseEvent, TrackingEvent
from bodyplay.runtime import (
    ArrayPoseSource,
    ClipPoseSource,
    FixedClock,
    ManualClock,
    PoseSample,
    Session,
    SessionOptions,
    SystemClock,
    create_session,
)
from bodyplay.trackers.base import TrackerCapabilities, TrackResult, lost_result

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"


def _walk(n: int = 20) -> np.ndarray:
    sk = Skeleton()
    q = np.repeat(sk.rest_pose()[None], n, axis=0)
    q[:, 2] = np.linspace(0.0, 1.0, n)
    return sk.joint_positions(q)


class _Collect:
    def __init__(self, session: Session, names: Sequence[str]) -> None:
        self.events: list[Event] = []
        for n in names:
            session.subscribe(n, self.events.append)

    def names(self) -> list[str]:
        return [e.name for e in self.events]


class _ThresholdRecognizer:
    """Performs "hand_up" whenever the right wrist rises above the head."""

    def __init__(self) -> None:
        self.up = False
        self.resets = 0

    def update(self, t: float, joints: np.ndarray, state: Sequence[str]) -> list[GestureEvent]:
        up = bool(joints[10, 1] > joints[4, 1])
        out = []
        if up and not self.up:
            out.append(GestureEvent(t=t, emitted_t=t, gesture="hand_up", phase="performed",
                                    progress=1.0, started_t=t))
        self.up = up
        return out

    def reset(self) -> None:
        self.resets += 1


def test_step_emits_one_pose_event_per_frame_with_capture_and_emit_times() -> None:
    j = _walk(5)
    s = create_session(source=ArrayPoseSource(j, fps=10.0), clock=FixedClock(0.5))
    got = _Collect(s, ["pose"])
    assert s.run() == 5
    poses = [e for e in got.events if isinstance(e, PoseEvent)]
    assert [p.frame for p in poses] == [0, 1, 2, 3, 4]
    assert [p.t for p in poses] == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4])
    assert [p.emitted_t for p in poses] == pytest.approx([0.0, 0.5, 1.0, 1.5, 2.0])
    np.testing.assert_allclose(poses[3].joints, j[3])
    assert poses[0].state == ("tracked",) * 17 and s.done


def test_tracking_events_fire_only_on_found_and_lost_transitions() -> None:
    j = _walk(12)
    j[4:8] = np.nan
    s = create_session(SessionOptions(lost_after=2), source=ArrayPoseSource(j),
                       clock=FixedClock())
    got = _Collect(s, ["tracking"])
    s.run()
    evs = [e for e in got.events if isinstance(e, TrackingEvent)]
    assert [(e.status, e.frame) for e in evs] == [("found", 0), ("lost", 5), ("found", 8)]


def test_gesture_events_come_after_the_pose_and_carry_the_session_clock() -> None:
    sk = Skeleton()
    q = np.repeat(sk.rest_pose()[None], 6, axis=0)
    q[3:, 3 + 3 * sk.node_index("r_shoulder") + 2] = -1.5  # right arm up from frame 3
    rec = _ThresholdRecognizer()
    s = create_session(source=ArrayPoseSource(sk.joint_positions(q)), gestures=rec,
                       clock=FixedClock(1.0, t0=100.0))
    got = _Collect(s, ["pose", "gesture"])
    s.run()
    names = got.names()
    i = names.index("gesture")
    assert names[i - 1] == "pose" and names.count("gesture") == 1
    g = got.events[i]
    assert isinstance(g, GestureEvent) and g.gesture == "hand_up"
    assert g.t == pytest.approx(0.1) and g.emitted_t == pytest.approx(103.0)


def test_filters_run_in_order_before_events_and_are_reset_when_lost() -> None:
    class AddOne:
        def __init__(self) -> None:
            self.resets = 0

        def filter(self, t: float, joints: np.ndarray, state: object = None) -> np.ndarray:
            return joints + 1.0

        def reset(self) -> None:
            self.resets += 1

    j = _walk(6)
    j[3:] = np.nan
    f1, f2 = AddOne(), AddOne()
    s = create_session(SessionOptions(lost_after=1), source=ArrayPoseSource(j),
                       filters=[f1, f2], clock=FixedClock())
    first = s.step()
    assert first is not None
    np.testing.assert_allclose(first.joints, j[0] + 2.0)
    s.run()
    assert f1.resets == 1 and f2.resets == 1


def test_frame_going_back_in_time_raises_timestamp_error_naming_both_frames() -> None:
    times = np.array([0.0, 0.1, 0.1, 0.3])
    s = create_session(source=ArrayPoseSource(_walk(4), times), clock=FixedClock())
    s.step()
    s.step()
    with pytest.raises(TimestampError, match=r"frame 2 .*0\.100000.*frame 1"):
        s.step()


class _FlakySource:
    """Raises on frame 2 but keeps going (a camera glitch)."""

    def __init__(self, n: int) -> None:
        self.n = n

    def __iter__(self) -> Iterator[PoseSample]:
        return self._Iter(self.n)

    class _Iter:
        def __init__(self, n: int) -> None:
            self.i = 0
            self.n = n

        def __next__(self) -> PoseSample:
            i = self.i
            self.i += 1
            if i >= self.n:
                raise StopIteration
            if i == 2:
                raise OSError("usb hiccup")
            j = np.zeros((17, 3))
            return PoseSample(t=i * 0.1, frame=i, joints=j, state=("tracked",) * 17,
                              confidence=np.ones(17))


def test_source_exception_on_one_frame_is_reported_and_skipped() -> None:
    s = create_session(source=_FlakySource(5), clock=FixedClock())
    got = _Collect(s, ["pose", "frame_error"])
    s.run()
    frames = [e.frame for e in got.events if isinstance(e, PoseEvent)]
    assert frames == [0, 1, 3, 4]
    errs = [e for e in got.events if e.name == "frame_error"]
    assert len(errs) == 1 and "usb hiccup" in errs[0].error and s.errors == 1


def test_source_failing_every_frame_ends_the_session_with_capture_error() -> None:
    class Dead:
        def __iter__(self) -> Dead:
            return self

        def __next__(self) -> PoseSample:
            raise OSError("unplugged")

    s = create_session(SessionOptions(max_source_errors=4), source=Dead(), clock=FixedClock())
    with pytest.raises(CaptureError, match="4 times in a row"):
        s.run()


class _FakeTracker:
    name = "fake"
    capabilities = TrackerCapabilities(joints=tuple(f"j{i}" for i in range(11)))
    cameras = ()

    def __init__(self) -> None:
        self.calls = 0

    def process(self, frames: FrameSet) -> TrackResult:
        self.calls += 1
        if frames.index == 1:
            raise RuntimeError("tracker diverged")
        if frames.index == 3:
            return lost_result(frames.index, frames.t)
        return TrackResult(frame=frames.index, t=frames.t, joints=np.ones((17, 3)),
                           state=("tracked",) * 17, confidence=np.full(17, 0.5), ms=1.0)

    def reset(self) -> None:
        pass


def _frames(n: int) -> list[FrameSet]:
    img = np.zeros((4, 4, 3), np.uint8)
    return [FrameSet((Frame(img, i / 30, i),), i / 30, i) for i in range(n)]


def test_frame_source_goes_through_the_tracker_and_tracker_errors_skip_the_frame() -> None:
    tr = _FakeTracker()
    s = create_session(SessionOptions(lost_after=1), source=_frames(5), tracker=tr,
                       clock=FixedClock())
    got = _Collect(s, ["pose", "tracking", "frame_error"])
    s.run()
    assert tr.calls == 5
    assert got.names() == ["tracking", "pose", "frame_error", "pose", "pose", "tracking",
                           "tracking", "pose"]
    pose = next(e for e in got.events if isinstance(e, PoseEvent))
    assert "upper_body_only" in pose.capabilities
    np.testing.assert_allclose(pose.confidence, 0.5)


def test_frame_sets_without_a_tracker_are_a_config_error() -> None:
    s = create_session(source=_frames(2), clock=FixedClock())
    with pytest.raises(ConfigError, match="no tracker"):
        s.step()


def test_worker_thread_serves_latest_pose_and_drain_until_stopped() -> None:
    n = 200
    s = create_session(source=ArrayPoseSource(_walk(n)), clock=SystemClock())
    with s:
        s.start()
        deadline = time.monotonic() + 10
        while s.latest_pose() is None and time.monotonic() < deadline:
            time.sleep(0.001)
        assert s.latest_pose() is not None
        s.join(timeout=10)
    assert not s.running
    events = s.drain(["pose"])
    assert [e.frame for e in events if isinstance(e, PoseEvent)] == list(range(n))


def test_worker_thread_error_is_raised_by_stop() -> None:
    times = np.array([0.0, 0.2, 0.1])
    s = create_session(source=ArrayPoseSource(_walk(3), times), clock=FixedClock())
    s.start()
    time.sleep(0.2)
    with pytest.raises(TimestampError):
        s.stop()


def test_realtime_option_paces_run_to_capture_times() -> None:
    s = create_session(SessionOptions(realtime=True), source=ArrayPoseSource(_walk(6), fps=50.0),
                       clock=SystemClock())
    t0 = time.perf_counter()
    s.run()
    assert time.perf_counter() - t0 >= 0.09  # 5 frame intervals of 20 ms


def test_run_respects_max_frames_and_resumes() -> None:
    s = create_session(source=ArrayPoseSource(_walk(10)), clock=ManualClock())
    assert s.run(max_frames=4) == 4
    assert s.run() == 6 and s.done
    assert s.step() is None


@pytest.mark.parametrize("max_frames", [-1, "10", 2.5, True])
def test_run_rejects_max_frames_that_is_not_a_whole_number(max_frames: object) -> None:
    s = create_session(source=ArrayPoseSource(_walk(3)), clock=ManualClock())
    with pytest.raises(ConfigError, match="max_frames must be a whole number"):
        s.run(max_frames=max_frames)  # type: ignore[arg-type]


def test_options_are_validated_by_the_factory() -> None:
    with pytest.raises(ConfigError, match="lost_after"):
        create_session(SessionOptions(lost_after=0), source=[])
    with pytest.raises(ConfigError, match="not iterable"):
        create_session(source=42)
    with pytest.raises(ConfigError, match="lacks method"):
        create_session(source=[], filters=[object()])
    assert isinstance(Session.from_options(source=[]), Session)


def test_clip_pose_source_feeds_a_mocap_clip_without_a_tracker() -> None:
    bvh = DATA / "mocap" / "cmu" / "13_29.bvh"
    if not bvh.exists():
        pytest.skip("shared data not available")
    pytest.importorskip("bodyplay.motion.clip")
    from bodyplay.motion.clip import load_clip

    clip = load_clip(bvh, fps=30.0).slice(0.0, 1.0)
    s = create_session(source=ClipPoseSource(clip), clock=FixedClock())
    poses: list[PoseEvent] = []
    s.subscribe("pose", poses.append)
    s.run()
    assert len(poses) == clip.num_frames
    np.testing.assert_allclose(poses[-1].joints, clip.joints()[-1])
