"""Every code example of the README and docs/ runs as written and prints what it says.

Python blocks run with ``clip.bvh`` read as the built-in clip 13_29 and, for the
fragments that use names defined by the surrounding text (``tracker``, ``joints``,
``vertices`` ...), a short setup that defines them; each block's output is checked.
Every ``bodyplay ...`` line of a shell block must parse with today's command line.
A new example without an entry in ``EXAMPLES`` fails
``test_every_python_example_of_the_docs_has_a_check``.
"""

from __future__ import annotations

import re
import shlex
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DOCS = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
SHARED = REPO.parent / "shared" / "data"


def _blocks(lang: str) -> list[tuple[str, int, str]]:
    """(doc, index among that doc's ``lang`` blocks, code) for every fenced block."""
    out = []
    for doc in DOCS:
        found = re.findall(r"```(\w*)\n(.*?)```", doc.read_text(), flags=re.S)
        code = [b for kind, b in found if kind == lang]
        out += [(str(doc.relative_to(REPO)), i, b) for i, b in enumerate(code)]
    return out


@dataclass(frozen=True)
class Example:
    """How to run one block: ``setup`` code run first in the same namespace, ``check``
    of what it printed, and what it needs (GL, ../shared, a slow pose database)."""

    check: Callable[[str], object]
    setup: str = ""
    gl: bool = False
    shared: bool = False
    slow: bool = False
    skip: str = ""


def _has(*patterns: str) -> Callable[[str], None]:
    def check(out: str) -> None:
        for p in patterns:
            assert re.search(p, out, flags=re.M), (p, out[-2000:])
    return check


def _silent(out: str) -> None:
    assert out == "", out


def _readme_gestures(out: str) -> None:
    """The README loop prints each performed gesture: the same ones, at the same times,
    as ``bodyplay events --clip 13_29`` (which recognizes the built-in set by default)."""
    import json

    from bodyplay.cli import main

    printed = [tuple(line.split()[::2]) for line in out.splitlines()]
    assert len(printed) >= 5 and {g for _, g in printed} >= {"jump", "raise_arms"}, out
    tmp = Path(__import__("tempfile").mkdtemp())
    assert main(["events", "--clip", "13_29", "--out", str(tmp / "e.jsonl"),
                 "--only", "gesture"]) == 0
    lines = [json.loads(x) for x in (tmp / "e.jsonl").read_text().splitlines()]
    cli = [(f"{e['t']:.2f}", e["gesture"]) for e in lines if e["phase"] == "performed"]
    assert printed == cli


_JOINTS = """
from bodyplay.motion import load_clip
_clip = load_clip("13_29", fps=30)
t, joints, state = 0.0, _clip.joints()[0], ["tracked"] * 17
"""

_CAPTURE = """
import os, tempfile
import numpy as np
from bodyplay.capture.camera import Camera, look_at, write_calib
from bodyplay.capture.video import VideoWriter
os.chdir(tempfile.mkdtemp())
os.makedirs("captures/session1")
_R, _t = look_at((0.0, 1.2, 3.0), (0.0, 1.0, 0.0))
write_calib("captures/session1/calib.json", [Camera.from_fov("cam0", 64, 48, 60.0, _R, _t)])
with VideoWriter("captures/session1/cam0.mp4", 30.0) as _w:
    for _i in range(5):
        _w.write(np.full((48, 64, 3), 40 * _i, np.uint8))
class _Counter:
    frames = 0
    def process(self, frames):
        self.frames += 1
        return frames.index
tracker = _Counter()
"""

_POSES = """
import os, tempfile
from bodyplay.motion import load_clip
from bodyplay.capture import PoseTrack, write_pose_jsonl
from bodyplay.trackers.base import lost_result
os.chdir(tempfile.mkdtemp())
_clip = load_clip("13_29", fps=30).slice(0.0, 0.2)
write_pose_jsonl("poses.jsonl", PoseTrack.from_arrays(range(_clip.num_frames), _clip.times,
                                                   _clip.joints()))
result = lost_result(7, 0.25)
"""

