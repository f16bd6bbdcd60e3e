"""A pure-Python FOON parser that follows the course rules the way the course scripts do:
objects and functional units are kept in plain lists and every lookup (is this object known?
is this unit a duplicate?) scans the list. This is the baseline users run today."""

from __future__ import annotations


class Obj:
    __slots__ = ("container", "id", "ingredients", "label", "states")

    def __init__(self, label: str) -> None:
        self.label = label
        self.states: list[str] = []
        self.ingredients: list[str] = []
        self.container: str | None = None
        self.id = -1

    def same(self, other: Obj) -> bool:
        return (
            self.label == other.label
            and sorted(self.states) == sorted(other.states)
            and sorted(self.ingredients) == sorted(other.ingredients)
            and self.container == other.container
        )

    def index_in(self, objs: list[Obj]) -> int:
        for i, o in enumerate(objs):
            if self.same(o):
                return i
        return -1


class Unit:
    __slots__ = ("inputs", "motion", "outputs")

    def __init__(self) -> None:
        self.inputs: list[Obj] = []
        self.outputs: list[Obj] = []
        self.motion = ""

    def repeats(self, units: list[Unit]) -> bool:
        for u in units:
            if (
                u.motion != self.motion
                or len(u.inputs) != len(self.inputs)
                or len(u.outputs) != len(self.outputs)
            ):
                continue
            if all(o.index_in(u.inputs) != -1 for o in self.inputs) and all(
                o.index_in(u.outputs) != -1 for o in self.outputs
            ):
                return True
        return False


def parse(path: str) -> tuple[list[Unit], list[Obj], dict[int, list[int]]]:
    units: list[Unit] = []
    unit = Unit()
    obj: Obj | None = None
    inputs = True
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            if line.startswith("//"):
                if obj is not None:
                    unit.outputs.append(obj)
                    obj = None
                if unit.motion:
                    units.append(unit)
                    unit = Unit()
                inputs = True
                continue
            f = line.split("\t")
            if len(f) < 2:
                continue
            f[1] = f[1].lower().rstrip()
            if line.startswith("O"):
                if obj is not None:
                    (unit.inputs if inputs else unit.outputs).append(obj)
                obj = Obj(f[1])
            elif line.startswith("S") and obj is not None:
                if len(f) > 2 and f[2].strip():
                    v = f[2].rstrip()
                    if v.startswith("{"):
                        obj.ingredients = v[1:-1].split(",")
                    elif v.startswith("["):
                        obj.container = v[1:-1]
                else:
                    obj.states.append(f[1])
            elif line.startswith("M"):
                if obj is not None:
                    unit.inputs.append(obj)
                obj = None
                inputs = False
                unit.motion = f[1]
    kept: list[Unit] = []
    for u in units:
        if not u.repeats(kept):
            kept.append(u)
    objects: list[Obj] = []
    for u in kept:
        for o in u.inputs + u.outputs:
            i = o.index_in(objects)
            if i == -1:
                o.id = len(objects)
                objects.append(o)
            else:
                o.id = i
    producers: dict[int, list[int]] = {}
    for k, u in enumerate(kept):
        for o in u.outputs:
            if o.states or o.ingredients or o.container is not None:
                producers.setdefault(o.id, []).append(k)
    return kept, objects, producers
