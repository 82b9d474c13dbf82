"""Evaluation of poses against truth: MPJPE, PCK, misses, frame matching, CLI."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.capture import PoseTrack, write_pose_jsonl
from bodyplay.cli import main
from bodyplay.errors import ConfigError
from bodyplay.evaluation import evaluate, plot_errors

N = 60
FPS = 30.0


@pytest.fixture
def truth() -> PoseTrack:
    rng = np.random.default_rng(7)
    t = np.arange(N) / FPS
    base = rng.normal(0, 0.2, (17, 3)) + [0, 1, 0]
    wave = 0.1 * np.sin(2 * np.pi * t)[:, None, None] * np.ones((1, 17, 3))
    return PoseTrack.from_arrays(np.arange(N), t, base + wave)


def shifted(track: PoseTrack, d: np.ndarray, **kw: object) -> PoseTrack:
    return PoseTrack.from_arrays(track.frames, track.t, track.joints + d, **kw)  # type: ignore[arg-type]


def test_truth_against_itself_scores_zero(truth: PoseTrack) -> None:
    r = evaluate(truth, truth, joints="all")
    assert r.mpjpe_cm == pytest.approx(0.0, abs=1e-9)
    assert r.pck5 == 1.0 and r.pck10 == 1.0
    assert r.frames_tracked == 1.0 and r.joints_tracked == 1.0
    assert r.jitter_ms2 == pytest.approx(r.truth_jitter_ms2)


def test_shift_of_three_cm_scores_three_cm(truth: PoseTrack) -> None:
    est = shifted(truth, np.array([0.0, 0.03, 0.0]))
    r = evaluate(truth, est, joints="upper", thresholds_cm=(2, 5, 10))
    assert r.mpjpe_cm == pytest.approx(3.0, rel=1e-9)
    assert all(v == pytest.approx(3.0) for v in r.per_joint_cm.values())
    assert r.pck == {2.0: 0.0, 5.0: 1.0, 10.0: 1.0}
    assert len(r.joints) == 11
    assert r.jitter_ms2 == pytest.approx(r.truth_jitter_ms2)  # a constant offset adds none


def test_noise_raises_jitter_above_the_truths(truth: PoseTrack) -> None:
    noise = np.random.default_rng(0).normal(0, 0.01, truth.joints.shape)
    r = evaluate(truth, shifted(truth, noise))
    # second difference of 1 cm white noise: sqrt(6) cm per frame^2 per axis
    assert r.jitter_ms2 > 5 * r.truth_jitter_ms2


def test_null_joints_count_as_missed_never_as_zero_error(truth: PoseTrack) -> None:
    joints = truth.joints + np.array([0.04, 0, 0])
    joints[:30, JOINT_INDEX["l_wrist"]] = np.nan
    r = evaluate(truth, PoseTrack.from_arrays(truth.frames, truth.t, joints), joints="upper")
    assert r.mpjpe_cm == pytest.approx(4.0)  # misses did not pull the mean towards 0
    assert r.per_joint_tracked["l_wrist"] == pytest.approx(0.5)
    assert r.joints_tracked == pytest.approx(1 - 30 / (N * 11))
    assert r.frames_tracked == pytest.approx(0.5)
    assert r.pck5 == pytest.approx(1 - 30 / (N * 11))
    assert r.frame_missed[:30].tolist() == [1] * 30 and r.frame_missed[30:].sum() == 0
    # a joint the tracker cannot see at all is NaN, not 0
    joints[:, JOINT_INDEX["r_wrist"]] = np.nan
    r = evaluate(truth, PoseTrack.from_arrays(truth.frames, truth.t, joints))
    assert np.isnan(r.per_joint_cm["r_wrist"]) and r.per_joint_tracked["r_wrist"] == 0.0


def test_frames_are_matched_by_number_and_missing_ones_are_misses(truth: PoseTrack) -> None:
    keep = np.arange(10, N)  # the tracker started late ...
    extra_frames = np.concatenate([keep, [N + 5]])  # ... and wrote a frame the truth lacks
    joints = np.concatenate([truth.joints[keep], truth.joints[:1]]) + np.array([0, 0, 0.02])
    est = PoseTrack.from_arrays(extra_frames, extra_frames / FPS, joints, ms=np.full(51, 8.0))
    r = evaluate(truth, est, joints="all")
    assert r.n_matched_frames == 50 and r.n_missing_frames == 10 and r.n_extra_frames == 1
    assert r.mpjpe_cm == pytest.approx(2.0)
    assert r.frames_tracked == pytest.approx(50 / 60) and r.pck5 == pytest.approx(50 / 60)
    assert r.ms_median == 8.0
    assert np.all(np.isnan(r.frame_error_cm[:10])) and r.frame_missed[:10].tolist() == [17] * 10


def test_unknown_joint_set_is_a_config_error(truth: PoseTrack) -> None:
    with pytest.raises(ConfigError, match="joints"):
        evaluate(truth, truth, joints="legs")  # type: ignore[arg-type]


def test_plot_draws_an_image(truth: PoseTrack, tmp_path: Path) -> None:
    joints = truth.joints.copy()
    joints[5:9] = np.nan
    r = evaluate(truth, PoseTrack.from_arrays(truth.frames, truth.t, joints + 0.01))
    img = cv2.imread(str(plot_errors(r, tmp_path / "e.png")))
    assert img is not None and img.shape == (360, 900, 3)
    red = (img[..., 2] > 150) & (img[..., 1] < 80) & (img[..., 0] < 80)
    assert red.sum() > 0  # missed frames are marked


def test_cli_json_round_trip(truth: PoseTrack, tmp_path: Path, capsys: pytest.CaptureFixture[str]
                             ) -> None:
    tpath = write_pose_jsonl(tmp_path / "truth.jsonl", truth, state=False, ms=False)
    est = shifted(truth, np.array([0.03, 0.0, 0.0]), ms=np.full(N, 11.0))
    ppath = write_pose_jsonl(tmp_path / "poses.jsonl", est)
    code = main(["eval", "--truth", str(tpath), "--poses", str(ppath), "--joints", "all",
                 "--json", "--plot", str(tmp_path / "e.png")])
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["mpjpe_cm"] == pytest.approx(3.0, abs=1e-3)
    assert summary["pck"] == {"5": 1.0, "10": 1.0}
    assert summary["ms_median"] == 11.0 and len(summary["per_joint_cm"]) == 17
    assert (tmp_path / "e.png").exists()
    assert main(["eval", "--truth", str(tpath), "--poses", str(ppath)]) == 0
    table = capsys.readouterr().out
    assert "MPJPE" in table and "3.00 cm" in table and "r_wrist" in table


def test_cli_reports_a_missing_file_as_an_error(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["eval", "--truth", str(tmp_path / "t.jsonl"), "--poses", "x"]) == 2
    assert "no such pose file" in capsys.readouterr().err
