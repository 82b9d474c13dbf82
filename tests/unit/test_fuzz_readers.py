"""Bad input, fuzzed: every reader gives a BodyplayError naming the file, or reads it.

Each reader gets a small valid file, damaged by hypothesis (cut short, bytes
overwritten, inserted or deleted, a line replaced by junk, a number replaced by a
value of another type) and must either read it or raise a
:class:`~bodyplay.errors.BodyplayError` whose message names the file; never
another exception, never a hang. The default run tries ``FUZZ_EXAMPLES`` inputs per
reader; ``-m slow`` tries ``FUZZ_EXAMPLES_SLOW`` (docs/reliability.md quotes both).
"""

from __future__ import annotations

import json
import re
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bodyplay.errors import BodyplayError

FUZZ_EXAMPLES = 40
FUZZ_EXAMPLES_SLOW = 1000

JUNK_VALUES = ["", "nan", "-inf", "1e999", "-1", "0", "null", "[]", "{}", '"x"', "[1, 2]",
               "true", "\x00", "\xff\xfe", "é", "9" * 40, "{", "]", "#", "=", ":", "\\"]


def _mutations(data: bytes) -> st.SearchStrategy[bytes]:
    """Damaged copies of ``data``: cut, overwritten, inserted, deleted, a line or a
    number replaced by junk, or a line duplicated."""
    n = len(data)
    pos = st.integers(0, max(n - 1, 0))
    junk = st.one_of(st.binary(min_size=1, max_size=16),
                     st.sampled_from(JUNK_VALUES).map(lambda s: s.encode("utf-8", "replace")))
    lines = data.split(b"\n")
    numbers = [m.span() for m in re.finditer(rb"-?\d+(\.\d+)?(e-?\d+)?", data)][:400]

    def cut(i: int) -> bytes:
        return data[:i]

    def overwrite(i: int, b: bytes) -> bytes:
        return data[:i] + b + data[i + len(b):]

    def insert(i: int, b: bytes) -> bytes:
        return data[:i] + b + data[i:]

    def delete(i: int, k: int) -> bytes:
        return data[:i] + data[i + k:]

    def line(i: int, b: bytes) -> bytes:
        out = list(lines)
        out[i % len(out)] = b
        return b"\n".join(out)

    def dup(i: int) -> bytes:
        out = list(lines)
        out.insert(i % len(out), out[i % len(out)])
        return b"\n".join(out)

    def number(i: int, b: bytes) -> bytes:
        if not numbers:
            return data + b
        a, z = numbers[i % len(numbers)]
        return data[:a] + b + data[z:]

    idx = st.integers(0, 10_000)
    return st.one_of(
        st.builds(cut, pos),
        st.builds(overwrite, pos, junk),
        st.builds(insert, pos, junk),
        st.builds(delete, pos, st.integers(1, 64)),
        st.builds(line, idx, junk),
        st.builds(dup, idx),
        st.builds(number, idx, junk),
        st.builds(number, idx, junk),
    )


def _check(read: Callable[[Path], Any], path: Path, data: bytes) -> None:
    """``read(path)`` with ``data`` in the file: it reads, or a BodyplayError names it."""
    path.write_bytes(data)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            read(path)
    except BodyplayError as exc:
        assert path.name in str(exc), f"the error does not name the file: {exc}"


def _fuzz(valid: Callable[[Path], bytes], read: Callable[[Path], Any], name: str,
          examples: int) -> Callable[..., None]:
    """A test body: damage ``valid``'s bytes and feed them to ``read``."""

    def run(tmp_path_factory: pytest.TempPathFactory) -> None:
        folder = tmp_path_factory.mktemp("fuzz")
        data = valid(folder)

        tried = []

        @settings(max_examples=examples, deadline=None, database=None,
                  suppress_health_check=list(HealthCheck))
        @given(_mutations(data))
        def inner(bad: bytes) -> None:
            tried.append(bad)
            _check(read, folder / name, bad)

        inner()
        distinct = len(set(tried))
        print(f"fuzz {name}: {len(tried)} inputs tried, {distinct} distinct")  # -s: the counts
        assert distinct >= 0.8 * examples  # the strategy is not starved

    return run


# ---- valid inputs -------------------------------------------------------------------
def _bvh(folder: Path) -> bytes:
    from bodyplay.motion import load_clip, write_bvh

    clip = load_clip("13_29", fps=30).slice(1.0, 0.2)
    p = write_bvh(folder / "ok.bvh", clip.skeleton, clip.poses, clip.fps)
    return Path(p).read_bytes()


