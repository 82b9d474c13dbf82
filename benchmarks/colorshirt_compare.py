"""Compare tags of the color-shirt validation set, clip by clip (issue 24).

``colorshirt_validation.py`` appends one row per (tag, clip, setting, seconds, draw)
to a JSONL file. Deciding whether a change earns its place means setting its rows
beside main's on the same captures: per setting the median, the worst clip and the
mean of the clips both tags ran (a clip without any pose has no MPJPE: it is counted
apart), how many clips got better or worse by more than a threshold, and the share
of frames with a pose (median and fewest), which a change may buy or sell against
the error. Rows may come from several files (a helper's and
the lead's), so every helper compares the same way.

    .venv/bin/python benchmarks/colorshirt_compare.py --results A.jsonl,B.jsonl \\
        --base d1-main-91e415a --tags my-change --draw 1 [--threshold 0.2]

Only clips that both the base and a tag ran in a setting count; the table says how
many. ``--settings`` limits the settings; ``--per-clip`` also lists every clip.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Comparison:
    """One tag against the base in one setting, over the clips both ran."""

    setting: str
    tag: str
    clips: int
    base: tuple[float, float, float]  # median, worst, mean of the clips' MPJPE (cm)
    new: tuple[float, float, float]
    better: int
    worse: int
    lost: tuple[int, int]  # clips without any pose: base, tag
    found_base: tuple[float, float]  # median, fewest share of frames with a pose
    found_new: tuple[float, float]
    per_clip: tuple[tuple[str, float, float], ...]  # (clip, base cm, new cm)


def load_rows(paths: list[Path]) -> list[dict[str, Any]]:
    """Every row of the JSONL files (missing files are an error: a typo is not a zero)."""
    rows: list[dict[str, Any]] = []
    for path in paths:
        if not path.exists():
            raise SystemExit(f"{path}: no such results file; give the --results that "
                             "colorshirt_validation.py wrote")
        rows += [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return rows


def _by_clip(rows: list[dict[str, Any]], tag: str, setting: str, draw: int
             ) -> dict[str, dict[str, Any]]:
    """The last row of each clip for this tag, setting and draw."""
    return {r["clip"]: r for r in rows if r["tag"] == tag and r["setting"] == setting
            and r.get("draw", 0) == draw}


def _stats(values: list[float]) -> tuple[float, float, float]:
    """Median, worst and mean of the clips with a pose (a clip without any has no
    MPJPE: it is counted in ``lost`` instead)."""
    a = np.asarray(values, float)
    a = a[np.isfinite(a)]
    if not len(a):
        return float("nan"), float("nan"), float("nan")
    return float(np.median(a)), float(a.max()), float(a.mean())


def compare(rows: list[dict[str, Any]], base: str, tag: str, setting: str, draw: int = 0,
            threshold: float = 0.2) -> Comparison | None:
    """``tag`` against ``base`` in ``setting`` over the clips both ran (None: none)."""
    old, new = _by_clip(rows, base, setting, draw), _by_clip(rows, tag, setting, draw)
    clips = sorted(set(old) & set(new))
    if not clips:
        return None
    b = [float(old[c]["mpjpe_cm"]) for c in clips]
    n = [float(new[c]["mpjpe_cm"]) for c in clips]
    fb = [float(old[c]["found"]) for c in clips]
    fn = [float(new[c]["found"]) for c in clips]
    return Comparison(
        setting, tag, len(clips), _stats(b), _stats(n),
        better=sum(y < x - threshold for x, y in zip(b, n, strict=True)),
        worse=sum(y > x + threshold for x, y in zip(b, n, strict=True)),
        lost=(sum(not np.isfinite(x) for x in b), sum(not np.isfinite(y) for y in n)),
        found_base=(float(np.median(fb)), min(fb)), found_new=(float(np.median(fn)), min(fn)),
        per_clip=tuple(zip(clips, b, n, strict=True)))


def table(comparisons: list[Comparison], base: str, threshold: float) -> list[str]:
    """Markdown lines: one row per (setting, tag)."""
    lines = [f"| setting | tag | clips | {base}: median / worst / mean (cm) | tag: median / "
             f"worst / mean | better / worse by > {threshold:g} cm | clips without a pose "
             "(base -> tag) | pose on frames, median / fewest (base -> tag) |",
             "|---|---|---|---|---|---|---|---|"]
    for c in comparisons:
        lines.append(
            f"| {c.setting} | {c.tag} | {c.clips} | {c.base[0]:.2f} / {c.base[1]:.2f} / "
            f"{c.base[2]:.2f} | {c.new[0]:.2f} / {c.new[1]:.2f} / {c.new[2]:.2f} | "
            f"{c.better} / {c.worse} | {c.lost[0]} -> {c.lost[1]} | "
            f"{100 * c.found_base[0]:.0f} / {100 * c.found_base[1]:.0f} -> "
            f"{100 * c.found_new[0]:.0f} / {100 * c.found_new[1]:.0f}% |")
    return lines


def main(argv: list[str] | None = None) -> int:
    """Print the comparison table of ``--tags`` against ``--base``."""
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", required=True, help="comma-separated JSONL files")
    ap.add_argument("--base", required=True, help="the tag to compare against (main)")
    ap.add_argument("--tags", required=True, help="comma-separated tags to compare")
    ap.add_argument("--draw", type=int, default=0)
    ap.add_argument("--settings", default="", help="only these settings (comma-separated)")
    ap.add_argument("--threshold", type=float, default=0.2,
                    help="a clip counts as better / worse beyond this many cm")
    ap.add_argument("--per-clip", action="store_true", help="also list every clip")
    args = ap.parse_args(argv)
    rows = load_rows([Path(p) for p in args.results.split(",")])
    settings = (args.settings.split(",") if args.settings else
                sorted({r["setting"] for r in rows if r["tag"] == args.base
                        and r.get("draw", 0) == args.draw}))
    if not settings:
        print(f"no rows of tag {args.base!r} in draw {args.draw}; tags there: "
              + ", ".join(sorted({r['tag'] for r in rows if r.get('draw', 0) == args.draw})))
        return 1
    found = [c for s in settings for t in args.tags.split(",")
             if (c := compare(rows, args.base, t, s, args.draw, args.threshold)) is not None]
    print("\n".join(table(found, args.base, args.threshold)))
    if args.per_clip:
        for c in found:
            print(f"\n{c.setting} {c.tag}:")
            for clip, b, n in c.per_clip:
                print(f"  {clip:48s} {b:6.2f} -> {n:6.2f} ({n - b:+.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
