"""``python -m apps.ninja``: the ninja gesture fight (see docs/ninja.md).

By default the embedded virtual ninja is filmed by the synthetic camera and tracked
(``--tracker``, default the silhouette tracker of the paper when installed, else the
color shirt); ``--headless --out DIR`` writes DIR/ninja.mp4 and DIR/summary.json.
"""

from __future__ import annotations

import argparse
from typing import Any

from bodyplay.app import game_argument_parser, game_main

__all__ = ["main", "default_tracker"]

_STYLES = ("fighter", "idle", "wrong", "still")


def default_tracker() -> str:
    """``silhouette`` (the paper's setup) when that tracker is installed, else
    ``colorshirt`` (the virtual actor wears the shirt either way)."""
    from bodyplay.plugins import PluginRegistry

    try:
        names = PluginRegistry().names("trackers")
    except Exception:  # a broken plugin list must not stop the game
        return "colorshirt"
    return "silhouette" if "silhouette" in names else "colorshirt"


def main(argv: list[str] | None = None) -> int:
    """Run the game; returns the exit code."""
    from apps.ninja.game.game import NinjaGame

    tracker = default_tracker()
    parser = game_argument_parser("ninja", __doc__.splitlines()[0], default_tracker=tracker)
    parser.add_argument("--player", choices=_STYLES, default="fighter",
                        help="how the virtual ninja plays (idle/wrong/still: to see losing)")

    def configure(args: argparse.Namespace) -> dict[str, Any]:
        return {"player_style": args.player}

    return game_main(NinjaGame, argv, name="ninja", description=__doc__.splitlines()[0],
                     default_tracker=tracker, parser=parser, configure=configure)


if __name__ == "__main__":
    raise SystemExit(main())
