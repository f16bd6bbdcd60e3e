"""foon: fast, exact task-tree retrieval for FOON (Functional Object-Oriented Networks).

A FOON is a graph of functional units (FUs): input objects, one motion, output objects.
Given a kitchen (the objects at hand) and a goal object, a task tree is a set of FUs that
makes the goal. ``foon`` parses every FOON dialect in the wild into a compact index and
plans over it in Rust: the course methods byte for byte, and sound methods whose trees are
always executable.

    >>> import foon
    >>> ex = foon.example()
    >>> tree = ex.foon.plan(ex.goals[0], kitchen=ex.kitchen, motions=ex.motions,
    ...                     utensils=ex.utensils, method="ids")
    >>> tree.solved
    True
"""

from __future__ import annotations

import json
import os
import warnings
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, Generic, Literal, TypeAlias, TypeVar, Union, overload

from foon import _foon
from foon._foon import FoonError, GoalNotFoundError, MissingRateError, ParseError

__version__: str = _foon.__version__

__all__ = [
    "METHODS",
    "Blocked",
    "Finding",
    "Example",
    "Foon",
    "FoonError",
    "FoonWarning",
    "FunctionalUnit",
    "GoalNotFoundError",
    "Kitchen",
    "MissingRateError",
    "MotionRates",
    "Object",
    "ParseError",
    "Planner",
    "TaskTree",
    "TreeCheck",
    "check",
    "example",
    "load",
    "load_utensils",
]

#: Every planning method, in the order comparison tables list them.
METHODS: tuple[str, ...] = tuple(_foon.methods())

Method = Literal[
    "bfs",
    "ids",
    "greedy-success",
    "greedy-inputs",
    "optimal-success",
    "optimal-units",
    "optimal-inputs",
]
PathLike: TypeAlias = Union[str, "os.PathLike[str]"]


class FoonWarning(UserWarning):
    """An annotation fault that did not stop loading (an FU dropped, a missing ``//``)."""


@dataclass(frozen=True)
class Object:
    """An object node: a label, its states, its ingredients and its container.

    Identity ignores the order of states and ingredients (they are multisets).
    """

    label: str
    states: tuple[str, ...] = ()
    ingredients: tuple[str, ...] = ()
    container: str | None = None

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Object:
        """From the kitchen/goal JSON shape ``{"label", "states", "ingredients", "container"}``."""
        if "label" not in d:
            raise ValueError(f"an object needs a 'label': {dict(d)!r}")
        return cls(
            str(d["label"]),
            tuple(d.get("states") or ()),
            tuple(d.get("ingredients") or ()),
            d.get("container"),
        )

    def to_dict(self) -> dict[str, Any]:
        """The kitchen/goal JSON shape."""
        return {
            "label": self.label,
            "states": list(self.states),
            "ingredients": list(self.ingredients),
            "container": self.container,
        }

    def identity(self) -> tuple[str, tuple[str, ...], tuple[str, ...], str | None]:
        """``(label, sorted states, sorted ingredients, container)``."""
        return (self.label, tuple(sorted(self.states)), tuple(sorted(self.ingredients)),
                self.container)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Object) and self.identity() == other.identity()

    def __hash__(self) -> int:
        return hash(self.identity())

    def __str__(self) -> str:
        s = self.label
        if self.states:
            s += " (" + ", ".join(self.states) + ")"
        if self.ingredients:
            s += " {" + ",".join(self.ingredients) + "}"
        if self.container is not None:
            s += f" in [{self.container}]"
        return s

    def _tuple(self) -> tuple[str, list[str], list[str], str | None]:
        return (self.label, list(self.states), list(self.ingredients), self.container)


ObjectLike: TypeAlias = Union[Object, Mapping[str, Any]]


def _as_object(o: ObjectLike) -> Object:
    return o if isinstance(o, Object) else Object.from_dict(o)


