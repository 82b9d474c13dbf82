"""One command line for every game: :func:`game_main`.

``python -m apps.<game> [--input ...] [--tracker ...] [--cameras 1|2] [--seconds S]
[--seed N] [--headless] [--out DIR] [--width W --height H] [--no-video]`` plays
the game, writes ``DIR/<name>.mp4`` and ``DIR/summary.json``, prints where they
are and returns the exit code. Errors the user can fix are printed as one line
naming the embedded default (``--input virtual``), never as a traceback.
"""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from bodyplay.app.game import Game
from bodyplay.app.options import VIRTUAL_INPUT, make_game_options
from bodyplay.app.runner import run_game
from bodyplay.errors import BodyplayError

__all__ = ["game_main", "game_argument_parser", "preferred_tracker"]


def preferred_tracker(*names: str, fallback: str = "colorshirt") -> str:
    """The first of ``names`` that is installed as a tracker plugin, else ``fallback``.

    A game states the tracker it was designed for (``preferred_tracker("silhouette")``)
    and still starts where that plugin is missing or the plugin list is broken.
    """
    from bodyplay.plugins import PluginRegistry

    try:
        installed = set(PluginRegistry().names("trackers"))
    except Exception:  # a broken plugin list must not stop the game
        return fallback
    return next((n for n in names if n in installed), fallback)


def game_argument_parser(name: str, description: str = "", *,
                         default_tracker: str = "colorshirt") -> argparse.ArgumentParser:
    """The argument parser every game shares (games may add their own options)."""
    p = argparse.ArgumentParser(prog=f"python -m apps.{name}", description=description)
    p.add_argument("--input", default=VIRTUAL_INPUT, metavar="SRC",
                   help="virtual (default: the embedded virtual player, no camera needed), "
                        "a webcam index (0), a capture folder, a video, a recording "
                        "*.jsonl, or pose:CLIP (a mocap clip fed as poses, no images)")
    p.add_argument("--tracker", default=default_tracker,
                   help=f"tracker for image input (default {default_tracker})")
    p.add_argument("--cameras", type=int, default=1, choices=(1, 2),
                   help="synthetic cameras filming the virtual player (default 1)")
    p.add_argument("--seconds", type=float, default=None,
                   help="seconds of game time to play (default: a whole round)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the game (default 0)")
    p.add_argument("--headless", action="store_true",
                   help="no window: render offscreen (EGL) and write the video")
    p.add_argument("--out", default=f"out/{name}", metavar="DIR",
                   help=f"folder of {name}.mp4 and summary.json (default out/{name})")
    p.add_argument("--width", type=int, default=640)
    p.add_argument("--height", type=int, default=480)
    p.add_argument("--no-video", action="store_true", help="do not write the video")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    return p


def game_main(
    game_factory: Callable[..., Game],
    argv: Sequence[str] | None = None,
    *,
    name: str | None = None,
    description: str = "",
    default_tracker: str = "colorshirt",
    parser: argparse.ArgumentParser | None = None,
    configure: Callable[[argparse.Namespace], dict[str, Any]] | None = None,
) -> int:
    """Parse ``argv``, build the game with ``game_factory(**configure(args))`` (or
    ``game_factory()``), run it and print where the files are; return the exit code
    (0 ok, 2 bad input or options, 130 interrupted).

    ``parser`` may be one made by :func:`game_argument_parser` with the game's own
    options added; ``configure`` turns the parsed arguments into the factory's
    keyword arguments.
    """
    game_name = name or getattr(game_factory, "name", None) or "game"
    p = parser or game_argument_parser(game_name, description, default_tracker=default_tracker)
    args = p.parse_args(list(argv) if argv is not None else None)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    try:
        options = make_game_options(
            input=args.input, tracker=args.tracker, cameras=args.cameras, seconds=args.seconds,
            seed=args.seed, headless=True if args.headless else None, out=Path(args.out),
            width=args.width, height=args.height, video=not args.no_video,
            progress=not args.no_progress,
        )
        game = game_factory(**(configure(args) if configure else {}))
        result = run_game(game, options)
    except BodyplayError as exc:
        print(f"{p.prog}: error: {exc}", file=sys.stderr)
        if "--input virtual" not in str(exc):
            print(f"{p.prog}: the embedded virtual player needs no camera: --input virtual",
                  file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"{p.prog}: interrupted", file=sys.stderr)
        return 130
    s = result.summary
    timing = s.get("timing", {})
    print(f"{game_name}: {s.get('frames', 0)} frames, {s.get('game_seconds', 0):.1f} s of game "
          f"in {timing.get('wall_seconds', 0):.1f} s ({timing.get('frames_per_second', 0)} fps)")
    headline = getattr(game, "headline", None)
    if callable(headline):
        print(headline(result.context))
    if result.video_path is not None:
        print(f"{'video':>8}: {result.video_path.resolve()}")
    if result.summary_path is not None:
        print(f"{'summary':>8}: {result.summary_path.resolve()}")
    for label, path in getattr(game, "extra_files", lambda ctx: {})(result.context).items():
        print(f"{label:>8}: {Path(path).resolve()}")
    return 0
