"""Faults at run time: a camera that stalls or disappears, subscribers that raise or
block, the disk filling up while recording. Each says what the session does."""

from __future__ import annotations

import errno
import os
import threading
import time
from pathlib import Path

import cv2
import numpy as np
import pytest

from bodyplay.body.skeleton import Skeleton
from bodyplay.capture.sources import WebcamSource
from bodyplay.errors import CaptureError, SessionError
from bodyplay.record import RecorderOptions, read_recording, record_session
from bodyplay.runtime import ArrayPoseSource, FixedClock, ManualClock, SessionOptions
from bodyplay.runtime import create_session as _create_session
from bodyplay.trackers.base import TrackResult

W, H = 32, 24


def create_session(*args, **kwargs):  # type: ignore[no-untyped-def]
    kwargs.setdefault("gestures", None)  # these tests count tracking and error events
    return _create_session(*args, **kwargs)


class Device:
    """A fake cv2.VideoCapture: ``plan[i]`` says what read ``i`` does: "ok", "fail"
    (unplugged) or "block" (stalls until ``release`` is set)."""

    def __init__(self, plan: list[str], clock: ManualClock | None = None) -> None:
        self.plan, self.i, self.clock = plan, 0, clock
        self.release_event = threading.Event()

    def isOpened(self) -> bool:  # noqa: N802 - OpenCV's name
        return True

    def set(self, prop: int, value: float) -> bool:
        return True

    def get(self, prop: int) -> float:
        return {cv2.CAP_PROP_FRAME_WIDTH: W, cv2.CAP_PROP_FRAME_HEIGHT: H}.get(prop, 0.0)

    def read(self) -> tuple[bool, np.ndarray | None]:
        step = self.plan[self.i] if self.i < len(self.plan) else "fail"
        self.i += 1
        if step == "block":
            self.release_event.wait(10.0)
            return True, np.zeros((H, W, 3), np.uint8)
        if step == "fail":
            if self.clock is not None:
                self.clock.advance(1.0)  # each failed read takes a second of the clock
            return False, None
        return True, np.zeros((H, W, 3), np.uint8)

    def release(self) -> None:
        pass


class StandingTracker:
    """Sees the rest pose in every frame it is given."""

    def __init__(self) -> None:
        self.joints = Skeleton().joint_positions(Skeleton().rest_pose())

    def process(self, frames):  # type: ignore[no-untyped-def]
        return TrackResult(frames.index, frames.t, self.joints, ("tracked",) * 17,
                           np.ones(17), 0.0)


def _webcam(device: Device) -> WebcamSource:
    ticks = iter(np.arange(0.0, 1000.0, 1 / 30))
    return WebcamSource(0, width=W, height=H, clock=lambda: float(next(ticks)),
                        opener=lambda i: device)


def _log(session) -> list[str]:  # type: ignore[no-untyped-def]
    out: list[str] = []
    for name in ("tracking", "frame_error", "pose"):
        session.on(name)(lambda e: out.append(
            f"{e.name}:{getattr(e, 'status', getattr(e, 'stage', ''))}"))
    return out


def test_camera_unplugged_mid_session_reports_lost_and_frame_errors_then_resumes() -> None:
    device = Device(["ok"] * 5 + ["fail"] * 3 + ["ok"] * 4 + ["end"])
    device.plan[-1] = "fail"
    s = create_session(SessionOptions(max_source_errors=5), source=_webcam(device),
                       tracker=StandingTracker(), clock=FixedClock(1 / 30))
    log = _log(s)
    with pytest.raises(CaptureError, match="failed 5 times in a row"):
        s.run()
    assert log[:6] == ["tracking:found", "pose:", "pose:", "pose:", "pose:", "pose:"]
    assert log[6:10] == ["frame_error:source", "tracking:lost", "frame_error:source",
                         "frame_error:source"]
    assert log[10:15] == ["tracking:found", "pose:", "pose:", "pose:", "pose:"]
    assert s.frames == 9 and s.errors == 3 + 5