def _calib(folder: Path) -> bytes:
    from bodyplay.capture.camera import Camera, look_at, write_calib

    cams = [Camera.from_fov(f"cam{i}", 64, 48, 60.0, *look_at((i, 1.2, 3.0), (0, 1, 0)))
            for i in range(2)]
    return Path(write_calib(folder / "ok.json", cams)).read_bytes()


def _poses(folder: Path) -> bytes:
    from bodyplay.capture.jsonl import PoseTrack, write_pose_jsonl
    from bodyplay.motion import load_clip

    clip = load_clip("13_29", fps=30).slice(1.0, 0.2)
    j = clip.joints()
    j[1, 12:] = np.nan
    track = PoseTrack.from_arrays(range(len(j)), clip.times, j, ms=np.full(len(j), 3.0))
    return Path(write_pose_jsonl(folder / "ok.jsonl", track)).read_bytes()


def _recording(folder: Path) -> bytes:
    from bodyplay.motion import load_clip
    from bodyplay.record import record_session
    from bodyplay.runtime import ArrayPoseSource, FixedClock, create_session

    j = load_clip("13_29", fps=30).slice(1.0, 0.2).joints()
    s = create_session(source=ArrayPoseSource(j), clock=FixedClock())
    with record_session(s, folder / "ok.jsonl"):
        s.run()
    return (folder / "ok.jsonl").read_bytes()


def _gesture(folder: Path) -> bytes:
    from importlib import resources

    return (resources.files("bodyplay") / "gestures" / "builtin" / "hit.toml").read_bytes()


QCA = """<?xml version='1.0' encoding='ASCII'?>
<calibration type="regular"><cameras>
 <camera active="1" serial="cam01">
  <fov_video bottom="479" left="0" right="639" top="0"/>
  <transform r11="0.55" r12="0.80" r13="0.21" r21="-0.43" r22="0.06" r23="0.90" r31="0.71"
   r32="-0.59" r33="0.38" x="1460.2" y="-1909.1" z="1896.5"/>
  <intrinsic centerPointU="20480.0" centerPointV="15360.0" focalLengthU="35840.0"
   focalLengthV="35840.0" radialDistortion1="-0.04" radialDistortion2="0.13"
   radialDistortion3="0.0" tangentalDistortion1="0.0006" tangentalDistortion2="0.0007"/>
 </camera>
</cameras></calibration>
"""

SPORTS2D = """[demo]
name = "demo"
size = [ 640, 480]
matrix = [ [ 800.0, 0.0, 320.0], [ 0.0, 800.0, 240.0], [ 0.0, 0.0, 1.0]]
distortions = [ 0.0, 0.0, 0.0, 0.0]
rotation = [ 1.2082, 1.2098, -1.2082]
translation = [ -3.51, 1.70, 10.0]
fisheye = false

[metadata]
adjusted = false
error = 0.0
"""


# ---- readers --------------------------------------------------------------------------
def _read_bvh(p: Path) -> None:
    from bodyplay.motion import read_bvh

    read_bvh(p)


def _read_calib(p: Path) -> None:
    from bodyplay.capture.camera import read_calib

    read_calib(p)


def _read_poses(p: Path) -> None:
    from bodyplay.capture.jsonl import read_pose_jsonl

    read_pose_jsonl(p)


def _read_recording(p: Path) -> None:
    from bodyplay.record import ReplaySource, read_recording

    read_recording(p)
    src = ReplaySource(p)
    for _ in src:
        pass


def _read_gesture(p: Path) -> None:
    from bodyplay.gestures import load_gestures

    load_gestures([str(p)])


def _read_qca(p: Path) -> None:
    from bodyplay.capture.calibration import read_qualisys_calib

    read_qualisys_calib(p)


def _read_sports2d(p: Path) -> None:
    from bodyplay.capture.external import read_toml_calib

    read_toml_calib(p)


# ---- videos and capture folders ------------------------------------------------------
def _video(folder: Path, name: str = "ok.mp4", frames: int = 4, size: tuple[int, int] = (64, 48),
           fourcc: str = "mp4v") -> Path:
    import cv2

    p = folder / name
    w = cv2.VideoWriter(str(p), cv2.VideoWriter.fourcc(*fourcc), 30.0, size)
    rng = np.random.default_rng(0)
    for _ in range(frames):
        w.write(rng.integers(0, 255, (size[1], size[0], 3), dtype=np.uint8))
    w.release()
    return p


def _read_video(p: Path) -> None:
    from bodyplay.capture.sources import VideoFileSource

    with VideoFileSource(p, fps=30.0) as src:
        for _ in src:
            pass


def _read_folder(p: Path) -> None:
    from bodyplay.capture.sources import open_source

    with open_source(p) as src:
        for _ in src:
            pass


