"""``python -m apps.cloth_mirror``: the avatar wears a simulated garment and mirrors you.

By default the embedded virtual player (the CMU 13_29 jumping jacks) is filmed by the
synthetic camera and tracked (``--tracker``: the silhouette tracker of the paper when
installed, else the color shirt); ``--input pose:13_29`` skips the tracking;
``--headless --out DIR`` writes DIR/cloth_mirror.mp4 and DIR/summary.json.
"""

from __future__ import annotations

import argparse
from typing import Any

from bodyplay.app import game_argument_parser, game_main, preferred_tracker
from bodyplay.cloth import GARMENTS

__all__ = ["main", "default_tracker"]


def default_tracker() -> str:
    """``silhouette`` (the paper's cloth demo) when that tracker is installed, else
    ``colorshirt`` (the virtual actor wears the shirt either way)."""
    return preferred_tracker("silhouette")


def main(argv: list[str] | None = None) -> int:
    """Run the cloth mirror; returns the exit code."""
    from apps.cloth_mirror.game.game import ClothMirrorGame

    tracker = default_tracker()
    title = __doc__.splitlines()[0]
    parser = game_argument_parser("cloth_mirror", title, default_tracker=tracker)
    parser.add_argument("--garment", choices=tuple(GARMENTS), default="robe",
                        help="what the avatar wears (default robe)")
    parser.add_argument("--wind", type=float, default=0.0,
                        help="wind towards the mirror, m/s (default 0)")

    def configure(args: argparse.Namespace) -> dict[str, Any]:
        return {"garment_name": args.garment, "wind": args.wind}

    return game_main(ClothMirrorGame, argv, name="cloth_mirror", description=title,
                     default_tracker=tracker, parser=parser, configure=configure)


if __name__ == "__main__":
    raise SystemExit(main())
