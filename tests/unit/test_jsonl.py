"""truth.jsonl / poses.jsonl reading and writing."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from bodyplay.body.joints import JOINT_INDEX, JOINT_NAMES
from bodyplay.capture import PoseJsonlWriter, PoseTrack, read_pose_jsonl, write_pose_jsonl
from bodyplay.errors import CaptureError


def record(frame: int, **over: object) -> dict[str, object]:
    rec: dict[str, object] = {
        "frame": frame,
        "t": frame / 30,
        "joints": {n: [0.1 * k, 1.0, 0.01 * frame] for k, n in enumerate(JOINT_NAMES)},
    }
    rec.update(over)
    return rec


def write_lines(path: Path, lines: list[str], final_newline: bool = True) -> Path:
    path.write_text("\n".join(lines) + ("\n" if final_newline else ""))
    return path


def test_read_gives_arrays_with_nan_for_null_and_lost_state(tmp_path: Path) -> None:
    rec = record(3)
    rec["joints"]["l_wrist"] = None  # type: ignore[index]
    rec["state"] = {"head": "inferred", "l_wrist": "lost"}
    rec["ms"] = 12.5
    path = write_lines(tmp_path / "p.jsonl", [json.dumps(record(2)), json.dumps(rec)])
    track = read_pose_jsonl(path)
    assert track.frames.tolist() == [2, 3]
    assert track.t == pytest.approx([2 / 30, 0.1])
    assert track.joints.shape == (2, 17, 3)
    w = JOINT_INDEX["l_wrist"]
    assert np.all(np.isnan(track.joints[1, w])) and not np.any(np.isnan(track.joints[0]))
    assert track.state[1, w] == "lost" and track.state[1, JOINT_INDEX["head"]] == "inferred"
    assert track.state[0, w] == "tracked"
    assert np.isnan(track.ms[0]) and track.ms[1] == 12.5


def test_write_then_read_round_trips(tmp_path: Path) -> None:
    rng = np.random.default_rng(1)
    joints = rng.normal(size=(5, 17, 3))
    joints[2, 4] = np.nan
    state = np.full((5, 17), "tracked", dtype="<U8")
    state[1, 6] = "inferred"
    frames = [0, 1, 2, 5, 6]
    track = PoseTrack.from_arrays(frames, np.arange(5) / 60, joints, state, [1, 2, 3, 4, 5])
    back = read_pose_jsonl(write_pose_jsonl(tmp_path / "p.jsonl", track))
    assert back.frames.tolist() == [0, 1, 2, 5, 6]
    np.testing.assert_allclose(back.joints, track.joints, atol=1e-6)
    assert (back.state == track.state).all() and back.state[2, 4] == "lost"
    np.testing.assert_allclose(back.ms, track.ms)
    truth_form = write_pose_jsonl(tmp_path / "t.jsonl", track, state=False, ms=False)
    first = json.loads(truth_form.read_text().splitlines()[0])
    assert set(first) == {"frame", "t", "joints"}


def test_truncated_last_line_is_dropped_with_a_warning(tmp_path: Path) -> None:
    full = json.dumps(record(0))
    cut = json.dumps(record(1))[:40]
    path = write_lines(tmp_path / "p.jsonl", [full, cut], final_newline=False)
    with pytest.warns(UserWarning, match="cut short"):
        track = read_pose_jsonl(path)
    assert track.frames.tolist() == [0]


@pytest.mark.parametrize(
    ("bad", "message"),
    [
        ("{not json", r"p.jsonl:2: not valid JSON"),
        (json.dumps({"frame": 1, "t": 0.1}), r'p.jsonl:2: missing "joints"'),
        (json.dumps({**record(1), "frame": -1}), r"p.jsonl:2: .*non-negative"),
        (json.dumps(record(1, joints={"nose": [0, 0, 0]})), r"p.jsonl:2: unknown joint 'nose'"),
        (json.dumps(record(1, joints={"head": [0, 0]})), r"p.jsonl:2: joint 'head' must be"),
        (json.dumps(record(1, state={"head": "maybe"})), r"p.jsonl:2: state of 'head'"),
        (json.dumps(record(0)), r"p.jsonl:2: frame 0 does not follow frame 0"),
    ],
)
def test_malformed_line_raises_with_its_line_number(tmp_path: Path, bad: str, message: str) -> None:
    path = write_lines(tmp_path / "p.jsonl", [json.dumps(record(0)), bad, json.dumps(record(5))])
    with pytest.raises(CaptureError, match=message):
        read_pose_jsonl(path)


def test_malformed_last_line_with_newline_is_not_excused(tmp_path: Path) -> None:
    path = write_lines(tmp_path / "p.jsonl", [json.dumps(record(0)), "{oops"], final_newline=True)
    with pytest.raises(CaptureError, match=":2: not valid JSON"):
        read_pose_jsonl(path)


def test_streaming_writer_flushes_each_record_and_rejects_going_back(tmp_path: Path) -> None:
    path = tmp_path / "p.jsonl"
    with PoseJsonlWriter(path) as writer:
        writer.write(record(0, ms=3.0))
        assert read_pose_jsonl(writer.partial).frames.tolist() == [0]  # readable mid-session
        assert not path.exists()  # not under the final name until complete
        with pytest.raises(CaptureError, match="after frame 0"):
            writer.write(record(0))
    assert len(read_pose_jsonl(path)) == 1 and not writer.partial.exists()


def test_streaming_writer_stopped_by_an_error_leaves_only_the_partial_file(
    tmp_path: Path,
) -> None:
    path = tmp_path / "p.jsonl"
    with pytest.raises(RuntimeError), PoseJsonlWriter(path) as writer:
        writer.write(record(0))
        raise RuntimeError("the tracker failed")
    assert not path.exists() and len(read_pose_jsonl(writer.partial)) == 1


def test_missing_file_is_a_capture_error(tmp_path: Path) -> None:
    with pytest.raises(CaptureError, match="no such pose file"):
        read_pose_jsonl(tmp_path / "none.jsonl")
