"""The machine a benchmark ran on, printed beside its figures (DESIGN.md: Measuring).

Shared by the scripts in this folder (run as ``.venv/bin/python benchmarks/NAME.py``,
which puts this folder on ``sys.path``) so they all describe the machine the same way.
"""

from __future__ import annotations

import os
import platform
from pathlib import Path

__all__ = ["cpu_model", "machine"]


def cpu_model() -> str:
    """The CPU model name from /proc/cpuinfo, else what :mod:`platform` knows."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def machine() -> str:
    """CPU model, core count and Python version, for the record."""
    return f"{cpu_model()}, {os.cpu_count()} cores, Python {platform.python_version()}"
