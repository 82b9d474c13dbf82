"""The quickstart's Python examples run as written (with a built-in clip for clip.bvh)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

QUICKSTART = Path(__file__).resolve().parents[2] / "docs" / "quickstart.md"


def _python_blocks() -> list[str]:
    text = QUICKSTART.read_text()
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


def _runnable(block: str) -> bool:
    # fragments that need a game loop or a pygame window are shown, not run
    return "while playing" not in block and "pygame.event.get" not in block


def _run(block: str) -> None:
    code = block.replace('"clip.bvh"', '"13_29"')
    exec(compile(code, str(QUICKSTART), "exec"), {"__name__": "quickstart"})


@pytest.mark.parametrize(
    "block", [b for b in _python_blocks() if _runnable(b) and "SyntheticCamera" not in b]
)
def test_quickstart_pose_level_example_runs(block: str, capsys: pytest.CaptureFixture[str]) -> None:
    _run(block)


@pytest.mark.slow
@pytest.mark.gl
@pytest.mark.parametrize("block", [b for b in _python_blocks() if "SyntheticCamera" in b])
def test_quickstart_synthetic_camera_example_runs(block: str) -> None:
    _run(block)
