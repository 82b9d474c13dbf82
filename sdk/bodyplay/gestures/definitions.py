"""Gestures as data: TOML definitions parsed into typed, validated definitions.

One file defines one gesture::

    [gesture]
    name = "hit"                     # optional, defaults to the file name
    description = "right arm swung up and lowered quickly"
    cooldown = 0.3                   # s after a performed gesture before it can start again
    timeout = 1.5                    # optional: s from start by which it must be performed
    inhibits = ["other"]             # optional: gestures this one takes precedence over

    [[stage]]
    name = "up"
    when = ["above(r_wrist, head) > 0.1"]   # all must hold (a conjunction)
    hold = 0.0                       # s the conditions must hold to complete the stage

    [[stage]]
    name = "down"
    when = ["above(r_wrist, r_shoulder) < -0.5"]
    within = 0.8                     # s after the previous stage by which this one must begin

A condition is ``feature(joint, ...) OP number`` with OP one of ``< <= > >=``; the
features are listed in :data:`bodyplay.gestures.features.FEATURES`. Problems (bad
TOML, unknown keys, unknown features or joints, wrong arity, an unknown gesture in
``inhibits``, a cycle of inhibitions) raise :class:`~bodyplay.errors.ConfigError`
naming the file and the key.
"""

from __future__ import annotations

import re
import tomllib
from collections.abc import Iterable
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.errors import ConfigError, reading
from bodyplay.gestures.features import FEATURES

__all__ = [
    "Condition",
    "Stage",
    "GestureDefinition",
    "parse_gesture",
    "load_gestures",
    "builtin_gesture_names",
    "parse_condition",
    "check_gesture_set",
]

_COND = re.compile(
    r"^\s*(?P<name>[A-Za-z_][A-Za-z0-9_]*)\s*(?:\((?P<args>[^()]*)\))?\s*"
    r"(?P<op><=|>=|<|>)\s*(?P<value>[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*$"
)
_OPS = ("<", "<=", ">", ">=")


@dataclass(frozen=True)
class Condition:
    """``feature(args) op threshold``, e.g. ``above(r_wrist, head) > 0.1``."""

    feature: str
    args: tuple[str, ...]
    op: str
    threshold: float

    def test(self, value: float) -> bool:
        """Whether a feature value satisfies the condition (NaN never does)."""
        if self.op == ">":
            return value > self.threshold
        if self.op == ">=":
            return value >= self.threshold
        if self.op == "<":
            return value < self.threshold
        return value <= self.threshold

    def __str__(self) -> str:
        args = f"({', '.join(self.args)})" if self.args else ""
        return f"{self.feature}{args} {self.op} {self.threshold:g}"


@dataclass(frozen=True)
class Stage:
    """One phase of a gesture: conditions that must all hold for ``hold`` seconds,
    beginning at most ``within`` seconds after the previous stage completed.

    ``when_no_legs`` (optional) replaces ``when`` in frames where no leg joint is seen
    (an upper-body tracker such as the color shirt): conditions on the pelvis alone.
    """

    name: str
    when: tuple[Condition, ...]
    hold: float = 0.0
    within: float = 1.0
    when_no_legs: tuple[Condition, ...] | None = None


@dataclass(frozen=True)
class GestureDefinition:
    """A gesture: a named sequence of stages with a cooldown and an optional timeout.

    ``inhibits`` names gestures this one takes precedence over (the recognizer
    withholds their ``performed`` while this one is under way and cancels them when
    it is performed; docs/gestures.md, "Precedence").
    """

    name: str
    stages: tuple[Stage, ...]
    description: str = ""
    cooldown: float = 0.3
    timeout: float | None = None
    source: str = ""
    inhibits: tuple[str, ...] = ()


def parse_condition(text: str, where: str = "condition") -> Condition:
    """Parse ``feature(args) op number``; ``where`` names the place for error messages."""
    if not isinstance(text, str):
        raise ConfigError(f"{where}: a condition must be a string like 'pelvis_drop > 0.25'")
    m = _COND.match(text)
    if m is None:
        raise ConfigError(
            f"{where}: cannot read condition {text!r}; write 'feature(joint, ...) OP number' "
            f"with OP one of {' '.join(_OPS)}"
        )
    name = m["name"]
    spec = FEATURES.get(name)
    if spec is None:
        raise ConfigError(
            f"{where}: unknown feature {name!r}; known features: {', '.join(sorted(FEATURES))}"
        )
    args = tuple(a.strip() for a in m["args"].split(",")) if m["args"] and m["args"].strip() else ()
    if len(args) != spec.arity:
        raise ConfigError(
            f"{where}: feature {name!r} takes {spec.arity} joint argument(s), got {len(args)}"
        )
    for a in args:
        if a not in JOINT_INDEX:
            raise ConfigError(
                f"{where}: unknown joint {a!r} in {text!r}; joints: {', '.join(JOINT_INDEX)}"
            )
    return Condition(name, args, m["op"], float(m["value"]))


