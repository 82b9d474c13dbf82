"""The identity check of an exact speed change: two runs' joints compared.

Shared by ``colorshirt_speed.py`` and ``silhouette_bench.py`` (``--poses`` saves a
run's joints per capture, ``--compare`` checks them against another commit's).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def compare_poses(new: dict[str, NDArray[np.float64]], old: dict[str, NDArray[np.float64]]
                  ) -> str:
    """Per capture in both, the largest joint difference (m) and the frames whose
    found/lost state differs: 0 and 0 when a change left the poses identical."""
    lines = []
    for key in sorted(set(new) & set(old)):
        a, b = new[key], old[key]
        if a.shape != b.shape:
            lines.append(f"{key}: {len(a)} frames against {len(b)}")
            continue
        state = int(np.count_nonzero((np.isnan(a) != np.isnan(b)).any(axis=(1, 2))))
        both = np.isfinite(a) & np.isfinite(b)
        diff = float(np.max(np.abs(a - b)[both])) if both.any() else 0.0
        lines.append(f"{key}: max joint difference {diff:.3g} m, joints reported differ on "
                     f"{state} of {len(a)} frames")
    missing = sorted(set(old) - set(new))
    if missing:
        lines.append(f"not run here: {', '.join(missing)}")
    return "\n".join(lines)
