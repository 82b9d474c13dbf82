"""Record sessions to crash-safe JSON lines, read them back, and replay them as a source."""

from bodyplay.record.format import (
    FrameRecord,
    Recording,
    event_from_json,
    event_line,
    read_recording,
)
from bodyplay.record.recorder import EventLogWriter, Recorder, RecorderOptions, record_session
from bodyplay.record.replay import ReplaySource

__all__ = [
    "EventLogWriter",
    "FrameRecord",
    "Recorder",
    "RecorderOptions",
    "Recording",
    "ReplaySource",
    "event_from_json",
    "event_line",
    "read_recording",
    "record_session",
]