def _emit_warnings(items: Sequence[tuple[str | None, int, int, str, str]]) -> None:
    for path, line, col, kind, message in items:
        warnings.warn(f"{path or '<string>'}:{line}:{col}: {message} [{kind}]", FoonWarning,
                      stacklevel=3)


class Kitchen:
    """The objects at hand. An object is available iff its identity equals an item's."""

    def __init__(self, items: Iterable[ObjectLike] = ()) -> None:
        self.items: tuple[Object, ...] = tuple(_as_object(o) for o in items)
        self._cached: list[tuple[str, list[str], list[str], str | None]] | None = None

    @classmethod
    def load(cls, path: PathLike) -> Kitchen:
        """From a JSON list of objects or a file of FOON object blocks (``O``/``S`` lines)."""
        return cls(Object(t[0], tuple(t[1]), tuple(t[2]), t[3])
                   for t in _foon.load_objects(os.fspath(path), "kitchen"))

    @classmethod
    def from_text(cls, text: str | bytes) -> Kitchen:
        """From JSON text or FOON object blocks."""
        return cls(Object(t[0], tuple(t[1]), tuple(t[2]), t[3])
                   for t in _foon.parse_objects(text, "kitchen"))

    def __iter__(self) -> Iterator[Object]:
        return iter(self.items)

    def __len__(self) -> int:
        return len(self.items)

    def __contains__(self, o: object) -> bool:
        return isinstance(o, Object | Mapping) and _as_object(o) in self.items

    def without(self, drop: Iterable[ObjectLike]) -> Kitchen:
        """A copy without the given items."""
        gone = {_as_object(o) for o in drop}
        return Kitchen(o for o in self.items if o not in gone)

    def to_json(self) -> str:
        return json.dumps([o.to_dict() for o in self.items], indent=4)

    def _tuples(self) -> list[tuple[str, list[str], list[str], str | None]]:
        if self._cached is None:
            self._cached = [o._tuple() for o in self.items]
        return self._cached

    def __repr__(self) -> str:
        return f"Kitchen({len(self.items)} items)"


KitchenLike: TypeAlias = Union[Kitchen, Iterable[ObjectLike], str, "os.PathLike[str]", None]


def _as_kitchen(k: KitchenLike) -> Kitchen:
    if k is None:
        return Kitchen()
    if isinstance(k, Kitchen):
        return k
    if isinstance(k, str | os.PathLike):
        return Kitchen.load(k)
    return Kitchen(k)


class MotionRates(Mapping[str, float]):
    """Success rate of each motion (``motion<TAB>rate`` lines in ``motion.txt``)."""

    def __init__(self, rates: Mapping[str, float] | Iterable[tuple[str, float]] = ()) -> None:
        pairs = rates.items() if isinstance(rates, Mapping) else rates
        self._rates: dict[str, float] = {}
        for m, r in pairs:
            r = float(r)
            if not 0.0 <= r <= 1.0:
                raise ValueError(f"rate of {m!r} must be between 0 and 1, not {r}")
            self._rates[str(m)] = r

    @classmethod
    def load(cls, path: PathLike) -> MotionRates:
        return cls(_foon.load_rates(os.fspath(path)))

    @classmethod
    def from_text(cls, text: str | bytes) -> MotionRates:
        return cls(_foon.parse_rates(text))

    def __getitem__(self, motion: str) -> float:
        return self._rates[motion]

    def __iter__(self) -> Iterator[str]:
        return iter(self._rates)

    def __len__(self) -> int:
        return len(self._rates)

    def __repr__(self) -> str:
        return f"MotionRates({len(self._rates)} motions)"


MotionsLike: TypeAlias = Union[MotionRates, Mapping[str, float], str, "os.PathLike[str]", None]


def _as_rates(m: MotionsLike) -> MotionRates | None:
    if m is None or isinstance(m, MotionRates):
        return m
    if isinstance(m, str | os.PathLike):
        return MotionRates.load(m)
    return MotionRates(m)


