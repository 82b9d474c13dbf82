"""``bodyplay events``: run a session headless and write every event as a JSON line.

Each line is one event's ``Event.to_json()``: its ``type``, ``t`` (capture time),
``emitted_t`` (session clock, fixed-step so the output is reproducible) and fields.
"""

from __future__ import annotations

import argparse
import sys
from collections import Counter

from bodyplay.commands._session_args import add_session_arguments, session_from_args
from bodyplay.events.types import Event
from bodyplay.plugins import PluginRegistry
from bodyplay.record.recorder import EventLogWriter, RecorderOptions

__all__ = ["register", "run"]


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``events`` sub-command."""
    p = subparsers.add_parser(
        "events",
        help="turn a clip or a capture into game events (JSON lines)",
        description="Run a session headless and write its events (pose, tracking, gesture, "
        "...) one JSON object per line.",
    )
    add_session_arguments(p)
    p.add_argument("--out", required=True, help="output events.jsonl ('-' for stdout)")
    p.add_argument("--only", action="append", default=None, metavar="NAME",
                   help="write only these event names (repeatable)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run the session to the end of its input; print a count per event type."""
    registry = PluginRegistry()
    session = session_from_args(args, registry)
    counts: Counter[str] = Counter()
    names = tuple(args.only) if args.only else session.bus.names
    for n in names:
        session.bus.subscribe(n, lambda e: counts.update([e.name]))
    if args.out == "-":
        from bodyplay.record.format import event_line

        def write(e: Event) -> None:
            sys.stdout.write(event_line(e).decode())

        for n in names:
            session.bus.subscribe(n, write)
        with session:
            session.run()
    else:
        opts = RecorderOptions(fsync="never", overwrite=args.force)
        with EventLogWriter(args.out, opts).attach(session.bus, names), session:
            session.run()
    summary = ", ".join(f"{n} {c}" for n, c in sorted(counts.items()))
    print(f"{session.frames} frames -> {summary or 'no events'}", file=sys.stderr)
    return 0
