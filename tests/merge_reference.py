"""A small, plain pure-Python merge of FOON text sources, for differential tests of
``foon.merge`` and for ``benchmarks/merge.py``.

It restates the merge rules of ``foon_core::merge`` directly: sources are read in order;
a unit's key at level L is (motion, multiset of its inputs' level-L keys, multiset of its
outputs' level-L keys), where an object's level-3 key is its identity (label, sorted states,
sorted ingredients, container), its level-2 key drops the ingredients and its level-1 key is
its label; the first unit met with a key is kept and every (source, line) where the key was
met is recorded, in reading order; support = the number of distinct sources among them; with
``min_support`` K only units of support >= K are kept. One dict from key to kept unit is the
only look-up table.

The reader follows the text rules of ``foon_reference.parse`` (SEMANTICS.md section 1) for
well-formed files: blank and ``#`` lines skipped, ``//`` ends a unit, a unit without a motion
line or with two is dropped, a last unit without ``//`` is kept; a unit's line is the line of
its first object or motion line. Standard library only (and the reference's object,
``foon_reference.RefObject``).
"""

from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass

from foon_reference import RefObject

Identity = tuple[str, tuple[str, ...], tuple[str, ...], str | None]

_KIND = re.compile(r"^[OSM][0-9]*\t")


#: An object as written in a unit (states and ingredients in line order): the reference's.
Obj = RefObject


@dataclass
class Unit:
    motion: str
    inputs: list[Obj]
    outputs: list[Obj]
    line: int


@dataclass
class Kept:
    """A kept unit: its first copy and every (source, line) its key was met at."""

    unit: Unit
    origins: list[tuple[str, int]]

    @property
    def support(self) -> int:
        return len({s for s, _ in self.origins})


def read_units(text: str) -> list[Unit]:
    """The complete units of FOON text, in order (faulty ones dropped)."""
    units: list[Unit] = []
    inputs: list[Obj] = []
    outputs: list[Obj] = []
    motion: str | None = None
    motions = 0
    start = 0
    last: Obj | None = None

    def close() -> None:
        if start and motions == 1 and motion is not None:
            units.append(Unit(motion, inputs, outputs, start))

    for n, raw in enumerate(text.split("\n"), start=1):
        line = raw.removesuffix("\r")
        if not line.strip() or line.startswith("#"):
            continue
        if line.startswith("//"):
            close()
            inputs, outputs, motion, motions, start, last = [], [], None, 0, 0, None
            continue
        if _KIND.match(line) is None:
            raise ValueError(f"line {n}: unknown line kind")
        fields = line.split("\t")
        while fields and fields[-1] == "":
            fields.pop()
        second = fields[1].lower().rstrip() if len(fields) > 1 else ""
        if not second:
            raise ValueError(f"line {n}: missing field")
        if not start:
            start = n
        kind = line[0]
        if kind == "O":
            last = Obj(second)
            (inputs if motion is None else outputs).append(last)
        elif kind == "S":
            if last is None:
                raise ValueError(f"line {n}: state before any object")
            if len(fields) >= 3:
                v = fields[2].rstrip()
                if v.startswith("{") and v.endswith("}"):
                    last.ingredients = v[1:-1].split(",")
                elif v.startswith("[") and v.endswith("]"):
                    last.container = v[1:-1]
                else:
                    raise ValueError(f"line {n}: expected {{ingredients}} or [container]")
            else:
                last.states.append(second)
        else:
            motions += 1
            if motion is None:
                motion = second
    close()
    return units


def object_key(o: Obj, level: int) -> object:
    """The key of an object at a level: objects equal at the level have equal keys."""
    if level == 1:
        return o.label
    if level == 2:
        return (o.label, tuple(sorted(o.states)), o.container)
    return o.identity()


def unit_key(u: Unit, level: int) -> tuple[str, frozenset[object], frozenset[object]]:
    """Motion, multiset of input keys, multiset of output keys (multisets as frozen counts)."""
    ins = frozenset(Counter(object_key(o, level) for o in u.inputs).items())
    outs = frozenset(Counter(object_key(o, level) for o in u.outputs).items())
    return (u.motion, ins, outs)


def merge(sources: list[tuple[str, str]], level: int = 3, min_support: int = 1) -> list[Kept]:
    """Merge (name, text) sources in order; the kept units in the order they were first met."""
    kept: dict[object, Kept] = {}
    for name, text in sources:
        for u in read_units(text):
            k = unit_key(u, level)
            if k in kept:
                kept[k].origins.append((name, u.line))
            else:
                kept[k] = Kept(u, [(name, u.line)])
    return [k for k in kept.values() if k.support >= min_support]


def objects(kept: list[Kept]) -> list[Identity]:
    """The distinct objects of the kept units, in first-seen order (inputs then outputs)."""
    seen: dict[Identity, None] = {}
    for k in kept:
        for o in k.unit.inputs + k.unit.outputs:
            seen.setdefault(o.identity(), None)
    return list(seen)


def motions(kept: list[Kept]) -> list[str]:
    return list(dict.fromkeys(k.unit.motion for k in kept))


def _obj_text(o: Obj) -> list[str]:
    lines = ["O\t" + o.label] + ["S\t" + s for s in o.states]
    if o.ingredients:
        lines.append("S\tcontains\t{" + ",".join(o.ingredients) + "}")
    if o.container is not None:
        lines.append("S\tin\t[" + o.container + "]")
    return lines


def unit_text(u: Unit) -> str:
    """The course text form of a unit (ends with ``//``, no newline)."""
    lines: list[str] = []
    for o in u.inputs:
        lines += _obj_text(o)
    lines.append("M\t" + u.motion)
    for o in u.outputs:
        lines += _obj_text(o)
    lines.append("//")
    return "\n".join(lines)
