"""Files written safely: whole or not at all, and caches that know what made them.

Two helpers every module that writes files should use:

* :func:`atomic_write` opens a temporary file beside the target and renames it over
  the target only when the ``with`` block ends without an error (after an
  ``fsync``), so a crash, a full disk or a bad input never leaves a half-written
  file under the final name; a failed write removes the temporary file.
* :func:`save_cache` / :func:`load_cache` store numpy arrays as an ``.npz`` with a
  stamp (what the cache is, the key of everything that shaped it, bodyplay's version
  and the cache's format version). :func:`load_cache` returns None, never stale data,
  when the file is missing, damaged, would need pickle, or was made by another
  version or for other inputs (another body, other options); the caller rebuilds.

Example::

    from bodyplay.files import load_cache, save_cache

    arrays = load_cache(path, kind="silhouette_tree", key=key, version=2)
    if arrays is None:
        arrays = build(...)                       # dict of numpy arrays
        save_cache(path, arrays, kind="silhouette_tree", key=key, version=2)

Nothing is ever loaded with pickle (``allow_pickle=False``).
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import tempfile
import zipfile
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import IO, Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["atomic_write", "save_cache", "load_cache", "default_cache_dir", "CACHE_STAMP"]

_log = logging.getLogger("bodyplay.files")

CACHE_STAMP = "__bodyplay_cache__"
"""Name of the array in a cache ``.npz`` that holds its stamp (JSON, as uint8 bytes)."""


def default_cache_dir() -> Path:
    """``$BODYPLAY_CACHE`` or ``~/.cache/bodyplay``: where built caches live."""
    env = os.environ.get("BODYPLAY_CACHE")
    return Path(env) if env else Path.home() / ".cache" / "bodyplay"


def _package_version() -> str:
    from bodyplay import __version__

    return __version__


@contextlib.contextmanager
def atomic_write(path: str | Path, mode: str = "wb") -> Iterator[IO[Any]]:
    """Write ``path`` whole or not at all: yields a file object on a temporary file in
    the same folder, renamed over ``path`` when the block ends without an error.

    ``mode`` is ``"wb"`` or ``"w"`` (text, UTF-8). The folder is created if missing.
    """
    if mode not in ("wb", "w"):
        raise ValueError(f"atomic_write mode must be 'wb' or 'w', got {mode!r}")
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".partial", dir=target.parent)
    try:
        fh: IO[Any] = os.fdopen(fd, mode, encoding="utf-8" if mode == "w" else None)
        with fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _stamp(kind: str, key: str, version: int) -> dict[str, Any]:
    return {"kind": kind, "key": key, "version": int(version), "bodyplay": _package_version()}


def save_cache(
    path: str | Path, arrays: Mapping[str, NDArray[Any]], *, kind: str, key: str, version: int
) -> Path:
    """Write ``arrays`` (compressed ``.npz``) with their stamp, atomically."""
    if CACHE_STAMP in arrays:
        raise ValueError(f"{CACHE_STAMP!r} is reserved for the cache's stamp")
    for name, a in arrays.items():
        if np.asarray(a).dtype == object:
            raise ValueError(f"cache array {name!r} holds Python objects; store numbers only")
    stamp = np.frombuffer(json.dumps(_stamp(kind, key, version)).encode(), np.uint8)
    p = Path(path)
    with atomic_write(p) as fh:
        payload: dict[str, Any] = {CACHE_STAMP: stamp, **arrays}
        np.savez_compressed(fh, **payload)
    return p


def load_cache(
    path: str | Path, *, kind: str, key: str, version: int
) -> dict[str, NDArray[Any]] | None:
    """The arrays of a cache written by :func:`save_cache` for exactly these inputs, or
    None (logged) when it is missing, damaged, unstamped or stamped for something else."""
    p = Path(path)
    if not p.is_file():
        return None
    want = _stamp(kind, key, version)
    try:
        with np.load(p, allow_pickle=False) as z:
            if CACHE_STAMP not in z.files:
                _log.info("%s: cache without a stamp (an older bodyplay); rebuilding", p)
                return None
            got = json.loads(bytes(z[CACHE_STAMP]).decode())
            if got != want:
                _log.info("%s: cache made for %s, not %s; rebuilding", p, got, want)
                return None
            return {k: z[k] for k in z.files if k != CACHE_STAMP}
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile,
            UnicodeDecodeError) as exc:
        _log.warning("%s: damaged cache (%s); rebuilding", p, exc)
        return None