_MESH = """
import numpy as np
from bodyplay.body import Skeleton, body_mesh
from bodyplay.trackers.colorshirt.database import shirt_vertex_mask
from bodyplay.capture.camera import Camera, look_at
_sk = Skeleton()
_mesh = body_mesh(_sk)
vertices = _mesh.pose(_sk, _sk.rest_pose()[None])
faces, face_ids = _mesh.faces, _mesh.face_part.astype(np.uint8)
camera = Camera.from_fov("cam0", 320, 240, 60.0, *look_at((0, 1.2, 3.0), (0, 1.0, 0)))
shirt = shirt_vertex_mask(_mesh)
"""

EXAMPLES: dict[tuple[str, int], Example] = {
    ("README.md", 0): Example(_readme_gestures),
    ("docs/capture.md", 0): Example(
        lambda out: (_has(r"^30\.0 \(Camera\(")(out)), setup=_CAPTURE),
    ("docs/capture.md", 1): Example(_silent, setup=_POSES),
    ("docs/cloth.md", 0): Example(_has(r"^\S+ \S+ \S+$"), setup="""
from bodyplay.motion import load_clip
poses = load_clip("13_29", fps=60).slice(9.0, 0.5).joints()
def draw(positions, faces):
    assert positions.shape[1] == 3 and faces.shape[1] == 3
"""),
    ("docs/colorshirt.md", 0): Example(_silent, slow=True, gl=True, setup="""
import os, tempfile
from bodyplay.cli import main
os.chdir(tempfile.mkdtemp())
assert main(["synth", "--clip", "13_29", "--start", "9", "--frames", "3", "--out", "capture",
             "--size", "320x240"]) == 0
from bodyplay.capture import open_source
source = open_source("capture")
"""),
    ("docs/colorshirt.md", 1): Example(_silent, skip="opens a window for the user to scribble in"),
    ("docs/game-kit.md", 0): Example(_silent),  # defines the game; its main is not called
    ("docs/gestures.md", 0): Example(_silent, setup=_JOINTS),
    ("docs/motion.md", 0): Example(_silent, shared=True, setup=f"""
import os, tempfile
_base = tempfile.mkdtemp()
os.symlink({str(SHARED.parent)!r}, os.path.join(_base, "shared"))
os.mkdir(os.path.join(_base, "work"))
os.chdir(os.path.join(_base, "work"))   # ../shared/data as in a checkout; output stays here
"""),
    ("docs/physics.md", 0): Example(_has(r"^\d+\.\d\d s: [lr]_hand saved ball")),
    ("docs/quickstart.md", 0): Example(_has(r"^player found$", r"^jump performed 100%$",
                                            r"right hand above the head")),
    ("docs/quickstart.md", 1): Example(_silent, setup="""
from bodyplay.runtime import ClipPoseSource, FixedClock, create_session
session = create_session(source=ClipPoseSource("13_29"), clock=FixedClock(1 / 30))
class _Playing:
    polls = 0
    def __bool__(self):  # ten passes of the game loop
        self.polls += 1
        return self.polls <= 10
playing = _Playing()
"""),
    ("docs/quickstart.md", 2): Example(_silent, setup="""
import os
os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
import pygame
pygame.init()
from bodyplay.runtime import ClipPoseSource, create_session
session = create_session(source=ClipPoseSource("13_29"))
"""),
    ("docs/quickstart.md", 3): Example(_silent),
    ("docs/quickstart.md", 4): Example(_has(r"right wrist at \[.*\] \(tracked\)"), slow=True,
                                       gl=True),
    ("docs/reliability.md", 0): Example(_silent, setup="""
import os, tempfile
import numpy as np
path = os.path.join(tempfile.mkdtemp(), "tree.npz")
key = "abc"
def build():
    return {"nodes": np.arange(4)}
"""),
    ("docs/virtual-players.md", 0): Example(_silent, slow=True, gl=True, setup="""
ball_launched_now = False
"""),
    ("docs/render.md", 0): Example(_silent, setup=_MESH),
    ("docs/render.md", 1): Example(_silent, gl=True, setup=_MESH + """
colors = np.full((len(vertices[0]), 3), 0.7, np.float32)
vertices = vertices[0]
photo = np.zeros((480, 640, 3), np.uint8)
camera = Camera.from_fov("cam0", 640, 480, 60.0, *look_at((0, 1.2, 3.0), (0, 1.0, 0)))
sub_frame_times = [0.0, 0.01]
def body_at(t):
    return RenderMesh(vertices, faces, colors, closed=True)
linear_background = np.zeros((480, 640, 3), np.float32)
"""),
    ("docs/smoothing.md", 0): Example(_silent, setup=_JOINTS),
    ("docs/synth.md", 0): Example(_silent, gl=True, slow=True, setup="""
import numpy as np
from bodyplay.body.actor import load_actor as _load
key_poses = _load("m").skeleton.rest_pose()[None]
"""),
    ("docs/synth.md", 1): Example(_silent, gl=True, setup="""
from bodyplay.body.actor import load_actor
from bodyplay.synth import SyntheticCamera, make_synthetic_camera_options
actor = load_actor("m")
opts = make_synthetic_camera_options(cameras=1)
t, pose_vector = 0.0, actor.skeleton.rest_pose()
"""),
}


