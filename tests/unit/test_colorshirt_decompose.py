"""Specifications of the validation's error decomposition (benchmarks/colorshirt_decompose.py)."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

import pytest


@pytest.fixture(scope="module")
def decompose(script_loader: Callable[..., ModuleType]) -> ModuleType:
    return script_loader("benchmarks/colorshirt_decompose.py")


def _row(errors: list[float], cameras: list[int], clip: str = "c") -> dict[str, object]:
    """A result row whose frames have every joint at ``errors[k]`` cm."""
    frames = [[k, *([e] * 11), n] for k, (e, n) in enumerate(zip(errors, cameras, strict=True))]
    return {"tag": "t", "setting": "steady-2-view", "clip": clip, "capture": clip,
            "body": "m", "per_frame": frames}


def test_decompose_takes_away_the_first_frame_and_the_lone_camera_frames(decompose) -> None:  # type: ignore[no-untyped-def]
    errors = [100.0] + [4.0] * 39 + [60.0] * 10 + [4.0] * 40
    cameras = [2] * 40 + [1] * 10 + [2] * 40
    k, e, n = decompose._frames(_row(errors, cameras))
    fn = decompose.causes(2, 15.0)
    assert fn["nothing"](k, e, n) == pytest.approx(sum(errors) / len(errors))
    # the first frame alone at the others' mean (60 cm on 10 frames remain)
    rest = (4.0 * 79 + 600.0) / 89
    assert fn["the first frame"](k, e, n) == pytest.approx((rest + 4.0 * 79 + 600.0) / 90)
    assert fn["frames with one camera's pixels"](k, e, n) == pytest.approx(
        (100.0 + 4.0 * 79 + 10 * (100.0 + 4.0 * 79) / 80) / 90)
    assert fn["the head's error by the neck's"](k, e, n) == pytest.approx(
        fn["nothing"](k, e, n))  # every joint equal here


def test_decompose_prints_the_table_of_a_tag_and_says_when_there_is_none(
        decompose, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:  # type: ignore[no-untyped-def]
    res = tmp_path / "results.jsonl"
    res.write_text("\n".join(json.dumps(_row([5.0, 6.0], [2, 2], c)) for c in "ab") + "\n")
    assert decompose.main(["--results", str(res), "--tag", "t"]) == 0
    out = capsys.readouterr().out
    assert "| a |" in out and "| the first frame |" in out
    assert decompose.main(["--results", str(res), "--tag", "other"]) == 1
    assert "no rows" in capsys.readouterr().out
