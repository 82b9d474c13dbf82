"""Measure gesture recognition against labeled time spans: precision and recall.

Labels are a TOML file of clips, each with a ``path`` and, per gesture, a list of
``[start, end]`` spans in seconds (see tests/fixtures/gestures/labels.toml). A listed
clip counts as labeled for every gesture: a ``performed`` event inside a span of its
gesture is a true positive (at most one per span), any other ``performed`` event is
a false positive, and a span without an event is a miss.
"""

from __future__ import annotations

import tomllib
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from bodyplay.errors import ConfigError
from bodyplay.events.types import GestureEvent
from bodyplay.gestures.recognizer import GestureRecognizer

__all__ = ["LabeledClip", "GestureScore", "load_labels", "score_events", "run_recognizer"]


@dataclass(frozen=True)
class LabeledClip:
    """One labeled clip: its file, a note, and the spans of each gesture."""

    name: str
    path: Path
    spans: dict[str, tuple[tuple[float, float], ...]]
    note: str = ""


@dataclass
class GestureScore:
    """Counts for one gesture (or all): true positives, false positives, labeled spans."""

    tp: int = 0
    fp: int = 0
    spans: int = 0
    false_times: list[tuple[str, float]] = field(default_factory=list)
    missed: list[tuple[str, float, float]] = field(default_factory=list)

    @property
    def precision(self) -> float:
        """TP / (TP + FP); 1.0 when nothing was detected."""
        n = self.tp + self.fp
        return self.tp / n if n else 1.0

    @property
    def recall(self) -> float:
        """TP / labeled spans; 1.0 when there is no span."""
        return self.tp / self.spans if self.spans else 1.0

    def add(self, other: GestureScore) -> None:
        """Accumulate another score into this one."""
        self.tp += other.tp
        self.fp += other.fp
        self.spans += other.spans
        self.false_times += other.false_times
        self.missed += other.missed


def load_labels(path: str | Path, data_root: str | Path) -> list[LabeledClip]:
    """Read a labels TOML file; clip paths are relative to ``data_root``."""
    p = Path(path)
    try:
        doc = tomllib.loads(p.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise ConfigError(f"{p}: cannot read labels: {e}") from None
    out = []
    for name, entry in doc.get("clips", {}).items():
        if "path" not in entry:
            raise ConfigError(f"{p}: clips.{name}.path is missing")
        spans: dict[str, tuple[tuple[float, float], ...]] = {}
        for key, val in entry.items():
            if key in ("path", "note"):
                continue
            try:
                spans[key] = tuple((float(a), float(b)) for a, b in val)
            except (TypeError, ValueError):
                raise ConfigError(
                    f"{p}: clips.{name}.{key} must be a list of [start, end]"
                ) from None
        out.append(LabeledClip(name, Path(data_root) / entry["path"], spans, entry.get("note", "")))
    return out


def score_events(
    clip: str,
    events: Iterable[GestureEvent],
    spans: Mapping[str, Sequence[tuple[float, float]]],
    gestures: Iterable[str],
) -> dict[str, GestureScore]:
    """Score one clip's performed events against its spans, per gesture."""
    performed = [e for e in events if e.phase == "performed"]
    scores: dict[str, GestureScore] = {}
    for g in gestures:
        s = GestureScore(spans=len(spans.get(g, ())))
        free = list(spans.get(g, ()))
        for e in sorted((e for e in performed if e.gesture == g), key=lambda e: e.t):
            hit = next((sp for sp in free if sp[0] <= e.t <= sp[1]), None)
            if hit is None:
                s.fp += 1
                s.false_times.append((clip, e.t))
            else:
                s.tp += 1
                free.remove(hit)
        s.missed = [(clip, a, b) for a, b in free]
        scores[g] = s
    return scores


def run_recognizer(
    recognizer: GestureRecognizer,
    times: NDArray[np.float64],
    joints: NDArray[np.float64],
    transform: Callable[[float, NDArray[np.float64]], NDArray[np.float64]] | None = None,
) -> list[GestureEvent]:
    """Feed a clip's frames to a fresh recognizer state; return every event.

    ``transform(t, joints)`` may modify each frame first (add noise, smooth).
    """
    recognizer.reset()
    events: list[GestureEvent] = []
    for t, j in zip(times, joints, strict=True):
        frame = transform(float(t), j) if transform is not None else j
        events.extend(recognizer.update(float(t), frame))
    return events
