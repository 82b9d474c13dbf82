"""``bodyplay colors fit``: fit the color-shirt color model (ten RGB Gaussians).

From synthetic renders (``--synthetic``: the actor in the shirt, labeled by its
rasterized patch id map; renders under colored lighting presets are first
white-balanced onto a neutral-light fit) or from photos of a real shirt with
scribble masks (``--scribbles photo.png:mask.png ...``: each scribble painted in the
nominal sRGB of its patch color, see docs/colorshirt.md). Writes a JSON model that
``bodyplay track --color-model`` (or ``ColorShirtOptions.color_model``) reads.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from bodyplay.errors import ConfigError

__all__ = ["register", "run"]


def register(subparsers: Any) -> None:
    """Add the ``colors`` sub-command (with its ``fit`` action)."""
    p = subparsers.add_parser(
        "colors", help="fit the color-shirt color model", description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = p.add_subparsers(dest="action", metavar="ACTION")
    sub.required = True
    f = sub.add_parser("fit", help="fit ten Gaussians to labeled shirt pixels")
    src = f.add_mutually_exclusive_group(required=True)
    src.add_argument("--synthetic", action="store_true",
                     help="label pixels of synthetic renders by their id maps")
    src.add_argument("--scribbles", nargs="+", metavar="PHOTO:MASK",
                     help="photo and scribble-mask image pairs of a white-balanced shirt")
    f.add_argument("--poses", type=int, default=36, help="synthetic poses to render")
    f.add_argument("--lightings", default="steady,tungsten,fluorescent,dim,mixed",
                   help="synthetic lighting presets, comma-separated (first fit: steady)")
    f.add_argument("--seed", type=int, default=0)
    f.add_argument("--out", required=True, help="JSON file to write")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Fit the model and write it; print per-color means and self-classification."""
    from bodyplay.body.shirt import SHIRT_COLORS
    from bodyplay.trackers.colorshirt.colorfit import scribble_samples, synthetic_color_samples
    from bodyplay.trackers.colorshirt.colors import ColorModel

    if args.synthetic:
        lights = [x.strip() for x in args.lightings.split(",") if x.strip()]
        px, lab = synthetic_color_samples(args.poses, seed=args.seed)
        if lights != ["steady"]:
            reference = ColorModel.fit(px, lab)
            parts = [(px, lab)]
            for i, name in enumerate(x for x in lights if x != "steady"):
                parts.append(synthetic_color_samples(max(6, args.poses // 3), lighting=name,
                                                     seed=args.seed + 100 + i,
                                                     reference=reference))
            px = np.concatenate([p for p, _ in parts])
            lab = np.concatenate([lb for _, lb in parts])
    else:
        pairs = []
        for item in args.scribbles:
            if ":" not in item:
                raise ConfigError(f"{item!r}: give scribbles as PHOTO:MASK")
            a, b = item.split(":", 1)
            pairs.append((a, b))
        px, lab = scribble_samples(pairs)
    model = ColorModel.fit(px, lab)
    out = model.save(Path(args.out))
    ids = model.classify(px.reshape(-1, 1, 3).clip(0, 255).astype(np.uint8)).ids.ravel()
    for k, c in enumerate(SHIRT_COLORS):
        sel = lab == k
        acc = float(np.mean(ids[sel] == k + 1)) if sel.any() else float("nan")
        mu = ", ".join(f"{v:.0f}" for v in model.means[k])
        print(f"{c.name:8s} n={int(sel.sum()):6d} mean=({mu}) classified-correctly={acc:.3f}")
    print(f"wrote {out} from {len(lab)} labeled pixels")
    return 0
