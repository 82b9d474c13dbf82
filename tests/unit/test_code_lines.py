"""Specifications of the code-line count (tools/code_lines.py)."""

from __future__ import annotations

from collections.abc import Callable
from types import ModuleType

import pytest


@pytest.fixture(scope="module")
def counter(script_loader: Callable[..., ModuleType]) -> ModuleType:
    return script_loader("tools/code_lines.py")


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
