"""Where the color-shirt tracker's validation error comes from, per clip and per cause.

Reads the rows ``colorshirt_validation.py`` appended to its results (each keeps,
per scored frame with a pose, the eleven upper-body joints' errors and how many
cameras' pixels counted) and prints, for one tag and setting:

* per clip: the MPJPE, the first scored frame's error, the first second's and
  the rest's, the frames fitted from one camera's pixels in a rig of several
  (and their error), the frames where the chest is off by more than
  ``--clutter-cm`` (a fit of the room, not the player), and the share of the
  error carried by the torso, the head, the elbows and the wrists;
* per cause: the half's median, mean and worst clip when the frames of that
  cause get the clip's other frames' mean error (a joint's error replaced by
  another joint's for the head and the arms): how much fixing that cause alone
  could give, and which cause is the largest.

    .venv/bin/python benchmarks/colorshirt_decompose.py --tag TAG --setting steady-2-view
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

FPS = 30
TORSO, HEAD, ELBOWS, WRISTS = [0, 1, 2, 3, 5, 8], [4], [6, 9], [7, 10]
"""Indices of the upper-body joints (pelvis .. r_wrist) per group."""


def _frames(row: dict[str, Any]) -> tuple[NDArray[np.int64], NDArray[np.float64],
                                            NDArray[np.int64]]:
    """Frame numbers, (F, 11) joint errors (cm) and cameras counted of a result row."""
    pf = np.asarray(row["per_frame"], np.float64).reshape(-1, 13)
    return pf[:, 0].astype(np.int64), pf[:, 1:12], pf[:, 12].astype(np.int64)


def _replaced(mean: NDArray[np.float64], mask: NDArray[np.bool_]) -> float:
    """Mean of ``mean`` with the frames of ``mask`` set to the other frames' mean."""
    if not mask.any() or mask.all():
        return float(mean.mean())
    out = mean.copy()
    out[mask] = mean[~mask].mean()
    return float(out.mean())


def causes(cameras: int, clutter_cm: float
           ) -> dict[str, Callable[[NDArray[np.int64], NDArray[np.float64],
                                    NDArray[np.int64]], float]]:
    """Per cause, the clip's MPJPE (cm) with that cause's error taken away."""
    def joints(src: list[int], dst: list[int]) -> Callable[..., float]:
        def f(k: NDArray[np.int64], e: NDArray[np.float64], n: NDArray[np.int64]) -> float:
            e = e.copy()
            e[:, dst] = e[:, src]
            return float(e.mean())
        return f

    def frames(pick: Callable[..., NDArray[np.bool_]]) -> Callable[..., float]:
        def f(k: NDArray[np.int64], e: NDArray[np.float64], n: NDArray[np.int64]) -> float:
            return _replaced(e.mean(axis=1), pick(k, e, n))
        return f

    return {
        "nothing": lambda k, e, n: float(e.mean()),
        "the first frame": frames(lambda k, e, n: k == 0),
        "the first second": frames(lambda k, e, n: k < FPS),
        "frames with one camera's pixels": frames(lambda k, e, n: n < cameras),
        "frames fitting the room (chest off, or one camera)": frames(
            lambda k, e, n: (e[:, 2] > clutter_cm) | (n < cameras)),
        "the head's error by the neck's": joints([3], [4]),
        "elbows and wrists by the shoulders": joints([5, 5, 8, 8], [6, 7, 9, 10]),
    }


def main(argv: list[str] | None = None) -> int:
    """Print the per-clip table and the per-cause summary of one tag and setting."""
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", default="/work/cache-colorshirt/results.jsonl")
    ap.add_argument("--tag", required=True)
    ap.add_argument("--setting", default="steady-2-view")
    ap.add_argument("--clutter-cm", type=float, default=15.0)
    args = ap.parse_args(argv)
    path = Path(args.results)
    if not path.exists():
        print(f"{path}: no results; run colorshirt_validation.py first")
        return 1
    rows = [r for r in map(json.loads, path.read_text().splitlines())
            if r["tag"] == args.tag and r["setting"] == args.setting and r.get("per_frame")]
    if not rows:
        print(f"no rows of tag {args.tag!r} and setting {args.setting!r} with per-frame "
              "errors (re-run colorshirt_validation.py with a new tag)")
        return 1
    cams = int(args.setting.split("-")[1])
    print(f"# {args.tag}, {args.setting}, {len(rows)} clips")
    print("| clip | capture | MPJPE | first frame | first second / rest | one camera's "
          "pixels (their error) | room fitted | torso / head / elbows / wrists share | body |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        k, e, n = _frames(r)
        m = e.mean(axis=1)
        first = k < FPS
        lone = n < cams
        room = (e[:, 2] > args.clutter_cm) | lone
        f0 = f"{m[k == 0][0]:.1f}" if (k == 0).any() else "lost"
        share = [e[:, g].sum() / e.sum() for g in (TORSO, HEAD, ELBOWS, WRISTS)]
        fs = f"{m[first].mean():.1f}" if first.any() else "-"
        rest = f"{m[~first].mean():.1f}" if (~first).any() else "-"
        lo = f"{lone.sum()} ({m[lone].mean():.0f})" if lone.any() else "0"
        print(f"| {r['clip']} | {r['capture']} | {m.mean():.2f} | {f0} | {fs} / {rest} | {lo} | "
              f"{room.mean():.0%} | " + " / ".join(f"{x:.2f}" for x in share)
              + f" | {r['body']} |")
    print("\n| error taken away | median | mean | worst clip |\n|---|---|---|---|")
    for name, fn in causes(cams, args.clutter_cm).items():
        v = np.array([fn(*_frames(r)) for r in rows])
        print(f"| {name} | {np.median(v):.2f} | {v.mean():.2f} | {v.max():.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
