"""``truth.jsonl`` and ``poses.jsonl``: per-frame joint positions as JSON lines.

One JSON object per line (DESIGN.md): ``{"frame": 12, "t": 0.4, "joints": {"pelvis":
[x, y, z] | null, ...}}``; ``poses.jsonl`` adds ``"state"`` per joint (``tracked``,
``inferred`` or ``lost``) and ``"ms"``. :class:`PoseTrack` holds a whole file as
arrays so that evaluation and plotting stay vectorised. Reading tolerates a
truncated last line (a recorder stopped mid-write) and is strict otherwise: any
malformed line raises :class:`~bodyplay.errors.CaptureError` naming its number.
"""

from __future__ import annotations

import json
import math
import os
import warnings
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import IO, Any, Self

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.joints import JOINT_INDEX, JOINT_NAMES, NUM_JOINTS
from bodyplay.errors import CaptureError, reading
from bodyplay.files import atomic_write

__all__ = ["PoseTrack", "PoseJsonlWriter", "read_pose_jsonl", "write_pose_jsonl", "JOINT_STATES"]

JOINT_STATES: tuple[str, ...] = ("tracked", "inferred", "lost")
"""The per-joint states a poses.jsonl record may give."""


@dataclass(frozen=True, eq=False)
class PoseTrack:
    """Joint positions over a sequence of frames (a truth or a tracker's output).

    ``frames`` (N,) int: strictly increasing 0-based frame numbers of the capture;
    ``t`` (N,) seconds; ``joints`` (N, 17, 3) world metres in JOINT_NAMES order, NaN
    where a joint was not reported; ``state`` (N, 17) strings in JOINT_STATES (a joint
    without coordinates is always ``lost``); ``ms`` (N,) processing time, NaN where
    the file gives none.
    """

    frames: NDArray[np.int64]
    t: NDArray[np.float64]
    joints: NDArray[np.float64]
    state: NDArray[np.str_]
    ms: NDArray[np.float64]

    def __post_init__(self) -> None:
        frames = np.asarray(self.frames, dtype=np.int64).reshape(-1)
        n = frames.size
        t = np.asarray(self.t, dtype=np.float64).reshape(-1)
        joints = np.asarray(self.joints, dtype=np.float64)
        if n == 0:
            joints = joints.reshape(0, NUM_JOINTS, 3)
        state = np.asarray(self.state, dtype="<U8")
        ms = np.asarray(self.ms, dtype=np.float64).reshape(-1)
        if t.shape != (n,) or ms.shape != (n,):
            raise CaptureError(f"PoseTrack: t and ms must have {n} entries like frames")
        if joints.shape != (n, NUM_JOINTS, 3):
            raise CaptureError(f"PoseTrack: joints must be ({n}, 17, 3), got {joints.shape}")
        if state.shape != (n, NUM_JOINTS):
            raise CaptureError(f"PoseTrack: state must be ({n}, 17), got {state.shape}")
        if n > 1 and np.any(np.diff(frames) <= 0):
            bad = int(np.argmax(np.diff(frames) <= 0)) + 1
            raise CaptureError(
                f"PoseTrack: frame numbers must increase; frame {frames[bad]} follows "
                f"{frames[bad - 1]}"
            )
        unknown = set(np.unique(state).tolist()) - set(JOINT_STATES)
        if unknown:
            raise CaptureError(f"PoseTrack: unknown joint states {sorted(unknown)}")
        missing = ~np.all(np.isfinite(joints), axis=-1)
        joints = joints.copy()
        joints[missing] = np.nan
        state = state.copy()
        state[missing] = "lost"
        joints[state == "lost"] = np.nan
        for name, value in (("frames", frames), ("t", t), ("joints", joints), ("state", state),
                            ("ms", ms)):
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    # ---- construction ---------------------------------------------------------------
    @classmethod
    def from_arrays(
        cls,
        frames: ArrayLike,
        t: ArrayLike,
        joints: ArrayLike,
        state: ArrayLike | None = None,
        ms: ArrayLike | None = None,
    ) -> PoseTrack:
        """Build a track; ``state`` defaults to tracked/lost by NaN, ``ms`` to NaN."""
        j = np.asarray(joints, dtype=np.float64)
        n = j.shape[0]
        if state is None:
            st = np.where(np.all(np.isfinite(j), axis=-1), "tracked", "lost").astype("<U8")
        else:
            st = np.asarray(state, dtype="<U8")
        return cls(
            np.asarray(frames, dtype=np.int64),
            np.asarray(t, dtype=np.float64),
            j,
            st,
            np.full(n, np.nan) if ms is None else np.asarray(ms, dtype=np.float64),
        )

    @classmethod
    def from_records(cls, records: Iterable[Mapping[str, Any]]) -> PoseTrack:
        """Build a track from truth/poses records (the dicts of the JSON lines)."""
        rows = [_parse_record(rec, f"record {i}") for i, rec in enumerate(records)]
        return cls._from_rows(rows)

    @classmethod
    def _from_rows(cls, rows: list[tuple[int, float, NDArray[np.float64], list[str], float]]
                   ) -> PoseTrack:
        n = len(rows)
        frames = np.array([r[0] for r in rows], dtype=np.int64)
        t = np.array([r[1] for r in rows], dtype=np.float64)
        joints = (
            np.stack([r[2] for r in rows]) if n else np.zeros((0, NUM_JOINTS, 3))
        )
        state = np.array([r[3] for r in rows], dtype="<U8").reshape(n, NUM_JOINTS)
        ms = np.array([r[4] for r in rows], dtype=np.float64)
        return cls(frames, t, joints, state, ms)

    # ---- access ---------------------------------------------------------------------
    def __len__(self) -> int:
        return int(self.frames.size)

    @property
    def reported(self) -> NDArray[np.bool_]:
        """(N, 17) True where the joint has coordinates."""
        return np.all(np.isfinite(self.joints), axis=-1)

    def records(self, state: bool = True, ms: bool = True) -> list[dict[str, Any]]:
        """The track as JSON-ready records (nulls for unreported joints)."""
        out: list[dict[str, Any]] = []
        for i in range(len(self)):
            rec: dict[str, Any] = {
                "frame": int(self.frames[i]),
                "t": round(float(self.t[i]), 6),
                "joints": {
                    name: (
                        [round(float(v), 6) for v in self.joints[i, j]]
                        if np.all(np.isfinite(self.joints[i, j]))
                        else None
                    )
                    for j, name in enumerate(JOINT_NAMES)
                },
            }
            if state:
                rec["state"] = {name: str(self.state[i, j]) for j, name in enumerate(JOINT_NAMES)}
            if ms and math.isfinite(float(self.ms[i])):
                rec["ms"] = round(float(self.ms[i]), 3)
            out.append(rec)
        return out