def load_utensils(path: PathLike) -> list[str]:
    """Reads a utensil list (one name a line)."""
    return list(_foon.load_utensils(os.fspath(path)))


UtensilsLike: TypeAlias = Union[Iterable[str], str, "os.PathLike[str]", None]


def _as_utensils(u: UtensilsLike) -> list[str]:
    if u is None:
        return []
    if isinstance(u, str | os.PathLike):
        return load_utensils(u)
    return [str(x) for x in u]


@dataclass(frozen=True)
class FunctionalUnit:
    """One step: input objects, a motion, output objects."""

    index: int
    motion: str
    inputs: tuple[Object, ...]
    outputs: tuple[Object, ...]
    line: int
    input_ids: tuple[int, ...] = field(repr=False, default=())
    output_ids: tuple[int, ...] = field(repr=False, default=())


T = TypeVar("T")


class _Read(Generic[T]):
    """A :class:`TaskTree` attribute read from the core's result of the same name."""

    def __init__(self, doc: str = "") -> None:
        self.__doc__ = doc
        self.name = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    @overload
    def __get__(self, tree: None, owner: type) -> _Read[T]: ...
    @overload
    def __get__(self, tree: TaskTree, owner: type) -> T: ...
    def __get__(self, tree: TaskTree | None, owner: type) -> _Read[T] | T:
        if tree is None:
            return self
        return self.read(tree)

    def read(self, tree: TaskTree) -> T:
        return getattr(tree._plan, self.name)  # type: ignore[no-any-return]


class _Kept(_Read[T]):
    """Like :class:`_Read`, built once per tree (a list the caller may keep)."""

    def read(self, tree: TaskTree) -> T:
        try:
            return tree._kept[self.name]  # type: ignore[no-any-return]
        except KeyError:
            v = tree._kept[self.name] = self.build(tree, getattr(tree._plan, self.name))
            return v  # type: ignore[no-any-return]

    def build(self, tree: TaskTree, raw: Any) -> Any:
        return raw


class _Objects(_Kept[list[Object]]):
    def build(self, tree: TaskTree, raw: Any) -> Any:
        return [tree.foon.object(o) for o in raw]