READERS: dict[str, tuple[Callable[[Path], bytes], Callable[[Path], Any], str]] = {
    "bvh": (_bvh, _read_bvh, "clip.bvh"),
    "calib.json": (_calib, _read_calib, "calib.json"),
    "poses.jsonl": (_poses, _read_poses, "poses.jsonl"),
    "recording": (_recording, _read_recording, "rec.jsonl"),
    "gesture toml": (_gesture, _read_gesture, "jab.toml"),
    "pose2sim qca": (lambda _: QCA.encode(), _read_qca, "Calib.qca.txt"),
    "sports2d toml": (lambda _: SPORTS2D.encode(), _read_sports2d, "Calib_demo.toml"),
    "video": (lambda folder: _video(folder).read_bytes(), _read_video, "cam0.mp4"),
}


@pytest.mark.parametrize("reader", sorted(READERS))
def test_damaged_file_is_read_or_rejected_with_an_error_naming_it(
    reader: str, tmp_path_factory: pytest.TempPathFactory
) -> None:
    valid, read, name = READERS[reader]
    _fuzz(valid, read, name, FUZZ_EXAMPLES)(tmp_path_factory)


@pytest.mark.slow
@pytest.mark.parametrize("reader", sorted(READERS))
def test_many_damaged_files_are_read_or_rejected_with_an_error_naming_them(
    reader: str, tmp_path_factory: pytest.TempPathFactory
) -> None:
    valid, read, name = READERS[reader]
    _fuzz(valid, read, name, FUZZ_EXAMPLES_SLOW)(tmp_path_factory)


@pytest.mark.parametrize("reader", sorted(set(READERS) - {"video"}))  # text formats
def test_a_corrupt_middle_line_is_named_by_its_line_number(
    reader: str, tmp_path: Path
) -> None:
    valid, read, name = READERS[reader]
    lines = valid(tmp_path).split(b"\n")
    mid = len(lines) // 2
    lines[mid] = b"{{ this is not valid ]] " + b"\xff"
    p = tmp_path / name
    p.write_bytes(b"\n".join(lines))
    with pytest.raises(BodyplayError) as info:
        read(p)
    msg = str(info.value)
    assert p.name in msg
    assert re.search(rf"\b(line )?{mid + 1}\b", msg), msg


def test_json_that_is_valid_but_of_the_wrong_shape_is_rejected_naming_the_file(
    tmp_path: Path,
) -> None:
    from bodyplay.capture.camera import read_calib

    for doc in ([], {"cameras": {}}, {"cameras": [1]}, {"cameras": [{"name": 3}]},
                {"cameras": [{"name": "c", "width": -1, "height": 2, "K": [[1]], "R": 0}]}):
        p = tmp_path / "calib.json"
        p.write_text(json.dumps(doc))
        with pytest.raises(BodyplayError, match="calib.json"):
            read_calib(p)




@pytest.mark.parametrize("case", ["zero frames", "empty file", "text file", "cut at 1 kB",
                                  "mjpg avi", "mkv"])
def test_video_of_no_frames_cut_short_or_another_codec_is_read_or_named(
    case: str, tmp_path: Path
) -> None:
    if case == "zero frames":
        p = _video(tmp_path, "cam0.mp4", frames=0)
    elif case == "empty file":
        p = tmp_path / "cam0.mp4"
        p.write_bytes(b"")
    elif case == "text file":
        p = tmp_path / "cam0.mp4"
        p.write_text("not a video\n")
    elif case == "cut at 1 kB":
        p = _video(tmp_path, "cam0.mp4", frames=4)
        p.write_bytes(p.read_bytes()[:1024])
    elif case == "mjpg avi":
        p = _video(tmp_path, "cam0.avi", fourcc="MJPG")
    else:
        p = _video(tmp_path, "cam0.mkv", fourcc="mp4v")
    try:
        _read_video(p)
    except BodyplayError as exc:
        assert p.name in str(exc)
        assert case not in ("mjpg avi", "mkv"), exc  # another codec is read, not refused


_DAMAGES = ["no calib", "calib names a missing camera", "video of another size", "empty video",
            "image of another size", "unreadable image", "no images", "calib is a folder",
            "two cameras of different lengths", "nothing"]


