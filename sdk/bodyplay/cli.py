"""The ``bodyplay`` command line.

Each sub-command lives in its own module under :mod:`bodyplay.commands`; a module
there exposes ``register(subparsers)`` which adds its parser and sets
``func=run`` (a callable taking the parsed namespace and returning an exit code).
Commands are discovered at start-up, so adding one never touches this file.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys
from collections.abc import Sequence

from bodyplay.errors import BodyplayError

__all__ = ["build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    """Build the top-level parser with every sub-command found in bodyplay.commands."""
    parser = argparse.ArgumentParser(
        prog="bodyplay",
        description="Motion capture from webcams as game input: synth, track, eval, demo, ...",
    )
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    subparsers.required = True
    import bodyplay.commands as commands_pkg

    for info in sorted(pkgutil.iter_modules(commands_pkg.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"bodyplay.commands.{info.name}")
        register = getattr(module, "register", None)
        if register is not None:
            register(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the process exit code.

    Errors the user can fix (:class:`bodyplay.errors.BodyplayError`) are printed as one
    line on stderr with exit code 2, never as a traceback.
    """
    parser = build_parser()
    args = parser.parse_args(list(argv) if argv is not None else None)
    try:
        return int(args.func(args) or 0)
    except BodyplayError as exc:
        print(f"bodyplay {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"bodyplay {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
