"""Specifications of bodyplay.motion.bvh: tolerant reading, clear errors, FK, writing."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import BVHError
from bodyplay.motion import builtin_clip_path, read_bvh, write_bvh

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"
MOCAP = DATA / "mocap"
SHARED_BVH = sorted(MOCAP.glob("*/*.bvh")) if MOCAP.is_dir() else []

SMALL = """HIERARCHY
ROOT Hips
{
\tOFFSET 0 0 0
\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
\tJOINT Arm
\t{
\t\tOFFSET 10 0 0
\t\tCHANNELS 3 Yrotation Zrotation Xrotation
\t\tEnd Site
\t\t{
\t\t\tOFFSET 5 0 0
\t\t}
\t}
}
MOTION
Frames: {frames}
Frame Time: 0.0333333
{rows}
"""


def _small(tmp_path: Path, rows: list[str], frames: int | None = None, crlf: bool = False) -> Path:
    text = SMALL.replace("{frames}", str(len(rows) if frames is None else frames))
    text = text.replace("{rows}", "\n".join(rows))
    if crlf:
        text = text.replace("\n", "\r\n")
    p = tmp_path / "walk.bvh"
    p.write_bytes(text.encode())
    return p


ROWS = ["0 0 0 0 0 0 0 0 0", "1 2 3 90 0 0 0 0 0", "0 0 0 30 40 50 60 70 80"]


@pytest.mark.parametrize("path", SHARED_BVH, ids=lambda p: p.name)
def test_read_bvh_reads_every_shared_mocap_file(path: Path) -> None:
    clip = read_bvh(path)
    cmu = path.parent.name == "cmu"
    assert clip.num_joints == (31 if cmu else 22)
    assert clip.fps == pytest.approx(120.0 if cmu else 30.0)
    assert clip.motion.shape == (clip.num_frames, sum(len(c) for c in clip.channels))
    P = clip.world_positions(slice(0, 50), include_end_sites=True)
    assert P.shape == (min(50, clip.num_frames), clip.num_joints + len(clip.end_sites), 3)
    assert np.all(np.isfinite(P))


def test_shared_mocap_is_present_or_skipped() -> None:
    if not SHARED_BVH:
        pytest.skip("../shared/data/mocap is absent")
    assert any(p.parent.name == "bandai_namco" for p in SHARED_BVH)


def test_world_positions_follow_the_channel_order(tmp_path: Path) -> None:
    clip = read_bvh(_small(tmp_path, ROWS))
    assert clip.channels[0][3:] == ("Zrotation", "Xrotation", "Yrotation")
    P = clip.world_positions(include_end_sites=True)
    assert np.allclose(P[0], [[0, 0, 0], [10, 0, 0], [15, 0, 0]])
    # Zrotation 90 at the root turns the arm from +X to +Y; root moved by (1, 2, 3)
    assert np.allclose(P[1, 1], [1, 12, 3], atol=1e-9)
    r_root = Rotation.from_euler("ZXY", [30, 40, 50], degrees=True)
    r_arm = Rotation.from_euler("YZX", [60, 70, 80], degrees=True)
    expect_end = r_root.apply([10, 0, 0]) + (r_root * r_arm).apply([5, 0, 0])
    assert np.allclose(P[2, 2], expect_end, atol=1e-9)


def test_read_bvh_warns_and_uses_the_frames_present_when_header_declares_fewer(
    tmp_path: Path,
) -> None:
    path = _small(tmp_path, ROWS, frames=len(ROWS) - 1)
    with pytest.warns(UserWarning, match="declares 2 frames but the file holds 3"):
        clip = read_bvh(path)
    assert clip.num_frames == 3


def test_read_bvh_warns_when_header_declares_more_frames(tmp_path: Path) -> None:
    with pytest.warns(UserWarning, match="declares 4 frames"):
        assert read_bvh(_small(tmp_path, ROWS, frames=4)).num_frames == 3


def test_read_bvh_tolerates_crlf_tabs_and_blank_lines(tmp_path: Path) -> None:
    rows = [ROWS[0], "", "\t".join(ROWS[1].split()), "   ", ROWS[2], ""]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        clip = read_bvh(_small(tmp_path, rows, frames=3, crlf=True))
    assert clip.num_frames == 3
    assert clip.names == ("Hips", "Arm")
    assert clip.end_sites[0].parent == 1


def test_read_bvh_names_file_line_and_joint_for_a_short_frame(tmp_path: Path) -> None:
    path = _small(tmp_path, [ROWS[0], "1 2 3 4"])
    with pytest.raises(
        BVHError, match=r"walk\.bvh:20: expected 6 numbers for the channels of Hips"
    ):
        read_bvh(path)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (
            lambda t: t.replace("0 0 0 0 0 0 0 0 0", "0 0 0 0 x 0 0 0 0"),
            r"walk\.bvh:19: 'x' is not",
        ),
        (lambda t: t.replace("Yrotation Zrotation", "Yrotation Wobble"), r":9: .*'Wobble'"),
        (lambda t: t.replace("MOTION", "MOTON"), r":16: unexpected 'MOTON'"),
        (lambda t: t.replace("OFFSET 10 0 0", "OFFSET 10 zero 0"), r":8: expected a number"),
        (lambda t: t.replace("OFFSET 10 0 0", "OFFSET 10 nan 0"), r":8: expected a finite"),
        (lambda t: t.replace("OFFSET 5 0 0", "OFFSET inf 0 0"), r":12: expected a finite"),
        (lambda t: t.replace("Frame Time: 0.0333333", "Frame Time: 0"), r":18: 'Frame Time'"),
        (lambda t: t.replace("HIERARCHY", "HIERARCHIE"), r":1: a BVH file starts"),
        (lambda t: t.split("MOTION")[0] + "MOTION\nFrames: 0\nFrame Time: 0.1\n", r"no frames"),
    ],
)
def test_read_bvh_rejects_malformed_input_naming_the_line(
    tmp_path: Path, edit: object, message: str
) -> None:
    path = _small(tmp_path, ROWS)
    path.write_text(edit(path.read_text()))  # type: ignore[operator]
    with pytest.raises(BVHError, match=message):
        read_bvh(path)


def test_read_bvh_reports_a_missing_file(tmp_path: Path) -> None:
    with pytest.raises(BVHError, match="no such BVH file"):
        read_bvh(tmp_path / "nope.bvh")


def test_read_bvh_reads_the_gzip_compressed_builtin_clips() -> None:
    clip = read_bvh(builtin_clip_path("131_03"))
    assert clip.num_joints == 31 and clip.fps == 120.0
    assert builtin_clip_path("131_03").stat().st_size < 5_000_000


def test_write_bvh_then_read_bvh_gives_the_same_forward_kinematics(tmp_path: Path) -> None:
    sk = Skeleton.from_shape("xl")
    rng = np.random.default_rng(3)
    lo, hi = sk.limits
    q = rng.uniform(np.maximum(lo, -3), np.minimum(hi, 3), (20, sk.pose_dim))
    q[:, 0:3] = rng.normal(0, 1, (20, 3))
    path = write_bvh(tmp_path / "out.bvh", sk, q, fps=30)
    clip = read_bvh(path)
    assert clip.fps == pytest.approx(30.0) and clip.num_frames == 20
    P = clip.world_positions(include_end_sites=True) / 100.0
    nodes = sk.node_positions(q)
    order = [sk.node_names.index(n) for n in clip.names]
    assert np.allclose(P[:, : clip.num_joints], nodes[:, order], atol=1e-5)
    ends = [sk.node_names.index(n) for n in ("head_top", "l_hand", "r_hand", "l_toe", "r_toe")]
    assert np.allclose(P[:, clip.num_joints :], nodes[:, ends], atol=1e-5)
