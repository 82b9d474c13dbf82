"""Reading and writing BVH motion capture files.

BVH is the lingua franca of motion capture: a joint hierarchy (offsets and channel
lists) followed by one line of numbers per frame. Real files disagree on details,
so :func:`read_bvh` is tolerant of what does not change the meaning (CRLF, tabs,
blank lines, any rotation channel order, position channels on any joint, a
``Frames:`` count that does not match the data) and strict about what does: every
malformed line raises :class:`~bodyplay.errors.BVHError` naming the file, the line
number and the problem. ``.bvh.gz`` files are read transparently.

Conventions (the common ones, as Blender and MotionBuilder read BVH): rotation
channels are intrinsic Euler angles in degrees applied in the listed order
(``Zrotation Xrotation Yrotation`` means ``R = Rz @ Rx @ Ry``); a joint's position
channels replace the matching components of its OFFSET (this is what makes
Bandai Namco's files, whose every joint carries positions, come out right, and is
the same as adding them for the usual root with a zero offset).
"""

from __future__ import annotations

import gzip
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import BVHError, ConfigError, reading
from bodyplay.files import atomic_write

__all__ = ["BVHClip", "EndSite", "read_bvh", "write_bvh"]

_ROT_CHANNELS = ("Xrotation", "Yrotation", "Zrotation")
_POS_CHANNELS = ("Xposition", "Yposition", "Zposition")
_ALL_CHANNELS = {c.lower(): c for c in _ROT_CHANNELS + _POS_CHANNELS}


@dataclass(frozen=True)
class EndSite:
    """An ``End Site`` block: a point fixed in its parent joint's frame (e.g. head top)."""

    parent: int
    offset: tuple[float, float, float]