class TaskTree:
    """The result of planning one goal. Objects and lists are built from the core's result
    when first read."""

    __slots__ = ("foon", "planner", "_plan", "_kept")

    def __init__(self, foon: Foon, plan: _foon.Plan, planner: Planner | None = None) -> None:
        self.foon = foon
        self.planner = planner
        self._plan = plan
        self._kept: dict[str, Any] = {}

    def __repr__(self) -> str:
        state = "solved" if self.solved else "unsolved"
        return (f"<TaskTree {self.goal} by {self.method}"
                f"{' (course)' if self.compat == 'course' else ''}: {state}, "
                f"{len(self.units)} units>")

    @property
    def goal(self) -> Object:
        return self.foon.object(self._plan.goal)

    @property
    def goal_id(self) -> int:
        return self._plan.goal

    method = _Read[str]()
    compat = _Read[str]('``"course"`` or ``"sound"``.')
    count = _Read[str]('``"nodes"`` or ``"ingredients"``.')
    solved = _Read[bool]()
    units = _Kept[list[int]]("FU indices (0-based, file order after de-duplication), in "
                             "output order.")
    unresolved = _Objects("Course methods: objects reached that are neither in the kitchen "
                          "nor produced.")
    missing = _Objects("Failed sound methods: raw items a tree would need that the kitchen "
                       "lacks.")
    cycle = _Objects("Failed sound methods blocked only by cycles: one blocking cycle "
                     "(first = last).")
    cycle_units = _Kept[list[int]]("The units of that cycle.")
    height = _Read[int | None]("Parallel steps of the tree (the goal's rank using only its "
                               "units).")
    success = _Read[float | None]("Product of the motion success rates of the units (None "
                                  "without a rate table).")
    cost = _Read[float | None]("The optimal methods' objective value (None for the others).")
    leaf_inputs = _Read[int]("Distinct kitchen items the units need.")
    expanded = _Read[int]("Objects expanded by the search.")
    peak_frontier = _Read[int]("Largest frontier (open list) during the search.")
    seconds = _Read[float]("Time spent planning, in seconds.")

    def __len__(self) -> int:
        return len(self.units)

    def __iter__(self) -> Iterator[FunctionalUnit]:
        return (self.foon.fu(i) for i in self.units)

    @property
    def fu_count(self) -> int:
        return len(self.units)

    def to_text(self) -> str:
        """The tree in the course output file form (``//`` then each FU)."""
        return self.foon._native.tree_text(self.units)

    def explanation(self) -> str:
        """One line saying why the goal could not be made (empty when solved)."""
        if self.solved:
            return ""
        if self.unresolved:
            return "not in the kitchen and not produced by any unit: " + "; ".join(
                str(o) for o in self.unresolved)
        if self.missing:
            return "missing from the kitchen: " + "; ".join(str(o) for o in self.missing)
        if self.cycle:
            steps = " -> ".join(str(o) for o in self.cycle)
            return f"every way to make it relies on a circular step: {steps}"
        if self.method == "optimal-success":
            return "every way to make it uses a motion whose success rate is 0"
        return "no task tree exists"

    def to_dict(self) -> dict[str, Any]:
        """The machine-readable form (what ``foon plan --format json`` prints)."""
        return {
            "goal": self.goal.to_dict(),
            "method": self.method,
            "compat": self.compat,
            "count": self.count,
            "solved": self.solved,
            "units": self.units,
            "fu_count": self.fu_count,
            "height": self.height,
            "success": self.success,
            "cost": self.cost,
            "leaf_inputs": self.leaf_inputs,
            "expanded": self.expanded,
            "peak_frontier": self.peak_frontier,
            "seconds": self.seconds,
            "unresolved": [o.to_dict() for o in self.unresolved],
            "missing": [o.to_dict() for o in self.missing],
            "cycle": [o.to_dict() for o in self.cycle],
            "cycle_units": self.cycle_units,
            "explanation": self.explanation(),
        }

    def to_json(self, indent: int | None = 2) -> str:
        return json.dumps(self.to_dict(), indent=indent)

    def is_valid(self, kitchen: KitchenLike = None, utensils: UtensilsLike = None) -> bool:
        """Whether the tree's units, in some order, make the goal from the kitchen (the one
        planned with, unless another kitchen or utensil list is given)."""
        p = self.planner
        if p is None or kitchen is not None or utensils is not None:
            p = self.foon.planner(
                kitchen if kitchen is not None else (p.kitchen if p else None),
                utensils=utensils if utensils is not None else (p.utensils if p else None))
        valid, _, _ = p._native.check_tree(self.units, self.goal_id)
        return bool(valid)


@dataclass(frozen=True)
class Blocked:
    """The first unit of a tree file that cannot run in the order written."""

    position: int
    line: int
    missing: list[Object]


@dataclass(frozen=True)
class TreeCheck:
    """What :meth:`Foon.verify` found."""

    valid: bool
    units: int
    goal_made: bool
    goal_absent: bool
    blocked: Blocked | None
    #: (position, line) of units that are not units of the FOON.
    foreign_units: list[tuple[int, int]]


