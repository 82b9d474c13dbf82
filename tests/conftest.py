"""Shared fixtures: paths to the shared data, a skeleton, temporary output folders."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED_DATA = REPO.parent / "shared" / "data"


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """../shared/data, or skip the test cleanly when it is absent."""
    if not SHARED_DATA.is_dir():
        pytest.skip(f"shared data not found at {SHARED_DATA}")
    return SHARED_DATA


@pytest.fixture(scope="session")
def skeleton():  # type: ignore[no-untyped-def]
    """The reference 1.75 m skeleton."""
    from bodyplay.body import Skeleton

    return Skeleton()
