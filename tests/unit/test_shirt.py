"""Specifications of the color shirt layout and the printable pattern command."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import cv2
import numpy as np

from bodyplay.body.shirt import NUM_COLORS, PATCHES, SHIRT_COLORS, patch_color_index
from bodyplay.cli import main

FRONT_SET = {
    "torso_front_upper_left", "torso_front_upper_right", "torso_front_lower_left",
    "torso_front_lower_right", "l_upper_arm_front", "r_upper_arm_front", "l_forearm_front",
    "r_forearm_front", "l_shoulder_cap", "r_shoulder_cap",
}


def test_each_of_the_ten_colors_is_used_exactly_twice() -> None:
    counts = Counter(p.color for p in PATCHES)
    assert len(SHIRT_COLORS) == NUM_COLORS == 10
    assert sorted(counts) == list(range(10))
    assert set(counts.values()) == {2}


def test_patch_ids_are_one_to_twenty() -> None:
    assert sorted(p.id for p in PATCHES) == list(range(1, 21))
    assert patch_color_index()[0] == -1


def test_front_set_and_back_set_each_use_all_ten_colors() -> None:
    front = [p.color for p in PATCHES if p.name in FRONT_SET]
    back = [p.color for p in PATCHES if p.name not in FRONT_SET]
    assert sorted(front) == list(range(10))
    assert sorted(back) == list(range(10))


def test_bodyplay_shirt_writes_a_png_with_every_color(tmp_path: Path) -> None:
    out = tmp_path / "shirt.png"
    assert main(["shirt", "--out", str(out)]) == 0
    img = cv2.imread(str(out))
    assert img is not None and img.shape[0] >= 1000 and img.shape[1] >= 1300
    pixels = img.reshape(-1, 3)
    for c in SHIRT_COLORS:
        bgr = np.array(c.rgb[::-1])
        assert np.sum(np.all(pixels == bgr, axis=1)) > 2000, c.name


def test_bodyplay_shirt_rejects_a_non_image_file_name(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    assert main(["shirt", "--out", str(tmp_path / "shirt.txt")]) == 2
    assert ".png" in capsys.readouterr().err
