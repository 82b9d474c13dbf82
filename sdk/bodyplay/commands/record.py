"""``bodyplay record``: record a session (poses, events, optionally frames) to JSON lines.

The recording survives the process being killed at any moment (see
:mod:`bodyplay.record`); play it back with ``bodyplay replay`` or export it with
``bodyplay export``.
"""

from __future__ import annotations

import argparse
import sys

from bodyplay.commands._session_args import add_session_arguments, session_from_args
from bodyplay.plugins import PluginRegistry
from bodyplay.record.recorder import RecorderOptions, record_session

__all__ = ["register", "run"]


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``record`` sub-command."""
    p = subparsers.add_parser(
        "record",
        help="record a session to a crash-safe JSON-lines file",
        description="Run a session and record its header, poses and events (and with "
        "--frames, the camera images) to REC.",
    )
    add_session_arguments(p)
    p.add_argument("--out", required=True, metavar="REC", help="recording file (.jsonl)")
    p.add_argument("--frames", choices=("none", "png", "jpeg"), default="none",
                   help="also save camera frames next to the recording (--input only)")
    p.add_argument("--fsync", choices=("never", "line", "interval"), default="interval",
                   help="how often to force lines to disk (default: once a second)")
    p.add_argument("--max-frames", type=int, default=None, help="stop after this many frames")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Record until the input ends (or --max-frames); print what was written."""
    registry = PluginRegistry()
    session = session_from_args(args, registry)
    opts = RecorderOptions(fsync=args.fsync, frames=args.frames, overwrite=args.force)
    meta = {"clip": args.clip, "input": args.input, "tracker": args.tracker,
            "gestures": args.gestures, "filters": list(args.filter)}
    with record_session(session, args.out, opts, meta=meta) as rec, session:
        session.run(args.max_frames)
    print(f"recorded {session.frames} frames ({rec.lines} lines) to {rec.path}",
          file=sys.stderr)
    return 0
