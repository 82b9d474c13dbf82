"""``python -m apps.ninja``: the ninja gesture fight (see docs/ninja.md).

By default the embedded virtual ninja is filmed by the synthetic camera and tracked
by the color-shirt tracker (``--tracker silhouette`` is the paper's: the ninja then
steps into view after a second of the empty room; see docs/ninja.md for why it is
not the default yet); ``--headless --out DIR`` writes DIR/ninja.mp4 and
DIR/summary.json.
"""

from __future__ import annotations

import argparse
from typing import Any

from bodyplay.app import game_argument_parser, game_main

__all__ = ["main", "default_tracker"]

_STYLES = ("fighter", "idle", "wrong", "still")


def default_tracker() -> str:
    """The tracker a run uses unless ``--tracker`` says otherwise: ``colorshirt``.

    The paper's silhouette tracker is installed and selectable (with the game's own
    hierarchy and an empty-room start), and on the virtual ninja it now follows the
    body: crouch and both side steps are recognized. It does not follow the arms:
    transfigure, hit and double hit are never recognized on silhouette-tracked input
    (``benchmarks/ninja_gestures.py --tracker silhouette``, docs/ninja.md), so the
    fight never starts. The game keeps the tracker that wins the fight until it does.
    """
    return "colorshirt"


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