def _params() -> list[object]:
    out = []
    for doc, i, code in _blocks("python"):
        ex = EXAMPLES.get((doc, i))
        marks: list[pytest.MarkDecorator] = []
        if ex is not None and ex.slow:
            marks.append(pytest.mark.slow)
        if ex is not None and ex.gl:
            marks.append(pytest.mark.gl)
        out.append(pytest.param(doc, i, code, id=f"{doc}#{i}", marks=marks))
    return out


def test_every_python_example_of_the_docs_has_a_check() -> None:
    missing = [(doc, i) for doc, i, _ in _blocks("python") if (doc, i) not in EXAMPLES]
    assert not missing, f"add these examples to EXAMPLES of {__file__}: {missing}"
    stale = set(EXAMPLES) - {(doc, i) for doc, i, _ in _blocks("python")}
    assert not stale, f"EXAMPLES names blocks that no longer exist: {stale}"


@pytest.mark.parametrize(("doc", "index", "code"), _params())
def test_python_example_runs_and_prints_what_it_says(
    doc: str, index: int, code: str, capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch, request: pytest.FixtureRequest,
) -> None:
    ex = EXAMPLES.get((doc, index))
    if ex is None:
        pytest.fail(f"{doc} example {index} has no entry in EXAMPLES")
    if ex.skip:
        pytest.skip(ex.skip)
    if ex.shared and not SHARED.is_dir():
        pytest.skip(f"needs ../shared/data ({SHARED})")
    if ex.gl:
        request.getfixturevalue("synth_gl")
    monkeypatch.chdir(REPO)
    namespace: dict[str, object] = {"__name__": "docs_example"}
    exec(compile(ex.setup, f"{doc} setup", "exec"), namespace)
    capsys.readouterr()
    source = code.replace('"clip.bvh"', '"13_29"')
    exec(compile(source, f"{doc} example {index}", "exec"), namespace)
    ex.check(capsys.readouterr().out)


def _command_lines() -> list[tuple[str, str]]:
    lines = []
    for doc, _, block in _blocks("sh") + _blocks(""):
        joined = re.sub(r"\\\n\s*", " ", block)
        for line in joined.splitlines():
            line = line.split("#", 1)[0].strip()
            if line.startswith("bodyplay "):
                lines.append((doc, line))
    return lines


@pytest.mark.parametrize(("doc", "line"), _command_lines())
def test_command_line_example_parses(doc: str, line: str) -> None:
    from bodyplay.cli import build_parser

    argv = shlex.split(line)[1:]
    # ``[--pck 5 10]``-style usage summaries list choices, not a command to type
    argv = [a for a in argv if not a.startswith("[") and not a.endswith("]") and "|" not in a]
    try:
        build_parser().parse_args(argv)
    except SystemExit as exc:  # argparse reports a bad example on stderr
        pytest.fail(f"{doc}: `{line}` does not parse (exit {exc.code})")
