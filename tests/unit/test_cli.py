"""Specifications of the ``bodyplay`` command line itself (bodyplay.cli): every command
module in bodyplay/commands is reachable and documented, and user errors are one line."""

from __future__ import annotations

import argparse
import importlib
import re
from pathlib import Path

import pytest

import bodyplay.commands
from bodyplay.cli import main

COMMANDS_DIR = Path(bodyplay.commands.__file__).parent


def _command_modules() -> list[str]:
    """Every module file in bodyplay/commands, except ``_private`` helpers."""
    return sorted(p.stem for p in COMMANDS_DIR.glob("*.py") if not p.stem.startswith("_"))


def _names_registered_by(module_name: str) -> list[str]:
    """The sub-command names a command module adds, asked of the module itself."""
    module = importlib.import_module(f"bodyplay.commands.{module_name}")
    register = getattr(module, "register", None)
    if register is None:  # the CLI silently skips such a module
        return []
    subparsers = argparse.ArgumentParser().add_subparsers()
    register(subparsers)
    return sorted(subparsers.choices)


COMMAND_NAMES = {m: _names_registered_by(m) for m in _command_modules()}


def test_the_commands_folder_is_found_and_holds_the_core_commands() -> None:
    # guards the discovery: an empty or wrong folder would make the tests below vacuous
    names = {n for ns in COMMAND_NAMES.values() for n in ns}
    assert {"synth", "eval", "demo"} <= names
    assert len(COMMAND_NAMES) >= 10


@pytest.mark.parametrize("module_name", sorted(COMMAND_NAMES))
def test_every_command_module_registers_a_sub_command(module_name: str) -> None:
    assert COMMAND_NAMES[module_name], f"bodyplay/commands/{module_name}.py adds no sub-command"


def test_top_level_help_lists_every_command_module(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    listed = set(re.findall(r"^ {4}(\S+)", out, flags=re.MULTILINE))
    for module_name, names in COMMAND_NAMES.items():
        for name in names:
            assert name in listed, f"{name} ({module_name}.py) missing from bodyplay --help"


@pytest.mark.parametrize("command", sorted(n for ns in COMMAND_NAMES.values() for n in ns))
def test_every_command_help_exits_zero_with_usage(
    command: str, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as exc:
        main([command, "--help"])
    assert exc.value.code == 0
    captured = capsys.readouterr()
    assert captured.out.startswith(f"usage: bodyplay {command}")
    assert captured.err == ""


def test_a_user_error_exits_2_with_one_line_and_no_traceback(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    truth = tmp_path / "missing.jsonl"
    rc = main(["eval", "--truth", str(truth), "--poses", str(tmp_path / "poses.jsonl")])
    assert rc == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("bodyplay eval: error: ")
    assert str(truth) in lines[0]  # says which file was wrong
    assert "Traceback" not in captured.err


def test_a_misspelled_command_exits_2_with_usage_and_no_traceback(
    capsys: pytest.CaptureFixture[str],
) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["evall"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: bodyplay") and "invalid choice: 'evall'" in err
    assert "Traceback" not in err


def test_python_dash_m_bodyplay_runs_the_command_line() -> None:
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-m", "bodyplay", "--help"], capture_output=True,
                          text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert "usage: bodyplay" in done.stdout and "track" in done.stdout
