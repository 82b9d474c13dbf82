"""Frames as every source yields them and every tracker consumes them."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["Frame", "FrameSet"]


@dataclass(frozen=True, eq=False)
class Frame:
    """One image from one camera.

    ``image`` is ``(height, width, 3)`` uint8 in **RGB** order (sources convert from
    OpenCV's BGR). ``t`` is the capture time in seconds since the first frame of the
    source, ``index`` the 0-based frame number in the source, ``camera`` the camera
    name as in calib.json.
    """

    image: NDArray[np.uint8]
    t: float
    index: int
    camera: str = "cam0"

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) in pixels."""
        return int(self.image.shape[1]), int(self.image.shape[0])


@dataclass(frozen=True, eq=False)
class FrameSet:
    """Synchronized frames from every camera of a rig at one instant."""

    frames: tuple[Frame, ...]
    t: float
    index: int

    def __len__(self) -> int:
        return len(self.frames)

    def __iter__(self) -> Iterator[Frame]:
        return iter(self.frames)

    def __getitem__(self, i: int) -> Frame:
        return self.frames[i]