@dataclass(frozen=True, eq=False)
class BVHClip:
    """A BVH file as read: the hierarchy and the raw channel values of every frame.

    ``motion[t, c]`` is channel ``c`` of frame ``t``; channels are laid out joint by
    joint in hierarchy order, ``channel_offsets[j]`` being where joint ``j``'s start.
    Positions are in the file's units (see :mod:`bodyplay.motion.retarget` for
    normalizing them).
    """

    names: tuple[str, ...]
    parents: tuple[int, ...]
    offsets: NDArray[np.float64]
    channels: tuple[tuple[str, ...], ...]
    frame_time: float
    motion: NDArray[np.float64]
    source: str = ""
    end_sites: tuple[EndSite, ...] = field(default=())

    @property
    def num_joints(self) -> int:
        """Number of joints (End Sites not counted)."""
        return len(self.names)

    @property
    def num_frames(self) -> int:
        """Number of frames of motion."""
        return int(self.motion.shape[0])

    @property
    def fps(self) -> float:
        """Frames per second: 1 / frame_time, snapped to a whole number when the file's
        frame time is a rounded 1/n (CMU writes .0083333 for 120 fps)."""
        rate = 1.0 / self.frame_time
        whole = round(rate)
        return float(whole) if whole > 0 and abs(rate - whole) < 1e-4 * rate else rate

    @property
    def channel_offsets(self) -> tuple[int, ...]:
        """Index of each joint's first channel in a frame's row of numbers."""
        starts, n = [], 0
        for ch in self.channels:
            starts.append(n)
            n += len(ch)
        return tuple(starts)

    def index(self, name: str) -> int:
        """Index of a joint by name, with a clear error for unknown names."""
        try:
            return self.names.index(name)
        except ValueError:
            raise ConfigError(
                f"{self.source or 'BVH'} has no joint {name!r}; joints are {', '.join(self.names)}"
            ) from None

    def _frames(self, frames: ArrayLike | slice | None) -> NDArray[np.float64]:
        if frames is None:
            return self.motion
        if isinstance(frames, slice):
            return self.motion[frames]
        return self.motion[np.asarray(frames, dtype=np.intp)]

    def local_transforms(
        self, frames: ArrayLike | slice | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Per-joint local rotations (T, J, 3, 3) and translations (T, J, 3) of frames."""
        m = self._frames(frames)
        T, J = m.shape[0], self.num_joints
        rot = np.broadcast_to(np.eye(3), (T, J, 3, 3)).copy()
        trans = np.broadcast_to(self.offsets, (T, J, 3)).copy()
        starts = self.channel_offsets
        # one Euler conversion per distinct channel order, all its joints at once
        groups: dict[str, tuple[list[int], list[list[int]]]] = {}
        for j, chans in enumerate(self.channels):
            s = starts[j]
            order = "".join(c[0] for c in chans if c in _ROT_CHANNELS)
            if order:
                js, cols = groups.setdefault(order, ([], []))
                js.append(j)
                cols.append([s + k for k, c in enumerate(chans) if c in _ROT_CHANNELS])
            for k, c in enumerate(chans):
                if c in _POS_CHANNELS:
                    trans[:, j, _POS_CHANNELS.index(c)] = m[:, s + k]
        for order, (js, cols) in groups.items():
            angles = m[:, np.asarray(cols)]  # (T, G, len(order))
            rot[:, js] = _euler_matrices(order, np.radians(angles))
        return rot, trans

    def global_transforms(
        self, frames: ArrayLike | slice | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """World rotations (T, J, 3, 3) and positions (T, J, 3) by forward kinematics."""
        rot, trans = self.local_transforms(frames)
        G_rot = np.empty_like(rot)
        G_pos = np.empty_like(trans)
        for j, p in enumerate(self.parents):
            if p < 0:
                G_rot[:, j] = rot[:, j]
                G_pos[:, j] = trans[:, j]
            else:
                G_rot[:, j] = G_rot[:, p] @ rot[:, j]
                G_pos[:, j] = G_pos[:, p] + np.einsum("tij,tj->ti", G_rot[:, p], trans[:, j])
        return G_rot, G_pos

    def world_positions(
        self, frames: ArrayLike | slice | None = None, include_end_sites: bool = False
    ) -> NDArray[np.float64]:
        """(T, J, 3) joint positions in the file's units and axes, by vectorized FK.

        With ``include_end_sites`` the End Sites follow the joints: (T, J + E, 3).
        """
        G_rot, G_pos = self.global_transforms(frames)
        if not include_end_sites or not self.end_sites:
            return G_pos
        ends = [
            G_pos[:, e.parent] + G_rot[:, e.parent] @ np.asarray(e.offset) for e in self.end_sites
        ]
        return np.concatenate([G_pos, np.stack(ends, axis=1)], axis=1)

    def end_site_of(self, joint: int) -> int | None:
        """Index into ``end_sites`` of the first End Site under ``joint``, if any."""
        for i, e in enumerate(self.end_sites):
            if e.parent == joint:
                return i
        return None


def _euler_matrices(order: str, angles: NDArray[np.float64]) -> NDArray[np.float64]:
    """(..., 3, 3) matrices of intrinsic rotations about the axes in ``order`` ("ZXY").

    Equivalent to ``Rotation.from_euler(order.upper(), angles).as_matrix()`` but
    several times faster for the hundred thousands of rotations a long clip holds.
    """
    out: NDArray[np.float64] | None = None
    for k, axis in enumerate(order.upper()):
        c, s = np.cos(angles[..., k]), np.sin(angles[..., k])
        R = np.zeros(angles.shape[:-1] + (3, 3))
        i = "XYZ".index(axis)
        a, b = (i + 1) % 3, (i + 2) % 3
        R[..., i, i] = 1.0
        R[..., a, a] = c
        R[..., b, b] = c
        R[..., a, b] = -s
        R[..., b, a] = s
        out = R if out is None else out @ R
    assert out is not None
    return out


# ---- reading ----------------------------------------------------------------------


class _Tokens:
    """Whitespace tokens of the hierarchy section with their 1-based line numbers."""

    def __init__(self, lines: Sequence[str], name: str) -> None:
        self.name = name
        self.items: list[tuple[str, int]] = []
        self.pos = 0
        self.lines = lines
        self.motion_line = -1
        for i, line in enumerate(lines):
            words = line.split()
            if words and words[0].upper() == "MOTION":
                self.motion_line = i
                break
            for w in words:
                # braces glued to words ("Hips{") are separate tokens
                for part in w.replace("{", " { ").replace("}", " } ").split():
                    self.items.append((part, i + 1))
        self.last_line = self.items[-1][1] if self.items else 1

    def error(self, line: int, msg: str) -> BVHError:
        return BVHError(f"{self.name}:{line}: {msg}")

    def peek(self) -> tuple[str, int]:
        if self.pos >= len(self.items):
            return "", self.last_line
        return self.items[self.pos]

    def next(self, what: str) -> tuple[str, int]:
        if self.pos >= len(self.items):
            raise self.error(self.last_line, f"file ends where {what} was expected")
        tok = self.items[self.pos]
        self.pos += 1
        return tok

    def expect(self, word: str) -> int:
        tok, line = self.next(f"{word!r}")
        if tok.upper() != word.upper():
            raise self.error(line, f"expected {word!r}, found {tok!r}")
        return line

    def number(self, what: str) -> float:
        tok, line = self.next(what)
        try:
            value = float(tok)
        except ValueError:
            raise self.error(line, f"expected a number for {what}, found {tok!r}") from None
        if not np.isfinite(value):
            raise self.error(line, f"expected a finite number for {what}, found {tok!r}")
        return value


def _read_text(path: Path) -> str:
    try:
        if path.suffix == ".gz":
            with gzip.open(path, "rt", encoding="utf-8", errors="replace") as f:
                return f.read()
        return path.read_text(encoding="utf-8", errors="replace")
    except FileNotFoundError:
        raise BVHError(f"{path}: no such BVH file") from None
    except OSError as exc:
        raise BVHError(f"{path}: cannot read the BVH file ({exc})") from None


def read_bvh(path: str | Path) -> BVHClip:
    """Read a BVH (or gzip-compressed ``.bvh.gz``) file into a :class:`BVHClip`.

    Raises :class:`BVHError` with ``file:line: problem`` for malformed input; warns
    (``warnings.warn``) and uses the frames present when ``Frames:`` disagrees.
    """
    with reading(path, BVHError, "BVH file"):
        return _read_bvh_unchecked(path)


def _read_bvh_unchecked(path: str | Path) -> BVHClip:
    """The unchecked reader behind :func:`read_bvh`."""
    path = Path(path)
    text = _read_text(path)
    name = path.name
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    toks = _Tokens(lines, name)

    first, line = toks.next("'HIERARCHY'")
    if first.upper() != "HIERARCHY":
        raise toks.error(line, f"a BVH file starts with 'HIERARCHY', found {first!r}")

    names: list[str] = []
    parents: list[int] = []
    offsets: list[tuple[float, float, float]] = []
    channels: list[tuple[str, ...]] = []
    ends: list[EndSite] = []

    def parse_offset(owner: str) -> tuple[float, float, float]:
        toks.expect("OFFSET")
        return (
            toks.number(f"the OFFSET of {owner}"),
            toks.number(f"the OFFSET of {owner}"),
            toks.number(f"the OFFSET of {owner}"),
        )

    def parse_joint(parent: int, keyword_line: int) -> None:
        # the joint's name: every token up to '{' on the keyword's line
        parts: list[str] = []
        while toks.peek()[0] != "{" and toks.peek()[1] == keyword_line:
            parts.append(toks.next("a joint name")[0])
        if not parts:
            raise toks.error(keyword_line, "a joint without a name")
        jname = " ".join(parts)
        if jname in names:
            raise toks.error(keyword_line, f"joint name {jname!r} is used twice")
        toks.expect("{")
        idx = len(names)
        names.append(jname)
        parents.append(parent)
        offsets.append(parse_offset(jname))
        tok, line = toks.peek()
        chans: tuple[str, ...] = ()
        if tok.upper() == "CHANNELS":
            toks.next("CHANNELS")
            count_tok, cline = toks.next(f"the channel count of {jname}")
            try:
                count = int(count_tok)
            except ValueError:
                raise toks.error(
                    cline, f"expected a channel count for {jname}, found {count_tok!r}"
                ) from None
            got: list[str] = []
            for _ in range(count):
                ch, chl = toks.next(f"a channel name of {jname}")
                canon = _ALL_CHANNELS.get(ch.lower())
                if canon is None:
                    raise toks.error(
                        chl,
                        f"{jname} declares {count} channels but {ch!r} is not a channel name "
                        "(Xposition ... Zrotation)",
                    )
                got.append(canon)
            if len(set(got)) != len(got):
                raise toks.error(cline, f"{jname} lists a channel twice: {' '.join(got)}")
            chans = tuple(got)
        channels.append(chans)
        while True:
            tok, line = toks.next(f"'}}' closing {jname}")
            up = tok.upper()
            if tok == "}":
                return
            if up == "JOINT":
                parse_joint(idx, line)
            elif up == "END":
                site_tok, sline = toks.next("'Site'")
                if site_tok.upper() != "SITE":
                    raise toks.error(sline, f"expected 'End Site', found 'End {site_tok}'")
                toks.expect("{")
                ends.append(EndSite(idx, parse_offset(f"the End Site of {jname}")))
                toks.expect("}")
            else:
                raise toks.error(
                    line, f"expected JOINT, End Site or '}}' in {jname}, found {tok!r}"
                )

    tok, line = toks.next("'ROOT'")
    if tok.upper() != "ROOT":
        raise toks.error(line, f"expected 'ROOT', found {tok!r}")
    parse_joint(-1, line)
    tok, line = toks.peek()
    if tok:
        raise toks.error(line, f"unexpected {tok!r} after the hierarchy (a second ROOT?)")
    if toks.motion_line < 0:
        raise toks.error(len(lines), "no MOTION section")

    motion, frame_time = _read_motion(lines, toks.motion_line, name, names, channels)
    return BVHClip(
        names=tuple(names),
        parents=tuple(parents),
        offsets=np.asarray(offsets, dtype=np.float64).reshape(-1, 3),
        channels=tuple(channels),
        frame_time=frame_time,
        motion=motion,
        source=str(path),
        end_sites=tuple(ends),
    )


def _header_value(lines: Sequence[str], i: int, key: str, name: str) -> tuple[str, int]:
    """The value after ``key`` (e.g. 'Frames:') on the next non-blank line from i."""
    while i < len(lines) and not lines[i].strip():
        i += 1
    if i >= len(lines):
        raise BVHError(f"{name}:{len(lines)}: file ends where {key!r} was expected")
    line = lines[i].strip()
    if not line.lower().startswith(key.lower()):
        raise BVHError(f"{name}:{i + 1}: expected {key!r}, found {line[:40]!r}")
    return line[len(key) :].strip(), i


def _read_motion(
    lines: Sequence[str],
    motion_line: int,
    name: str,
    names: Sequence[str],
    channels: Sequence[tuple[str, ...]],
) -> tuple[NDArray[np.float64], float]:
    value, i = _header_value(lines, motion_line + 1, "Frames:", name)
    try:
        declared = int(value)
    except ValueError:
        raise BVHError(
            f"{name}:{i + 1}: expected a frame count after 'Frames:', found {value!r}"
        ) from None
    value, i = _header_value(lines, i + 1, "Frame Time:", name)
    try:
        frame_time = float(value)
    except ValueError:
        raise BVHError(
            f"{name}:{i + 1}: expected seconds after 'Frame Time:', found {value!r}"
        ) from None
    if not frame_time > 0 or not np.isfinite(frame_time):
        raise BVHError(f"{name}:{i + 1}: 'Frame Time' must be positive, found {value}")

    ncols = sum(len(c) for c in channels)
    bounds = np.cumsum([len(c) for c in channels])
    rows: list[list[str]] = []
    for k in range(i + 1, len(lines)):
        words = lines[k].split()
        if not words:
            continue
        if len(words) != ncols:
            if len(words) < ncols:
                j = int(np.searchsorted(bounds, len(words), side="right"))
                have = len(words) - (int(bounds[j - 1]) if j > 0 else 0)
                msg = (
                    f"expected {len(channels[j])} numbers for the channels of {names[j]}, "
                    f"found {have} (a frame has {ncols} numbers, this line {len(words)})"
                )
            else:
                msg = f"expected {ncols} numbers per frame, found {len(words)}"
            raise BVHError(f"{name}:{k + 1}: {msg}")
        rows.append(words)
        if len(rows) == 1:
            first_data_line = k
    if not rows:
        raise BVHError(f"{name}:{len(lines)}: the MOTION section holds no frames")
    try:
        motion = np.array(rows, dtype=np.float64).reshape(len(rows), ncols)
    except ValueError:
        # find the offending line for the message
        n = 0
        for k in range(first_data_line, len(lines)):
            words = lines[k].split()
            if not words:
                continue
            for w in words:
                try:
                    float(w)
                except ValueError:
                    raise BVHError(f"{name}:{k + 1}: {w!r} is not a number") from None
            n += 1
        raise BVHError(f"{name}: unreadable numbers in the MOTION section") from None
    if not np.all(np.isfinite(motion)):
        bad = int(np.argwhere(~np.isfinite(motion))[0, 0])
        raise BVHError(f"{name}: frame {bad} holds NaN or infinite values")
    if declared != len(rows):
        warnings.warn(
            f"{name}: the header declares {declared} frames but the file holds {len(rows)}; "
            f"using the {len(rows)} present",
            stacklevel=3,
        )
    return motion, frame_time


# ---- writing ----------------------------------------------------------------------

_WRITE_ORDER = "ZYX"


def write_bvh(
    path: str | Path,
    skeleton: Skeleton,
    poses: ArrayLike,
    fps: float,
    units_per_metre: float = 100.0,
) -> Path:
    """Write pose vectors of ``skeleton`` as a BVH file (for ``bodyplay export``).

    Every skeleton node with a child becomes a joint (the root with 6 channels, the
    others with ``Zrotation Yrotation Xrotation``); end nodes (hands, toes, head top)
    become End Sites. Lengths are written in centimetres by default
    (``units_per_metre``), which is what Blender and most tools expect. ``.gz``
    paths are gzip-compressed. Returns the path written.
    """
    q = skeleton._check(np.atleast_2d(np.asarray(poses, dtype=np.float64)))
    if q.ndim != 2:
        raise ConfigError(f"poses must have shape (T, {skeleton.pose_dim}), got {q.shape}")
    if not fps > 0:
        raise ConfigError(f"fps must be positive, got {fps}")
    if not units_per_metre > 0:
        raise ConfigError(f"units_per_metre must be positive, got {units_per_metre}")
    parents = skeleton.parents
    n = skeleton.num_nodes
    children: list[list[int]] = [[] for _ in range(n)]
    for i, p in enumerate(parents):
        if p >= 0:
            children[p].append(i)
    off = skeleton.offsets * units_per_metre
    joints: list[int] = []  # hierarchy (depth-first) order, as the channels are laid out

    out: list[str] = ["HIERARCHY"]

    def fmt(v: NDArray[np.float64]) -> str:
        return " ".join(f"{x:.6f}" for x in v)

    def emit(i: int, depth: int) -> None:
        pad = "  " * depth
        kw = "ROOT" if parents[i] < 0 else "JOINT"
        joints.append(i)
        out.append(f"{pad}{kw} {skeleton.node_names[i]}")
        out.append(f"{pad}{{")
        out.append(f"{pad}  OFFSET {fmt(off[i])}")
        rot = " ".join(f"{a}rotation" for a in _WRITE_ORDER)
        if parents[i] < 0:
            out.append(f"{pad}  CHANNELS 6 Xposition Yposition Zposition {rot}")
        else:
            out.append(f"{pad}  CHANNELS 3 {rot}")
        for c in children[i]:
            if children[c]:
                emit(c, depth + 1)
            else:
                out.append(f"{pad}  End Site")
                out.append(f"{pad}  {{")
                out.append(f"{pad}    OFFSET {fmt(off[c])}")
                out.append(f"{pad}  }}")
        out.append(f"{pad}}}")

    emit(0, 0)
    T = q.shape[0]
    rotvecs = q[:, 3:].reshape(T, n, 3)[:, joints]
    euler = Rotation.from_rotvec(rotvecs.reshape(-1, 3)).as_euler(_WRITE_ORDER, degrees=True)
    euler = euler.reshape(T, len(joints) * 3)
    data = np.concatenate([q[:, 0:3] * units_per_metre, euler], axis=1)
    out.append("MOTION")
    out.append(f"Frames: {T}")
    out.append(f"Frame Time: {1.0 / fps:.8f}")
    body = "\n".join(" ".join(f"{x:.6f}" for x in row) for row in data)
    text = "\n".join(out) + "\n" + body + "\n"
    path = Path(path)
    raw = text.encode("utf-8")
    with atomic_write(path) as f:  # whole or not at all
        f.write(gzip.compress(raw, mtime=0) if path.suffix == ".gz" else raw)
    return path
