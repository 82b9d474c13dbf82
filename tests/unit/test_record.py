"""Specifications of recordings: format, crash tolerance, frames, replay source."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from bodyplay.body import Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.capture.frames import Frame, FrameSet
from bodyplay.errors import CaptureError, ConfigError
from bodyplay.events import ContactEvent, GestureEvent, PoseEvent
from bodyplay.record import (
    EventLogWriter,
    Recorder,
    RecorderOptions,
    ReplaySource,
    read_recording,
    record_session,
)
from bodyplay.runtime import ArrayPoseSource, FixedClock, create_session
from bodyplay.trackers.base import TrackResult


def _joints(n: int) -> np.ndarray:
    sk = Skeleton()
    q = np.repeat(sk.rest_pose()[None], n, axis=0)
    q[:, 0] = np.linspace(0, 1, n)
    return sk.joint_positions(q)


def _record(path: Path, joints: np.ndarray, **opts: object) -> None:
    s = create_session(source=ArrayPoseSource(joints), clock=FixedClock(), gestures=None)
    with record_session(s, path, RecorderOptions(**opts), meta={"who": "test"}):  # type: ignore[arg-type]
        s.run()


def test_recording_has_a_header_line_then_one_json_event_per_line(tmp_path: Path) -> None:
    p = tmp_path / "rec.jsonl"
    _record(p, _joints(4))
    lines = p.read_text().splitlines()
    head = json.loads(lines[0])
    assert head["type"] == "header" and head["version"] == 1 and head["meta"] == {"who": "test"}
    assert head["options"]["lost_after"] == 3 and head["cameras"] == []
    kinds = [json.loads(x)["type"] for x in lines[1:]]
    assert kinds == ["tracking", "pose", "pose", "pose", "pose"]
    pose = json.loads(lines[2])
    assert {"t", "emitted_t", "frame", "joints", "state", "confidence"} <= set(pose)


def test_read_recording_rebuilds_typed_events_with_nan_for_lost_joints(tmp_path: Path) -> None:
    j = _joints(5)
    j[2, 11:] = np.nan
    p = tmp_path / "rec.jsonl"
    _record(p, j)
    rec = read_recording(p)
    assert not rec.truncated and len(rec.poses) == 5
    assert isinstance(rec.poses[2], PoseEvent)
    np.testing.assert_allclose(rec.joints(), j, atol=1e-6)
    assert rec.poses[2].state[11] == "lost" and rec.poses[2].state[0] == "tracked"
    assert rec.fps == pytest.approx(30.0)


def test_truncated_last_line_is_ignored_on_read(tmp_path: Path) -> None:
    p = tmp_path / "rec.jsonl"
    _record(p, _joints(6))
    data = p.read_bytes()
    cut = data[: len(data) - 40]  # the process died half-way through the last line
    p.write_bytes(cut)
    rec = read_recording(p)
    assert rec.truncated and len(rec.poses) == 5


def test_corrupt_line_in_the_middle_is_an_error_naming_the_line(tmp_path: Path) -> None:
    p = tmp_path / "rec.jsonl"
    _record(p, _joints(3))
    lines = p.read_text().splitlines(keepends=True)
    lines[2] = '{"type": "pose", broken\n'
    p.write_text("".join(lines))
    with pytest.raises(CaptureError, match=r"rec.jsonl:3: corrupt line"):
        read_recording(p)


def test_not_a_recording_is_a_clear_error(tmp_path: Path) -> None:
    p = tmp_path / "x.jsonl"
    p.write_text('{"type": "pose"}\n')
    with pytest.raises(CaptureError, match="not a bodyplay recording"):
        read_recording(p)
    with pytest.raises(CaptureError, match="no such recording"):
        read_recording(tmp_path / "missing.jsonl")


def test_recorder_refuses_to_overwrite_unless_asked(tmp_path: Path) -> None:
    p = tmp_path / "rec.jsonl"
    Recorder(p).close()
    with pytest.raises(ConfigError, match="exists"):
        Recorder(p)
    Recorder(p, RecorderOptions(overwrite=True)).close()


def test_each_line_is_on_disk_as_soon_as_the_event_is_emitted(tmp_path: Path) -> None:
    p = tmp_path / "rec.jsonl"
    s = create_session(source=ArrayPoseSource(_joints(3)), clock=FixedClock())
    rec = record_session(s, p, RecorderOptions(fsync="never"))
    s.step()
    # read back while the recorder is still open: no buffering in the process
    assert len(read_recording(p).poses) == 1
    rec.close()


def test_recorder_options_are_validated() -> None:
    with pytest.raises(ConfigError, match="fsync"):
        RecorderOptions(fsync="sometimes").validate()  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="frames"):
        RecorderOptions(frames="gif").validate()  # type: ignore[arg-type]


class _Tracker:
    name = "t"
    cameras = (Camera.from_fov("cam0", 8, 6, 60.0),)

    def process(self, frames: FrameSet) -> TrackResult:
        return TrackResult(frame=frames.index, t=frames.t, joints=np.zeros((17, 3)),
                           state=("tracked",) * 17, confidence=np.ones(17), ms=0.0)

    def reset(self) -> None:
        pass


@pytest.mark.parametrize("kind", ["png", "jpeg"])
def test_frames_are_saved_as_images_next_to_the_recording(tmp_path: Path, kind: str) -> None:
    rng = np.random.default_rng(0)
    sets = [FrameSet((Frame(rng.integers(0, 255, (6, 8, 3), dtype=np.uint8), i / 30, i),),
                     i / 30, i) for i in range(3)]
    s = create_session(source=sets, tracker=_Tracker(), clock=FixedClock())
    p = tmp_path / "rec.jsonl"
    with record_session(s, p, RecorderOptions(frames=kind)):  # type: ignore[arg-type]
        s.run()
    rec = read_recording(p)
    assert [f.frame for f in rec.frames] == [0, 1, 2]
    assert rec.cameras[0].name == "cam0"
    img = rec.frames[1].files["cam0"]
    assert img.exists() and img.parent.parent == tmp_path / "rec.frames"
    if kind == "png":
        import cv2

        back = cv2.cvtColor(cv2.imread(str(img)), cv2.COLOR_BGR2RGB)
        np.testing.assert_array_equal(back, sets[1].frames[0].image)


def test_replay_source_yields_the_recorded_poses_and_chosen_events(tmp_path: Path) -> None:
    p = tmp_path / "rec.jsonl"
    s = create_session(source=ArrayPoseSource(_joints(4)), clock=FixedClock())
    rec = record_session(s, p)

    def contact(e: PoseEvent) -> None:
        if e.frame == 2:
            s.emit(ContactEvent(t=e.t, emitted_t=e.emitted_t, part="r_wrist", obj="ball",
                                phase="begin"))

    s.subscribe("pose", contact)
    s.run()
    rec.close()
    src = ReplaySource(p, replay_events=["contact"])
    samples = list(src)
    assert [x.frame for x in samples] == [0, 1, 2, 3]
    assert [len(x.events) for x in samples] == [0, 0, 1, 0]
    s2 = create_session(source=src, clock=src.clock())
    contacts: list[ContactEvent] = []
    s2.subscribe("contact", contacts.append)
    s2.run()
    assert len(contacts) == 1 and contacts[0].obj == "ball"


def test_event_log_writer_writes_every_event_as_json(tmp_path: Path) -> None:
    p = tmp_path / "events.jsonl"
    with EventLogWriter(p) as w:
        w(GestureEvent(t=1.0, emitted_t=1.5, gesture="wave", phase="started", progress=0.0,
                       started_t=1.0))
    d = json.loads(p.read_text())
    assert d == {"type": "gesture", "t": 1.0, "emitted_t": 1.5, "gesture": "wave",
                 "phase": "started", "progress": 0.0, "started_t": 1.0, "player": 0}
