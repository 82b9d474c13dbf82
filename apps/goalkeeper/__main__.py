"""``python -m apps.goalkeeper``: play a round (see ``--help``)."""

from __future__ import annotations

import argparse
from typing import Any

from apps.goalkeeper.game import GoalkeeperGame, GoalkeeperOptions
from bodyplay.app import game_argument_parser, game_main

__all__ = ["main"]


def _parser() -> argparse.ArgumentParser:
    p = game_argument_parser("goalkeeper", "Block the shots with your hands, arms, body, head.")
    p.add_argument("--shots", type=int, default=20, help="shots in the round (default 20)")
    p.add_argument("--virtual-poses", action="store_true",
                   help="the virtual keeper as poses, without camera or tracker (fast)")
    return p


def _configure(args: argparse.Namespace) -> dict[str, Any]:
    return {"options": GoalkeeperOptions(shots=args.shots),
            "virtual_poses": args.virtual_poses}


def main(argv: list[str] | None = None) -> int:
    """Run the game; returns the exit code."""
    return game_main(GoalkeeperGame, argv, name="goalkeeper", parser=_parser(),
                     configure=_configure)


if __name__ == "__main__":
    raise SystemExit(main())