def _parse_record(
    rec: Any, where: str
) -> tuple[int, float, NDArray[np.float64], list[str], float]:
    """Validate one record; errors say where and what is wrong."""
    if not isinstance(rec, Mapping):
        raise CaptureError(f"{where}: expected a JSON object, got {type(rec).__name__}")
    for key in ("frame", "t", "joints"):
        if key not in rec:
            raise CaptureError(f'{where}: missing "{key}" (expected frame, t, joints)')
    frame = rec["frame"]
    if isinstance(frame, bool) or not isinstance(frame, int) or frame < 0:
        raise CaptureError(f'{where}: "frame" must be a non-negative integer, got {frame!r}')
    t = rec["t"]
    if isinstance(t, bool) or not isinstance(t, int | float) or not math.isfinite(t):
        raise CaptureError(f'{where}: "t" must be a finite number of seconds, got {t!r}')
    joints_in = rec["joints"]
    if not isinstance(joints_in, Mapping):
        raise CaptureError(f'{where}: "joints" must be an object of joint name -> [x, y, z]')
    joints = np.full((NUM_JOINTS, 3), np.nan)
    for name, value in joints_in.items():
        j = JOINT_INDEX.get(name)
        if j is None:
            raise CaptureError(
                f"{where}: unknown joint {name!r}; expected names from {', '.join(JOINT_NAMES)}"
            )
        if value is None:
            continue
        if (
            not isinstance(value, list | tuple)
            or len(value) != 3
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        ):
            raise CaptureError(f"{where}: joint {name!r} must be [x, y, z] or null, got {value!r}")
        joints[j] = value
    reported = np.all(np.isfinite(joints), axis=-1)
    states = ["tracked" if r else "lost" for r in reported]
    state_in = rec.get("state")
    if state_in is not None:
        if not isinstance(state_in, Mapping):
            raise CaptureError(f'{where}: "state" must be an object of joint name -> state')
        for name, value in state_in.items():
            j = JOINT_INDEX.get(name)
            if j is None:
                raise CaptureError(f"{where}: unknown joint {name!r} in state")
            if value not in JOINT_STATES:
                raise CaptureError(
                    f"{where}: state of {name!r} is {value!r}; expected one of {JOINT_STATES}"
                )
            if reported[j]:
                states[j] = str(value)
    ms_in = rec.get("ms")
    if ms_in is not None and (isinstance(ms_in, bool) or not isinstance(ms_in, int | float)):
        raise CaptureError(f'{where}: "ms" must be a number, got {ms_in!r}')
    ms = float(ms_in) if ms_in is not None else math.nan
    return int(frame), float(t), joints, states, ms