def _capture(folder: Path, damage: str) -> Path:
    import cv2

    from bodyplay.capture.camera import Camera, look_at, write_calib

    cap = folder / "cap"
    cap.mkdir()
    cams = [Camera.from_fov(f"cam{i}", 64, 48, 60.0, *look_at((i, 1.2, 3.0), (0, 1, 0)))
            for i in range(2)]
    if damage != "no calib" and damage != "calib is a folder":
        extra = [Camera.from_fov("cam9", 64, 48, 60.0, *look_at((0, 1.2, 3.0), (0, 1, 0)))]
        write_calib(cap / "calib.json",
                    cams + (extra if damage == "calib names a missing camera" else []))
    if damage == "calib is a folder":
        (cap / "calib.json").mkdir()
    _video(cap, "cam0.mp4", size=(80, 48) if damage == "video of another size" else (64, 48),
           frames=0 if damage == "empty video" else 4)
    images = cap / "cam1"
    images.mkdir()
    n = 0 if damage == "no images" else (2 if damage == "two cameras of different lengths" else 4)
    for i in range(n):
        size = (50, 40) if damage == "image of another size" and i == 2 else (48, 64)
        cv2.imwrite(str(images / f"{i:06d}.png"), np.full((*size, 3), 9 * i, np.uint8))
    if damage == "unreadable image":
        (images / "000001.png").write_bytes(b"\x89PNG broken")
    return cap


@settings(max_examples=FUZZ_EXAMPLES, deadline=None, database=None,
          suppress_health_check=list(HealthCheck))
@given(st.sampled_from(_DAMAGES))
def test_damaged_capture_folder_is_read_or_rejected_naming_the_folder(damage: str) -> None:
    import tempfile
    import warnings

    with tempfile.TemporaryDirectory() as tmp:
        cap = _capture(Path(tmp), damage)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                _read_folder(cap)
            except BodyplayError as exc:
                assert str(cap) in str(exc), exc
                return
        assert damage in ("nothing", "two cameras of different lengths"), damage
        uneven = [w for w in caught if "different numbers of frames" in str(w.message)]
        if damage == "two cameras of different lengths":
            assert uneven and str(cap) in str(uneven[0].message), [str(w.message) for w in caught]
        else:
            assert not uneven


# ---- --set values and the command line -----------------------------------------------
@settings(max_examples=4 * FUZZ_EXAMPLES, deadline=None, database=None)
@given(st.sampled_from(["max_speed", "threshold", "body", "locate.tau", "database_size",
                        "arm_selection_frames", "pose_prior", "initial_white_balance", "nope",
                        "locate.nope", "", "locate."]),
       st.one_of(st.sampled_from(JUNK_VALUES), st.text(max_size=12)))
def test_set_values_are_applied_or_rejected_with_a_config_error(name: str, value: str) -> None:
    from bodyplay.errors import ConfigError
    from bodyplay.trackers.colorshirt import ColorShirtOptions
    from bodyplay.trackers.colorshirt.options import options_with_overrides

    try:
        options_with_overrides(ColorShirtOptions(), [f"{name}={value}"])
    except ConfigError as exc:
        assert name.split(".")[-1] in str(exc) or "--set" in str(exc), exc


CLI_CASES = {
    "eval": ("poses.jsonl", "poses.jsonl",
             lambda f, p: ["eval", "--truth", str(p), "--poses", str(p)]),
    "events --clip": ("clip.bvh", "bvh",
                      lambda f, p: ["events", "--clip", str(p), "--out", str(f / "e.jsonl")]),
    "export": ("rec.jsonl", "recording",
               lambda f, p: ["export", str(p), "--format", "poses", "--out", str(f / "o.jsonl")]),
    "import": ("Calib_demo.toml", "sports2d toml",
               lambda f, p: ["import", str(f), "--out", str(f / "capture")]),
}


@pytest.mark.parametrize("case", sorted(CLI_CASES))
def test_command_line_on_damaged_input_exits_2_naming_the_file_and_writes_no_output(
    case: str, tmp_path_factory: pytest.TempPathFactory, capsys: pytest.CaptureFixture[str]
) -> None:
    from bodyplay.cli import main

    name, reader, argv = CLI_CASES[case]
    valid = READERS[reader][0]
    folder = tmp_path_factory.mktemp("cli")
    data = valid(folder)
    if case == "import":
        _video(folder, "demo.mp4")

    tried = []

    @settings(max_examples=FUZZ_EXAMPLES // 2, deadline=None, database=None,
              suppress_health_check=list(HealthCheck))
    @given(_mutations(data))
    def inner(bad: bytes) -> None:
        tried.append(bad)
        p = folder / name
        p.write_bytes(bad)
        for out in ("e.jsonl", "o.jsonl"):
            (folder / out).unlink(missing_ok=True)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            code = main(argv(folder, p))
        err = capsys.readouterr().err
        if code != 0:
            assert code == 2 and p.name in err, err
            assert not (folder / "e.jsonl").exists() and not (folder / "o.jsonl").exists()

    inner()
    with capsys.disabled():
        print(f"fuzz bodyplay {case}: {len(tried)} inputs tried")