class Foon:
    """A parsed FOON: an immutable compact index, safe to share between threads."""

    def __init__(self, native: _foon.Foon) -> None:
        self._native = native

    @classmethod
    def load(cls, path: PathLike, *, strict: bool = False) -> Foon:
        """Reads a FOON file of any dialect. Annotation faults are reported as
        :class:`FoonWarning` (errors with ``strict=True``)."""
        f = cls(_foon.Foon.load(os.fspath(path), strict=strict))
        _emit_warnings(f._native.warnings())
        return f

    @classmethod
    def from_text(cls, text: str | bytes, *, strict: bool = False,
                  path: PathLike | None = None) -> Foon:
        """Parses FOON text; ``path`` only names the source in messages."""
        f = cls(_foon.Foon.from_text(text, strict=strict,
                                     path=None if path is None else os.fspath(path)))
        _emit_warnings(f._native.warnings())
        return f

    @property
    def fu_count(self) -> int:
        return int(self._native.fu_count)

    @property
    def object_count(self) -> int:
        return int(self._native.object_count)

    def __len__(self) -> int:
        return self.fu_count

    def __repr__(self) -> str:
        src = self._native.source
        return f"<Foon {self.fu_count} units, {self.object_count} objects{f' from {src}' if src else ''}>"

    def stats(self) -> dict[str, int]:
        """Counts: functional units, objects, produced objects, motions, ..."""
        return dict(self._native.stats())

    @property
    def warnings(self) -> list[tuple[str | None, int, int, str, str]]:
        """Load warnings as ``(path, line, column, kind, message)``."""
        return list(self._native.warnings())

    def object(self, i: int) -> Object:
        """Object ``i`` (ids in first-seen order), in its first written form."""
        label, states, ingredients, container = self._native.object(i)
        return Object(label, tuple(states), tuple(ingredients), container)

    def objects(self) -> Iterator[Object]:
        return (self.object(i) for i in range(self.object_count))

    def fu(self, i: int) -> FunctionalUnit:
        """Functional unit ``i`` (file order after dropping faulty and duplicate units)."""
        motion, ins, outs, line = self._native.fu(i)
        return FunctionalUnit(i, motion, tuple(self.object(o) for o in ins),
                              tuple(self.object(o) for o in outs), line, tuple(ins), tuple(outs))

    def fu_text(self, i: int) -> str:
        return self._native.fu_text(i)

    def to_text(self) -> str:
        """The whole FOON in the course text form."""
        return self._native.to_text()

    def producers(self, o: int) -> list[int]:
        return list(self._native.producers(o))

    def consumers(self, o: int) -> list[int]:
        return list(self._native.consumers(o))

    def find(self, goal: ObjectLike) -> int | None:
        """The id of the object with this identity, or None."""
        o = _as_object(goal)
        return self._native.find(o.label, list(o.states), list(o.ingredients), o.container)

    def with_label(self, label: str) -> list[Object]:
        """Every object with this label."""
        return [self.object(i) for i in self._native.objects_with_label(label)]

    def goal_id(self, goal: ObjectLike | int | str) -> int:
        """Resolves a goal: an object id, an object (or its dict), or a label that only one
        object has. Raises :class:`GoalNotFoundError`."""
        if isinstance(goal, bool):
            raise TypeError("a goal is an object, an object id or a label")
        if isinstance(goal, int):
            if not 0 <= goal < self.object_count:
                raise GoalNotFoundError(f"The goal node does not exist: object id {goal}")
            return goal
        if isinstance(goal, str):
            ids = self._native.objects_with_label(goal)
            if len(ids) == 1:
                return int(ids[0])
            if not ids:
                raise GoalNotFoundError(f"The goal node does not exist: {goal}")
            shown = "\n".join(f"  {self.object(i)}" for i in ids[:20])
            more = f"\n  ... and {len(ids) - 20} more" if len(ids) > 20 else ""
            raise GoalNotFoundError(
                f"the label '{goal}' matches {len(ids)} objects; give states and container "
                f"to choose one:\n{shown}{more}")
        o = _as_object(goal)
        i = self.find(o)
        if i is None:
            raise GoalNotFoundError(f"The goal node does not exist: {o}")
        return i

    def plan(
        self,
        goal: ObjectLike | int | str,
        kitchen: KitchenLike = None,
        method: Method | str = "ids",
        *,
        compat: Literal["course"] | None = None,
        count: Literal["nodes", "ingredients"] = "nodes",
        motions: MotionsLike = None,
        utensils: UtensilsLike = None,
        default_rate: float | None = None,
    ) -> TaskTree:
        """Plans a task tree for ``goal`` from ``kitchen``.

        ``method``: ``ids`` (default), ``greedy-success``, ``greedy-inputs``,
        ``optimal-success``, ``optimal-units``, ``optimal-inputs`` or ``bfs``. Sound unless
        ``compat="course"``, which reproduces the course code's trees byte for byte.
        """
        return self.plan_many([goal], kitchen, method, compat=compat, count=count,
                              motions=motions, utensils=utensils, default_rate=default_rate,
                              threads=1)[0]

    def plan_many(
        self,
        goals: Iterable[ObjectLike | int | str],
        kitchen: KitchenLike = None,
        method: Method | str = "ids",
        *,
        compat: Literal["course"] | None = None,
        count: Literal["nodes", "ingredients"] = "nodes",
        motions: MotionsLike = None,
        utensils: UtensilsLike = None,
        default_rate: float | None = None,
        threads: int | None = None,
    ) -> list[TaskTree]:
        """Plans many goals in one call: the kitchen is matched once, the interpreter is
        released, and the goals are spread over ``threads`` threads (all cores by default)."""
        p = self.planner(kitchen, motions=motions, utensils=utensils, default_rate=default_rate)
        return p.plan_many(goals, method, compat=compat, count=count, threads=threads)

    def planner(
        self,
        kitchen: KitchenLike = None,
        *,
        motions: MotionsLike = None,
        utensils: UtensilsLike = None,
        default_rate: float | None = None,
    ) -> Planner:
        """Prepares the kitchen, utensils and motion rates once, for many plans."""
        return Planner(self, kitchen, motions=motions, utensils=utensils,
                       default_rate=default_rate)

    def ranks(self, kitchen: KitchenLike = None, utensils: UtensilsLike = None) -> list[int | None]:
        """Rank of every object from the kitchen: the fewest parallel steps that make it
        (None when it cannot be made)."""
        return self.planner(kitchen, utensils=utensils).ranks()

    def verify(
        self,
        tree: Foon | PathLike,
        goal: ObjectLike,
        kitchen: KitchenLike = None,
        utensils: UtensilsLike = None,
    ) -> TreeCheck:
        """Checks a task tree (a tree file, or a :class:`Foon` parsed from one) in the order
        its units are written: each unit's needed inputs must be in the kitchen or made by an
        earlier unit, and the goal must be made. Also lists units that are not in this FOON."""
        t = tree if isinstance(tree, Foon) else Foon.load(tree)
        d = self._native.verify_tree(t._native, _as_kitchen(kitchen)._tuples(),
                                     _as_utensils(utensils), _as_object(goal)._tuple())
        blocked = None
        if d["blocked"] is not None:
            pos, line, missing = d["blocked"]
            blocked = Blocked(pos, line, [Object(m[0], tuple(m[1]), tuple(m[2]), m[3])
                                          for m in missing])
        return TreeCheck(valid=d["valid"], units=d["units"], goal_made=d["goal_made"],
                         goal_absent=d["goal_absent"], blocked=blocked,
                         foreign_units=[tuple(x) for x in d["foreign_units"]])



