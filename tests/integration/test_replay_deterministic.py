"""Replaying a recording gives a game exactly the same events, byte for byte."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from bodyplay.events import GestureEvent
from bodyplay.plugins import PluginRegistry
from bodyplay.record import EventLogWriter, ReplaySource, read_recording, record_session
from bodyplay.runtime import create_session
from bodyplay.testing import Timeline, scripted_session


class _HandAbove:
    """A tiny recognizer: started when the right wrist passes the head, performed 0.3 s on."""

    def __init__(self) -> None:
        self.since: float | None = None
        self.done = False

    def update(self, t: float, joints: np.ndarray, state: Sequence[str]) -> list[GestureEvent]:
        up = bool(joints[10, 1] > joints[4, 1])
        out: list[GestureEvent] = []
        if up and self.since is None:
            self.since = t
            out.append(GestureEvent(t=t, emitted_t=t, gesture="hand_up", phase="started",
                                    progress=0.0, started_t=t))
        elif up and self.since is not None and not self.done and t - self.since >= 0.3:
            self.done = True
            out.append(GestureEvent(t=t, emitted_t=t, gesture="hand_up", phase="performed",
                                    progress=1.0, started_t=self.since))
        elif not up:
            self.since, self.done = None, False
        return out

    def reset(self) -> None:
        self.since, self.done = None, False


def _replay(rec_path: Path, out: Path) -> bytes:
    src = ReplaySource(rec_path)
    s = create_session(source=src, clock=src.clock(), gestures=_HandAbove(),
                       plugins=PluginRegistry(entry_points=[]))
    with EventLogWriter(out).attach(s.bus):
        s.run()
    return out.read_bytes()


def test_two_replays_of_a_recording_produce_byte_identical_event_logs(tmp_path: Path) -> None:
    tl = Timeline().hold("idle", 0.5).gesture("raise_right_hand").gesture("wave_right")
    live = scripted_session(tl, fps=30.0, gestures=_HandAbove(),
                            player={"noise": 0.005, "seed": 7})
    rec_path = tmp_path / "live.jsonl"
    with record_session(live, rec_path):
        live.run()
    first = _replay(rec_path, tmp_path / "a.jsonl")
    second = _replay(rec_path, tmp_path / "b.jsonl")
    assert first == second
    assert b'"gesture":"hand_up","phase":"performed"' in first
    # the replay reproduces the recorded poses and gestures, not just itself
    recorded = read_recording(rec_path)
    replayed = read_recording_lines(first)
    assert [g["phase"] for g in replayed if g["type"] == "gesture"] == [
        e.phase for e in recorded.of("gesture")  # type: ignore[attr-defined]
    ]
    assert sum(1 for e in replayed if e["type"] == "pose") == len(recorded.poses)


def read_recording_lines(data: bytes) -> list[dict[str, object]]:
    import json

    return [json.loads(line) for line in data.splitlines() if line]