def _number(table: dict[str, Any], key: str, where: str, default: float | None,
            minimum: float = 0.0, positive: bool = False) -> float | None:
    if key not in table:
        return default
    v = table[key]
    ok = isinstance(v, int | float) and not isinstance(v, bool) and (
        v > minimum if positive else v >= minimum
    )
    if not ok:
        rel = ">" if positive else ">="
        raise ConfigError(f"{where}.{key}: must be a number {rel} {minimum:g}, got {v!r}")
    return float(v)


def _check_keys(table: dict[str, Any], allowed: set[str], where: str) -> None:
    extra = sorted(set(table) - allowed)
    if extra:
        raise ConfigError(
            f"{where}: unknown key(s) {', '.join(extra)}; allowed: {', '.join(sorted(allowed))}"
        )


def parse_gesture(text: str, source: str = "<string>", default_name: str = "") -> GestureDefinition:
    """Parse one gesture's TOML text; ``source`` names it in error messages."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ConfigError(f"{source}: malformed TOML: {e}") from None
    _check_keys(doc, {"gesture", "stage"}, source)
    head = doc.get("gesture", {})
    if not isinstance(head, dict):
        raise ConfigError(f"{source}: [gesture] must be a table")
    _check_keys(head, {"name", "description", "cooldown", "timeout", "inhibits"},
                f"{source}: gesture")
    name = head.get("name", default_name)
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        raise ConfigError(f"{source}: gesture.name must be an identifier, got {name!r}")
    desc = head.get("description", "")
    if not isinstance(desc, str):
        raise ConfigError(f"{source}: gesture.description must be a string")
    cooldown = _number(head, "cooldown", f"{source}: gesture", 0.3)
    timeout = _number(head, "timeout", f"{source}: gesture", None, positive=True)
    inhibits = _inhibits(head, name, source)
    raw_stages = doc.get("stage")
    if not isinstance(raw_stages, list) or not raw_stages:
        raise ConfigError(f"{source}: needs at least one [[stage]] with a 'when' list")
    stages = []
    for i, st in enumerate(raw_stages):
        where = f"{source}: stage[{i}]"
        if not isinstance(st, dict):
            raise ConfigError(f"{where}: must be a table")
        _check_keys(st, {"name", "when", "hold", "within", "when_no_legs"}, where)
        when = st.get("when")
        if isinstance(when, str):
            when = [when]
        if not isinstance(when, list) or not when:
            raise ConfigError(f"{where}.when: must be a non-empty list of condition strings")
        conds = tuple(parse_condition(c, f"{where}.when[{k}]") for k, c in enumerate(when))
        no_legs = None
        if "when_no_legs" in st:
            nl = st["when_no_legs"]
            if isinstance(nl, str):
                nl = [nl]
            if not isinstance(nl, list) or not nl:
                raise ConfigError(f"{where}.when_no_legs: must be a non-empty list of "
                                  "condition strings")
            no_legs = tuple(parse_condition(c, f"{where}.when_no_legs[{k}]")
                            for k, c in enumerate(nl))
        sname = st.get("name", f"stage{i + 1}")
        if not isinstance(sname, str):
            raise ConfigError(f"{where}.name: must be a string")
        hold = _number(st, "hold", where, 0.0)
        within = _number(st, "within", where, 1.0, positive=True)
        assert hold is not None and within is not None
        stages.append(Stage(sname, conds, hold, within, no_legs))
    assert cooldown is not None
    return GestureDefinition(name, tuple(stages), desc, cooldown, timeout, source, inhibits)


def _inhibits(head: dict[str, Any], name: str, source: str) -> tuple[str, ...]:
    """``gesture.inhibits``: a list of distinct gesture names, not the gesture itself."""
    raw = head.get("inhibits", [])
    where = f"{source}: gesture.inhibits"
    if isinstance(raw, str):
        raw = [raw]
    if not isinstance(raw, list):
        raise ConfigError(f"{where}: must be a list of gesture names, got {raw!r}")
    for g in raw:
        if not isinstance(g, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", g):
            raise ConfigError(f"{where}: {g!r} is not a gesture name")
        if g == name:
            raise ConfigError(f"{where}: a gesture cannot inhibit itself ({g!r})")
    if len(set(raw)) != len(raw):
        raise ConfigError(f"{where}: names a gesture twice: {raw}")
    return tuple(raw)


def check_gesture_set(definitions: Iterable[GestureDefinition]) -> tuple[GestureDefinition, ...]:
    """Check the gestures meant to run together; return them inhibitors first.

    Every name in a definition's ``inhibits`` must be one of ``definitions`` or a
    built-in gesture (a built-in that is not in the set is simply not there to
    inhibit: ``double_hit`` alone still loads); inhibitions may not form a cycle
    (``a`` inhibits ``b`` inhibits ``a``). The returned order puts every gesture after
    all of those that inhibit it (stable otherwise), which is the order the recognizer
    settles a frame's completions in. Raises :class:`ConfigError` naming the file.
    """
    defs = tuple(definitions)
    names = {d.name: d for d in defs}
    builtin = set(builtin_gesture_names())
    for d in defs:
        for g in d.inhibits:
            if g not in names and g not in builtin:
                raise ConfigError(
                    f"{d.source or d.name}: gesture.inhibits: unknown gesture {g!r}; gestures "
                    f"here: {', '.join(sorted(names))}; built-ins: {', '.join(sorted(builtin))}"
                )
    # Kahn's algorithm over the edges inhibitor -> inhibited within the set.
    blockers = {d.name: {o.name for o in defs if d.name in o.inhibits} for d in defs}
    order: list[GestureDefinition] = []
    left = list(defs)
    while left:
        ready = [d for d in left if not blockers[d.name] - {o.name for o in order}]
        if not ready:
            cycle = sorted(d.name for d in left if blockers[d.name])
            src = next(d.source or d.name for d in left if blockers[d.name])
            raise ConfigError(
                f"{src}: gesture.inhibits: the inhibitions among {', '.join(cycle)} form a "
                "cycle; precedence must run one way (remove one of them)"
            )
        order.append(ready[0])
        left.remove(ready[0])
    return tuple(order)


def builtin_gesture_names() -> tuple[str, ...]:
    """Names of the gestures shipped with bodyplay (``gestures/builtin/*.toml``)."""
    folder = resources.files("bodyplay.gestures").joinpath("builtin")
    return tuple(sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml")))


def _load_one(item: str | Path) -> list[GestureDefinition]:
    p = Path(item)
    if p.suffix == ".toml" or p.exists():
        if p.is_dir():
            files = sorted(p.glob("*.toml"))
            if not files:
                raise ConfigError(f"{p}: no *.toml gesture definitions in this folder")
            return [d for f in files for d in _load_one(f)]
        try:
            raw = p.read_bytes()
        except OSError as e:
            raise ConfigError(f"{p}: cannot read gesture definition ({e.strerror})") from None
        with reading(p, ConfigError, "gesture definition"):
            return [parse_gesture(raw.decode("utf-8"), str(p), p.stem)]
    name = str(item)
    if name in ("builtin", "all"):
        return [d for n in builtin_gesture_names() for d in _load_one(n)]
    if name not in builtin_gesture_names():
        raise ConfigError(
            f"{name!r} is neither a .toml file nor a built-in gesture; built-ins: "
            f"{', '.join(builtin_gesture_names())}"
        )
    res = resources.files("bodyplay.gestures").joinpath("builtin", f"{name}.toml")
    return [parse_gesture(res.read_text(encoding="utf-8"), f"builtin:{name}.toml", name)]


def load_gestures(
    path_or_builtin: str | Path | Iterable[str | Path] = "builtin",
) -> list[GestureDefinition]:
    """Load gesture definitions from files, folders or built-in names.

    Accepts a ``.toml`` path, a folder of them, a built-in name (``"crouch"``),
    ``"builtin"`` for all built-ins, or a list of these. Duplicate names, unknown names
in ``inhibits`` and cycles of inhibitions are errors (:func:`check_gesture_set`).
    """
    items = (
        [path_or_builtin] if isinstance(path_or_builtin, str | Path) else list(path_or_builtin)
    )
    out: list[GestureDefinition] = []
    seen: dict[str, str] = {}
    for it in items:
        for d in _load_one(it):
            if d.name in seen:
                raise ConfigError(
                    f"gesture {d.name!r} defined twice: {seen[d.name]} and {d.source}"
                )
            seen[d.name] = d.source
            out.append(d)
    check_gesture_set(out)
    return out