class Planner:
    """A FOON with a kitchen, utensils and motion rates prepared once: plan any number of
    goals without paying for the preparation again (it is what :meth:`Foon.plan` builds
    for each call)."""

    def __init__(
        self,
        foon: Foon,
        kitchen: KitchenLike = None,
        *,
        motions: MotionsLike = None,
        utensils: UtensilsLike = None,
        default_rate: float | None = None,
    ) -> None:
        self.foon = foon
        self.kitchen = _as_kitchen(kitchen)
        self.motions = _as_rates(motions)
        self.utensils = _as_utensils(utensils)
        self.default_rate = default_rate
        self._native = _foon.Planner(
            foon._native, self.kitchen._tuples(), self.utensils,
            None if self.motions is None else list(self.motions.items()), default_rate)

    def plan(
        self,
        goal: ObjectLike | int | str,
        method: Method | str = "ids",
        *,
        compat: Literal["course"] | None = None,
        count: Literal["nodes", "ingredients"] = "nodes",
    ) -> TaskTree:
        """Plans one goal (see :meth:`Foon.plan`)."""
        return self.plan_many([goal], method, compat=compat, count=count, threads=1)[0]

    def plan_many(
        self,
        goals: Iterable[ObjectLike | int | str],
        method: Method | str = "ids",
        *,
        compat: Literal["course"] | None = None,
        count: Literal["nodes", "ingredients"] = "nodes",
        threads: int | None = None,
    ) -> list[TaskTree]:
        """Plans many goals, spread over ``threads`` threads (all cores by default)."""
        if threads is not None and threads < 1:
            raise ValueError("threads must be at least 1")
        ids = [self.foon.goal_id(g) for g in goals]
        raw = self._native.plan(ids, str(method), compat or "sound", count, threads)
        return [self._tree(d) for d in raw]

    def ranks(self) -> list[int | None]:
        """Rank of every object: the fewest parallel steps that make it from the kitchen
        (None when it cannot be made)."""
        return list(self._native.ranks())

    def _tree(self, plan: _foon.Plan) -> TaskTree:
        return TaskTree(self.foon, plan, self)


