"""Specifications of the color-shirt commands: colors fit, build-db; the scribble tool."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
from colorshirt_paint import clutter, paint_shirt

from bodyplay.body.shirt import SHIRT_COLORS
from bodyplay.cli import main
from bodyplay.trackers.colorshirt.colorfit import scribble_labels
from bodyplay.trackers.colorshirt.colors import ColorModel


def test_scribble_labels_decode_painted_colors_and_ignore_black() -> None:
    mask = np.zeros((2, 3, 3), np.uint8)
    mask[0, 0] = SHIRT_COLORS[4].rgb
    mask[1, 2] = np.clip(np.array(SHIRT_COLORS[9].rgb) - 10, 0, 255)
    lab = scribble_labels(mask)
    assert lab[0, 0] == 4 and lab[1, 2] == 9 and lab[0, 1] == -1


def test_colors_fit_from_scribbled_photos_writes_a_model(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(0)
    pairs = []
    sums = np.zeros((10, 3))
    counts = np.zeros(10)
    for i in range(2):
        img = clutter(200, 200, rng)
        labels = paint_shirt(img, 20, 10, 30, rng)
        mask = np.zeros_like(img)
        on = labels >= 0
        mask[on] = np.array([c.rgb for c in SHIRT_COLORS], np.uint8)[labels[on]]
        mask[::2] = 0  # scribbles need not cover the patches
        scribbled = labels.copy()
        scribbled[::2] = -1
        for k in range(10):
            sums[k] += img[scribbled == k].sum(axis=0)
            counts[k] += (scribbled == k).sum()
        a, b = tmp_path / f"p{i}.png", tmp_path / f"m{i}.png"
        cv2.imwrite(str(a), cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
        cv2.imwrite(str(b), cv2.cvtColor(mask, cv2.COLOR_RGB2BGR))
        pairs.append(f"{a}:{b}")
    out = tmp_path / "model.json"
    assert main(["colors", "fit", "--scribbles", *pairs, "--out", str(out)]) == 0
    model = ColorModel.load(out)
    assert np.allclose(model.means, sums / counts[:, None], atol=0.01)
    assert "wrote" in capsys.readouterr().out


def test_colors_fit_rejects_malformed_scribble_pairs(tmp_path: Path) -> None:
    assert main(["colors", "fit", "--scribbles", "nocolon", "--out", str(tmp_path / "m.json")]) == 2


def test_build_db_command_caches_a_database(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    assert main(["build-db", "--size", "60", "--cache", str(tmp_path)]) == 0
    assert len(list(tmp_path.glob("colorshirt_db_60_*.npz"))) == 1
    assert "60 poses" in capsys.readouterr().out


def test_scribble_tool_imports_without_opening_a_window() -> None:
    from bodyplay.trackers.colorshirt import scribble

    assert callable(scribble.scribble_white_balance) and callable(scribble.collect_scribbles)