def read_pose_jsonl(path: str | Path) -> PoseTrack:
    """Read ``truth.jsonl`` or ``poses.jsonl`` into a :class:`PoseTrack`.

    Blank lines are skipped. A last line that is cut short (no final newline and not
    valid JSON) is dropped with a warning; any other malformed line raises
    CaptureError with its line number.
    """
    with reading(path, CaptureError, "pose file (JSON lines)"):
        return _read_pose_jsonl_unchecked(path)


def _read_pose_jsonl_unchecked(path: str | Path) -> PoseTrack:
    """The unchecked reader behind :func:`read_pose_jsonl`."""
    p = Path(path)
    if not p.is_file():
        raise CaptureError(f"{p}: no such pose file; expected truth.jsonl or poses.jsonl")
    text = p.read_text()
    lines = text.split("\n")
    last = max((i for i, line in enumerate(lines) if line.strip()), default=-1)
    truncated_ok = not text.endswith("\n")
    rows = []
    prev_frame: tuple[int, int] | None = None
    for i, line in enumerate(lines):
        if not line.strip():
            continue
        where = f"{p}:{i + 1}"
        try:
            rec = json.loads(line)
        except json.JSONDecodeError as exc:
            if i == last and truncated_ok:
                warnings.warn(f"{where}: last line is cut short; ignoring it", stacklevel=2)
                break
            raise CaptureError(f"{where}: not valid JSON ({exc.msg}); fix or delete the line") \
                from None
        row = _parse_record(rec, where)
        if prev_frame is not None and row[0] <= prev_frame[0]:
            raise CaptureError(
                f"{where}: frame {row[0]} does not follow frame {prev_frame[0]} (line "
                f"{prev_frame[1]}); frames must increase"
            )
        prev_frame = (row[0], i + 1)
        rows.append(row)
    return PoseTrack._from_rows(rows)


def write_pose_jsonl(
    path: str | Path, track: PoseTrack, *, state: bool = True, ms: bool = True
) -> Path:
    """Write a track as JSON lines; ``state=False, ms=False`` gives truth.jsonl form."""
    p = Path(path)
    with atomic_write(p, "w") as fh:  # whole or not at all
        for rec in track.records(state=state, ms=ms):
            fh.write(json.dumps(rec, separators=(",", ":")) + "\n")
    return p


class PoseJsonlWriter:
    """Append records to a poses/truth JSON-lines file one frame at a time.

    Lines go to ``<name>.partial`` (flushed each, so a crashed run leaves a file that
    :func:`read_pose_jsonl` still reads, under a name that says it is incomplete), renamed
    to ``path`` by :meth:`close`; a ``with`` block that ends in an error leaves only the
    ``.partial`` file, never a partial output under the final name. Frames must increase.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.partial = self.path.with_name(self.path.name + ".partial")
        self._fh: IO[str] | None = self.partial.open("w")
        self._last: int | None = None

    def write(self, record: Mapping[str, Any]) -> None:
        """Validate and append one record (e.g. ``TrackResult.to_json()``)."""
        if self._fh is None:
            raise CaptureError(f"{self.path}: writer is closed")
        frame = _parse_record(record, f"{self.path} record")[0]
        if self._last is not None and frame <= self._last:
            raise CaptureError(f"{self.path}: frame {frame} written after frame {self._last}")
        self._last = frame
        self._fh.write(json.dumps(dict(record), separators=(",", ":")) + "\n")
        self._fh.flush()

    def close(self, complete: bool = True) -> None:
        """Close the file; ``complete`` renames it to its final name."""
        if self._fh is not None:
            self._fh.close()
            self._fh = None
            if complete:
                os.replace(self.partial, self.path)

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close(complete=exc_type is None)