@dataclass(frozen=True)
class Finding:
    """One problem found by :func:`check`."""

    path: str | None
    line: int
    column: int
    severity: Literal["error", "warning", "note"]
    code: str
    message: str

    def __str__(self) -> str:
        return (f"{self.path or '<string>'}:{self.line}:{self.column}: {self.severity}: "
                f"{self.message} [{self.code}]")


def check(
    paths: PathLike | Iterable[PathLike],
    *,
    kitchen: KitchenLike = None,
    motions: MotionsLike = None,
    utensils: UtensilsLike = None,
) -> list[Finding]:
    """Lints FOON files: parse errors, annotation faults (no motion, two motions, no final
    ``//``), duplicate units, ingredients with stray spaces or listed twice, empty
    containers, objects reachable only through cycles; with a kitchen, objects that are used
    but never produced nor in it; with motion rates, motions without a rate. Files of object
    blocks (kitchens, goals) are checked as such."""
    ps = [paths] if isinstance(paths, str | os.PathLike) else list(paths)
    rates = _as_rates(motions)
    raw = _foon.check([os.fspath(p) for p in ps],
                      None if kitchen is None else _as_kitchen(kitchen)._tuples(),
                      None if rates is None else list(rates.items()), _as_utensils(utensils))
    return [Finding(*f) for f in raw]  # type: ignore[arg-type]


def load(path: PathLike, *, strict: bool = False) -> Foon:
    """Reads a FOON file of any dialect (see :meth:`Foon.load`)."""
    return Foon.load(path, strict=strict)


@dataclass(frozen=True)
class Example:
    """The small example FOON shipped with the package, with its kitchen, motion rates,
    utensils and goals (the first goal is the default one)."""

    foon: Foon
    kitchen: Kitchen
    motions: MotionRates
    utensils: list[str]
    goals: list[Object]
    paths: dict[str, Path]


def _data_path(name: str) -> Path:
    return Path(str(resources.files("foon") / "data" / name))


def example() -> Example:
    """Loads the embedded example (see ``foon/data/README.md``)."""
    paths = {k: _data_path(n) for k, n in (("foon", "example.foon"), ("kitchen", "kitchen.json"),
                                           ("motions", "motion.txt"),
                                           ("utensils", "utensils.txt"),
                                           ("goals", "goals.json"))}
    goals = [Object(t[0], tuple(t[1]), tuple(t[2]), t[3])
             for t in _foon.load_objects(os.fspath(paths["goals"]), "goal")]
    return Example(load(paths["foon"]), Kitchen.load(paths["kitchen"]),
                   MotionRates.load(paths["motions"]), load_utensils(paths["utensils"]), goals,
                   paths)
