"""Safe files: atomic writes, stamped caches, no pickle anywhere."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
import zipfile
from pathlib import Path

import numpy as np
import pytest

from bodyplay.body.skeleton import Skeleton
from bodyplay.files import CACHE_STAMP, atomic_write, load_cache, save_cache
from bodyplay.trackers.colorshirt.database import (
    DatabaseOptions,
    PoseDatabase,
    load_or_build_database,
)

SDK = Path(__file__).resolve().parents[2] / "sdk"
STAMP = {"kind": "thing", "key": "abc", "version": 1}


def test_atomic_write_replaces_the_file_only_when_the_block_succeeds(tmp_path: Path) -> None:
    p = tmp_path / "out.json"
    p.write_text("old")
    with pytest.raises(RuntimeError), atomic_write(p, "w") as fh:
        fh.write("half of the new")
        raise RuntimeError("disk full")
    assert p.read_text() == "old" and os.listdir(tmp_path) == ["out.json"]
    with atomic_write(p, "w") as fh:
        fh.write("new")
    assert p.read_text() == "new" and os.listdir(tmp_path) == ["out.json"]


def test_cache_round_trips_and_is_refused_when_made_for_other_inputs(tmp_path: Path) -> None:
    p = tmp_path / "c.npz"
    save_cache(p, {"a": np.arange(5)}, **STAMP)  # type: ignore[arg-type]
    got = load_cache(p, **STAMP)  # type: ignore[arg-type]
    assert got is not None and np.array_equal(got["a"], np.arange(5))
    assert load_cache(p, kind="thing", key="other body", version=1) is None
    assert load_cache(p, kind="thing", key="abc", version=2) is None
    assert load_cache(p, kind="other", key="abc", version=1) is None
    assert load_cache(tmp_path / "missing.npz", **STAMP) is None  # type: ignore[arg-type]


def test_cache_from_another_bodyplay_version_is_refused(tmp_path: Path) -> None:
    p = tmp_path / "c.npz"
    stamp = {**STAMP, "bodyplay": "0.0.1"}
    np.savez(p, a=np.arange(3), **{CACHE_STAMP: np.frombuffer(json.dumps(stamp).encode(),
                                                                np.uint8)})
    assert load_cache(p, **STAMP) is None  # type: ignore[arg-type]


@pytest.mark.parametrize("damage", ["truncated", "garbage", "pickled", "unstamped", "empty"])
def test_damaged_or_pickled_cache_loads_as_none_never_as_data(tmp_path: Path, damage: str) -> None:
    p = tmp_path / "c.npz"
    save_cache(p, {"a": np.arange(1000)}, **STAMP)  # type: ignore[arg-type]
    raw = p.read_bytes()
    if damage == "truncated":
        p.write_bytes(raw[: len(raw) // 2])
    elif damage == "garbage":
        p.write_bytes(b"\x00not a zip" * 50)
    elif damage == "empty":
        p.write_bytes(b"")
    elif damage == "unstamped":
        np.savez(p, a=np.arange(3))
    else:  # an object array can only be read with pickle
        stamp = np.frombuffer(json.dumps({**STAMP, "bodyplay": _version()}).encode(), np.uint8)
        with zipfile.ZipFile(p, "w") as z:
            for name, arr in ((CACHE_STAMP, stamp), ("a", np.array([{"x": 1}], dtype=object))):
                with z.open(f"{name}.npy", "w") as fh:
                    np.lib.format.write_array(fh, arr, allow_pickle=True)
    assert load_cache(p, **STAMP) is None  # type: ignore[arg-type]


def _version() -> str:
    from bodyplay import __version__

    return __version__


def test_no_module_loads_numpy_files_with_pickle_allowed() -> None:
    offenders = []
    for path in sorted(SDK.rglob("*.py")):
        text = path.read_text()
        for m in re.finditer(r"np\.load\(", text):
            call = text[m.start():].split("\n", 2)  # the call's line and the next
            if "allow_pickle=False" not in "".join(call[:2]):
                offenders.append(f"{path.relative_to(SDK)}: {call[0]}")
        assert "import pickle" not in text, path
    assert not offenders, offenders


def _src(sk, n, rng, o):  # type: ignore[no-untyped-def]
    q = np.repeat(sk.rest_pose()[None], n, axis=0)
    q[:, 3:] += rng.normal(0.0, 0.3, q[:, 3:].shape)
    return q


@pytest.mark.slow  # two bodies' meshes and databases: about 50 s here
def test_pose_database_cache_of_another_body_or_version_is_rebuilt_not_trusted(
    tmp_path: Path,
) -> None:
    o = DatabaseOptions(size=40, pca_dims=8, candidates=16)
    tall = load_or_build_database(Skeleton.from_shape("l"), o, tmp_path / "a", pose_source=_src)
    short = load_or_build_database(Skeleton.from_shape("s"), o, tmp_path / "b", pose_source=_src)
    (tall_file,) = (tmp_path / "a").glob("colorshirt_db_*.npz")
    (short_file,) = (tmp_path / "b").glob("colorshirt_db_*.npz")
    assert tall_file.name != short_file.name
    # the tall body's cache under the short body's name: detected, rebuilt for the short body
    short_file.write_bytes(tall_file.read_bytes())
    with pytest.raises(ValueError, match="not a pose database"):
        PoseDatabase.load(short_file, o, key="not the tall body's key")
    again = load_or_build_database(Skeleton.from_shape("s"), o, tmp_path / "b", pose_source=_src)
    assert np.array_equal(again.ids, short.ids) and not np.array_equal(again.ids, tall.ids)
    key = short_file.stem.split("_")[-1]
    assert PoseDatabase.load(short_file, o, key=key) is not None  # rewritten, short body's stamp


@pytest.mark.slow
def test_build_db_killed_while_saving_leaves_no_cache_and_the_next_run_builds_it(
    tmp_path: Path,
) -> None:
    cmd = [sys.executable, "-m", "bodyplay.cli", "build-db", "--size", "1000",
           "--cache", str(tmp_path)]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 300
        while time.monotonic() < deadline and proc.poll() is None:
            if list(tmp_path.glob(".colorshirt_db_*.partial")):
                os.kill(proc.pid, signal.SIGKILL)  # in the middle of writing the cache
                break
            time.sleep(0.002)
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.wait()
    assert proc.returncode == -signal.SIGKILL, "the build ended before it could be killed"
    assert not list(tmp_path.glob("colorshirt_db_*.npz"))  # nothing under the final name
    assert subprocess.run(cmd, capture_output=True).returncode == 0
    (final,) = tmp_path.glob("colorshirt_db_*.npz")
    assert np.load(final, allow_pickle=False)["poses"].shape[0] == 1000
