"""Specifications of the code-line count (tools/code_lines.py)."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def counter() -> ModuleType:
    spec = importlib.util.spec_from_file_location("code_lines", REPO / "tools" / "code_lines.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_code_lines_skips_docstrings_comments_and_blank_lines(counter: ModuleType) -> None:
    source = ('"""Module.\n\nMore prose.\n"""\n\n# a comment\nimport os\n\n\n'
              'def f(x: int) -> int:\n    """What f does."""\n    return x + 1  # why\n')
    assert counter.code_lines(source) == 3


def test_code_lines_counts_a_multiline_string_that_is_not_a_docstring(counter: ModuleType) -> None:
    source = 'import os\nTEXT = """one\ntwo\n"""\n'
    assert counter.code_lines(source) == 4


def test_moving_a_docstrings_prose_out_does_not_change_the_count(counter: ModuleType) -> None:
    long = ('def f() -> None:\n    """What.\n\n    Why, at length,\n    over lines.\n'
            '    """\n    pass\n')
    short = 'def f() -> None:\n    """What."""\n    pass\n'
    assert counter.code_lines(long) == counter.code_lines(short) == 2


def test_main_without_files_says_how_to_call_it(
        counter: ModuleType, capsys: pytest.CaptureFixture[str]) -> None:
    assert counter.main([]) == 2
    assert "usage" in capsys.readouterr().err