def test_camera_that_never_comes_back_ends_the_session_after_source_timeout() -> None:
    clock = ManualClock()
    device = Device(["ok"] * 3, clock=clock)
    s = create_session(SessionOptions(source_timeout=10.0, max_source_errors=1000,
                                      frame_timeout=None),  # read in this thread
                       source=_webcam(device), tracker=StandingTracker(), clock=clock)
    log = _log(s)
    with pytest.raises(CaptureError, match=r"no frame for 10\.0 s .*source_timeout=10\.0 s"):
        s.run()
    assert log.count("frame_error:source") == 11 and log.count("tracking:lost") == 1


def test_camera_that_stalls_is_reported_after_frame_timeout_and_resumes() -> None:
    device = Device(["ok", "ok", "block"] + ["ok"] * 10_000)
    s = create_session(SessionOptions(frame_timeout=0.2, max_source_errors=100),
                       source=_webcam(device), tracker=StandingTracker(),
                       clock=FixedClock(1 / 30))
    log = _log(s)
    errors: list[str] = []
    s.on("frame_error")(lambda e: errors.append(e.error))

    def wait_for(cond) -> None:  # type: ignore[no-untyped-def]
        deadline = time.monotonic() + 5.0
        while not cond() and time.monotonic() < deadline:
            time.sleep(0.01)
        assert cond(), log[-5:]

    s.start()
    wait_for(lambda: "tracking:lost" in log)  # nothing for 0.2 s: reported, not a hang
    assert "no frame for 0.2 s" in errors[0]
    assert log[:4] == ["tracking:found", "pose:", "pose:", "frame_error:source"]
    device.release_event.set()  # the camera delivers again
    wait_for(lambda: log.count("tracking:found") == 2 and log[-1] == "pose:")
    s.stop()
    assert s.errors == len(errors) >= 1


def _walk(n: int) -> np.ndarray:
    sk = Skeleton()
    q = np.repeat(sk.rest_pose()[None], n, axis=0)
    q[:, 0] = np.linspace(0.0, 1.0, n)
    return sk.joint_positions(q)


def test_subscriber_that_raises_is_unsubscribed_and_the_others_get_every_event() -> None:
    s = create_session(source=ArrayPoseSource(_walk(10)), clock=FixedClock())
    got: list[int] = []
    failures: list[tuple[int, bool]] = []

    @s.on("pose")
    def broken(e):  # type: ignore[no-untyped-def]
        raise RuntimeError("bug in the game")

    s.on("pose")(lambda e: got.append(e.frame))
    s.on("subscriber_error")(lambda e: failures.append((e.failures, e.unsubscribed)))
    assert s.run() == 10
    assert got == list(range(10)) and failures == [(1, False), (2, False), (3, True)]


def test_subscriber_that_blocks_is_named_when_the_session_cannot_stop() -> None:
    release = threading.Event()
    s = create_session(source=ArrayPoseSource(_walk(5)), clock=FixedClock())

    @s.on("pose")
    def waits_for_the_network(e):  # type: ignore[no-untyped-def]
        release.wait(10.0)

    s.start()
    time.sleep(0.1)
    with pytest.raises(SessionError, match="blocked in waits_for_the_network"):
        s.stop(timeout=0.2)
    release.set()
    s.join(timeout=5.0)
    assert not s.running


def test_disk_full_while_recording_keeps_the_recording_so_far_readable(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import bodyplay.record.recorder as recorder

    real_write = os.write
    budget = {"lines": 6}

    def write(fd: int, data: bytes | memoryview) -> int:
        budget["lines"] -= 1
        if budget["lines"] < 0:  # the disk fills up half way through a line
            real_write(fd, bytes(data)[: len(data) // 2])
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real_write(fd, data)

    monkeypatch.setattr(recorder.os, "write", write)
    s = create_session(source=ArrayPoseSource(_walk(20)), clock=FixedClock())
    errors: list[str] = []
    s.on("subscriber_error")(lambda e: errors.append(e.error))
    with record_session(s, tmp_path / "rec.jsonl", RecorderOptions(fsync="never")):
        assert s.run() == 20  # the game goes on
    rec = read_recording(tmp_path / "rec.jsonl")
    assert not rec.truncated and len(rec.poses) == 4  # header, found, 4 poses: 6 lines
    assert "No space left on device" in errors[0] and len(errors) == 3
