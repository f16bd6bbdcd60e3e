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

# Importing foon is kept cheap (the command line pays for it on every call): no typing,
# json, dataclasses, pathlib or importlib.resources at import time; modules that only some
# calls need are imported inside them.
from __future__ import annotations

import os
from _collections_abc import Mapping

from foon import _foon
from foon._foon import FoonError, GoalNotFoundError, MissingRateError, OutputError, ParseError

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable, Iterable, Iterator, Sequence
    from pathlib import Path
    from typing import Any, Literal, TypeAlias

    Method: TypeAlias = Literal[
        "bfs",
        "ids",
        "greedy-success",
        "greedy-inputs",
        "optimal-success",
        "optimal-units",
        "optimal-inputs",
        "optimal-shared",
    ]
    PathLike: TypeAlias = str | bytes | os.PathLike[str] | os.PathLike[bytes]
    ObjectLike: TypeAlias = "Object | Mapping[str, Any]"
    KitchenLike: TypeAlias = "Kitchen | Iterable[ObjectLike] | PathLike | None"
    MotionsLike: TypeAlias = "MotionRates | Mapping[str, float] | PathLike | None"
    UtensilsLike: TypeAlias = "Iterable[str] | PathLike | None"
    GoalLike: TypeAlias = "ObjectLike | int | str"
    _Fields: TypeAlias = tuple[str, tuple[str, ...], tuple[str, ...], str | None]

    from foon._batch import BatchSummary, CacheInfo, batch, batch_cache_info, clear_batch_cache
    from foon._explain import GoalExplanation, Similar
    from foon._kbest import RankedTree
    from foon._kitchens import KitchenSet
    from foon._merge import MergeReport, load_merged, merge, merge_report
    from foon._split import Profile, Profiles, SplitResult
    from foon._synth import (
        MAX_SYNTH_UNITS,
        SYNTH_TEXT_LIMIT,
        SynthReport,
        synth,
        synth_goals,
        synth_kitchen,
        synth_motions,
    )

__version__: str = _foon.__version__

__all__ = [
    "FORMATS",
    "MAX_PICTURE_NODES",
    "MAX_SYNTH_UNITS",
    "METHODS",
    "SYNTH_TEXT_LIMIT",
    "BatchSummary",
    "Blocked",
    "CacheInfo",
    "Example",
    "Finding",
    "Foon",
    "FoonError",
    "FoonWarning",
    "FunctionalUnit",
    "GoalExplanation",
    "GoalNotFoundError",
    "Kitchen",
    "KitchenSet",
    "MergeReport",
    "MissingRateError",
    "MotionRates",
    "Object",
    "OutputError",
    "ParseError",
    "Planner",
    "Profile",
    "Profiles",
    "RankedTree",
    "Similar",
    "SplitResult",
    "SynthReport",
    "TaskTree",
    "TreeCheck",
    "batch",
    "batch_cache_info",
    "check",
    "clear_batch_cache",
    "example",
    "load",
    "load_goals",
    "load_merged",
    "load_utensils",
    "merge",
    "merge_report",
    "synth",
    "synth_goals",
    "synth_kitchen",
    "synth_motions",
]

#: Names defined in submodules that ``import foon`` does not load until they are used.
_LAZY: dict[str, str] = {
    **dict.fromkeys(
        (
            "MAX_SYNTH_UNITS",
            "SYNTH_TEXT_LIMIT",
            "SynthReport",
            "synth",
            "synth_goals",
            "synth_kitchen",
            "synth_motions",
        ),
        "foon._synth",
    ),
    **dict.fromkeys(("MergeReport", "load_merged", "merge", "merge_report"), "foon._merge"),
    "RankedTree": "foon._kbest",
    **dict.fromkeys(("GoalExplanation", "Similar"), "foon._explain"),
    **dict.fromkeys(("Profile", "Profiles", "SplitResult"), "foon._split"),
    "KitchenSet": "foon._kitchens",
    **dict.fromkeys(
        ("BatchSummary", "CacheInfo", "batch", "batch_cache_info", "clear_batch_cache"),
        "foon._batch",
    ),
}


def __getattr__(name: str) -> object:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'foon' has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


#: Every planning method, in the order comparison tables list them.
METHODS: tuple[str, ...] = tuple(_foon.methods())

#: Every output format: name -> (extension, MIME type, binary, needs Graphviz's ``dot``,
#: writes a task tree, writes a FOON, writes a comparison).
FORMATS: dict[str, tuple[str, str, bool, bool, bool, bool, bool]] = {
    f[0]: f[1:] for f in _foon.formats()
}


#: Pictures (svg, png, pdf, html) refuse graphs of more nodes (objects + motions) than this
#: unless given a larger ``max_nodes``: Graphviz takes minutes on them.
MAX_PICTURE_NODES: int = _foon.MAX_PICTURE_NODES


def _out(data: bytes, format: str) -> str | bytes:
    """Text formats as str, binary ones (png, pdf) as bytes."""
    return data if FORMATS[format][2] else data.decode("utf-8")


_new = object.__new__
_set = object.__setattr__


def _count(n: int, one: str, many: str | None = None) -> str:
    """``"1 unit"``, ``"2 units"``: a count with its noun in the right number."""
    return f"{n} {one if n == 1 else (many or one + 's')}"


_PATH_TYPES = (str, bytes, os.PathLike)


def _type(v: object) -> str:
    return type(v).__name__


class FoonWarning(UserWarning):
    """An annotation fault that did not stop loading (an FU dropped, a missing ``//``)."""


class _Frozen:
    __slots__ = ()

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError(f"{type(self).__name__} is immutable")

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"{type(self).__name__} is immutable")


class Object(_Frozen):
    """An object node: a label, its states, its ingredients and its container.

    Identity ignores the order of states and ingredients (they are multisets). The fields are
    checked by the core's rule: ``label`` a non-empty ``str``, ``states`` and ``ingredients``
    sequences of ``str`` (not a ``str``), ``container`` a ``str`` or ``None``.
    """

    __slots__ = ("_identity", "container", "ingredients", "label", "states")
    __match_args__ = ("label", "states", "ingredients", "container")

    label: str
    states: tuple[str, ...]
    ingredients: tuple[str, ...]
    container: str | None
    _identity: tuple[str, tuple[str, ...], tuple[str, ...], str | None]

    def __init__(
        self,
        label: str,
        states: Iterable[str] = (),
        ingredients: Iterable[str] = (),
        container: str | None = None,
    ) -> None:
        _fill(self, _foon.object_fields(label, states, ingredients, container))

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Object:
        """From the kitchen/goal JSON shape ``{"label", "states", "ingredients", "container"}``
        (checked as the core checks kitchen and goal files)."""
        return _fill(_new(cls), _foon.object_fields_of_mapping(d))

    def to_dict(self) -> dict[str, Any]:
        """The kitchen/goal JSON shape."""
        return {
            "label": self.label,
            "states": list(self.states),
            "ingredients": list(self.ingredients),
            "container": self.container,
        }

    def identity(self) -> tuple[str, tuple[str, ...], tuple[str, ...], str | None]:
        """``(label, sorted states, sorted ingredients, container)``, by the core's rule
        (computed once per object)."""
        try:
            return self._identity
        except AttributeError:
            label, states, ingredients, container = _foon.object_identity(*self._fields())
            ident = (label, tuple(states), tuple(ingredients), container)
            _set(self, "_identity", ident)
            return ident

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Object) and self.identity() == other.identity()

    def __hash__(self) -> int:
        return hash(self.identity())

    def __repr__(self) -> str:
        return (
            f"Object(label={self.label!r}, states={self.states!r}, "
            f"ingredients={self.ingredients!r}, container={self.container!r})"
        )

    def __str__(self) -> str:
        """``label (states) {ingredients} in [container]`` (the core's one-line form)."""
        return _foon.object_text(*self._fields())

    def __reduce__(self) -> tuple[Any, ...]:
        return (Object, self._fields())

    def _fields(self) -> _Fields:
        return (self.label, self.states, self.ingredients, self.container)

    def _tuple(self) -> tuple[str, list[str], list[str], str | None]:
        return (self.label, list(self.states), list(self.ingredients), self.container)


def _fill(o: Object, fields: _Fields) -> Object:
    label, states, ingredients, container = fields
    _set(o, "label", label)
    _set(o, "states", states)
    _set(o, "ingredients", ingredients)
    _set(o, "container", container)
    return o


def _object(t: tuple[str, Sequence[str], Sequence[str], str | None]) -> Object:
    """An object from fields the core gives (already checked)."""
    return _fill(_new(Object), (t[0], tuple(t[1]), tuple(t[2]), t[3]))


def _as_object(o: ObjectLike, what: str = "an object") -> Object:
    if isinstance(o, Object):
        return o
    if isinstance(o, Mapping):
        return Object.from_dict(o)
    raise TypeError(f"{what} must be an Object or a mapping, not {_type(o)}")


def _emit_warnings(items: Sequence[tuple[str | None, int, int, str, str]]) -> None:
    """Issues load warnings at the first caller outside this package."""
    if not items:
        return
    import sys
    import warnings

    level, frame = 1, sys._getframe(0)
    while frame is not None and frame.f_globals.get("__name__", "").partition(".")[0] == "foon":
        frame = frame.f_back  # type: ignore[assignment]
        level += 1
    for path, line, col, kind, message in items:
        warnings.warn(
            f"{path or '<string>'}:{line}:{col}: {message} [{kind}]", FoonWarning, stacklevel=level
        )


class Kitchen:
    """The objects at hand. An object is available iff its identity equals an item's.

    A handle on the core's kitchen: a set of identities (an item repeated, in any order of
    its states and ingredients, counts once) kept in the order of first appearance. Reading,
    matching and comparing happen in the core; items become :class:`Object` s only when they
    are asked for (iteration, ``items``). Equality ignores the order of the items; the
    ``fingerprint`` names the set on any machine."""

    __slots__ = ("_native",)

    _native: _foon.Kitchen

    def __init__(self, items: Iterable[ObjectLike] = ()) -> None:
        if isinstance(items, (*_PATH_TYPES, Mapping, Object)):
            raise TypeError(
                f"items must be an iterable of objects, not {_type(items)} (use Kitchen.load "
                "for a file)"
            )
        if isinstance(items, Kitchen):
            self._native = items._native
            return
        self._native = _foon.Kitchen([_as_object(o, "a kitchen item")._tuple() for o in items])

    @classmethod
    def load(cls, path: PathLike) -> Kitchen:
        """From a JSON list of objects or a file of FOON object blocks (``O``/``S`` lines)."""
        return _kitchen(_foon.Kitchen.load(path))

    @classmethod
    def from_text(cls, text: str | bytes) -> Kitchen:
        """From JSON text or FOON object blocks."""
        return _kitchen(_foon.Kitchen.parse(text))

    @property
    def items(self) -> tuple[Object, ...]:
        """Every item, as an :class:`Object` (built on each call)."""
        return tuple(self)

    @property
    def fingerprint(self) -> str:
        """32 hex digits naming the set of identities, the same on every machine and for
        every order of the items."""
        return self._native.fingerprint

    def __iter__(self) -> Iterator[Object]:
        n, native = len(self._native), self._native
        for start in range(0, n, 1024):
            for t in native.slice(start, start + 1024):
                yield _object(t)

    def __len__(self) -> int:
        return len(self._native)

    def __getitem__(self, i: int) -> Object:
        if not isinstance(i, int):
            raise TypeError(f"kitchen indices must be integers, not {_type(i)}")
        n = len(self._native)
        if not -n <= i < n:
            raise IndexError(f"kitchen index {i} out of range ({n} items)")
        return _object(self._native.get(i % n))

    def __contains__(self, o: object) -> bool:
        return isinstance(o, Object | Mapping) and self._native.contains(_as_object(o)._tuple())

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Kitchen) and self._native.equals(other._native)

    def __hash__(self) -> int:
        return hash(self._native.fingerprint)

    def __reduce__(self) -> tuple[Any, ...]:
        return (_kitchen_of_bytes, (self._native.to_bytes(),))

    def without(self, drop: Iterable[ObjectLike]) -> Kitchen:
        """A copy without the given items."""
        return _kitchen(self._native.without(_as_kitchen(drop)._native))

    def with_items(self, add: Iterable[ObjectLike]) -> Kitchen:
        """A copy with the given items added (after its own, those it lacks, in order)."""
        return _kitchen(self._native.with_items(_as_kitchen(add)._native))

    def to_json(self) -> str:
        """The kitchen as a JSON list of objects (the kitchen file shape)."""
        return self._native.to_json()

    def _tuples(self) -> list[tuple[str, list[str], list[str], str | None]]:
        """The items as field tuples, for the calls that take a list of objects."""
        return self._native.tuples()

    def __repr__(self) -> str:
        return f"Kitchen({len(self._native)} items)"


def _kitchen(native: _foon.Kitchen) -> Kitchen:
    k: Kitchen = _new(Kitchen)
    k._native = native
    return k


def _kitchen_of_bytes(data: bytes) -> Kitchen:
    """A pickled kitchen, from its compact bytes."""
    return _kitchen(_foon.Kitchen.from_bytes(data))


def _as_kitchen(k: KitchenLike) -> Kitchen:
    if k is None:
        return Kitchen()
    if isinstance(k, Kitchen):
        return k
    if isinstance(k, _PATH_TYPES):
        return Kitchen.load(k)
    if isinstance(k, Mapping | Object) or not hasattr(k, "__iter__"):
        raise TypeError(
            f"kitchen must be a Kitchen, a path or an iterable of objects, not {_type(k)}"
        )
    return Kitchen(k)


def _as_items(items: Iterable[ObjectLike] | None, name: str) -> Kitchen:
    """Items given as objects (a kitchen change): ``TypeError`` naming the argument for
    anything else (a path among them: a change is not read from a file)."""
    if items is None:
        return Kitchen()
    if isinstance(items, Kitchen):
        return items
    if isinstance(items, (*_PATH_TYPES, Mapping, Object)) or not hasattr(items, "__iter__"):
        raise TypeError(f"{name} must be an iterable of objects, not {_type(items)}")
    return Kitchen(items)


class MotionRates(Mapping[str, float]):
    """Success rate of each motion (``motion<TAB>rate`` lines in ``motion.txt``); every rate
    is between 0 and 1 (checked by the core)."""

    def __init__(self, rates: Mapping[str, float] | Iterable[tuple[str, float]] = ()) -> None:
        pairs = rates.items() if isinstance(rates, Mapping) else rates
        # Names follow the rate file's rule (trimmed, lower-cased), checked by the core.
        self._rates: dict[str, float] = dict(_foon.check_rates(pairs))

    @classmethod
    def load(cls, path: PathLike) -> MotionRates:
        return cls(_foon.load_rates(path))

    @classmethod
    def from_text(cls, text: str | bytes) -> MotionRates:
        return cls(_foon.parse_rates(text))

    def __getitem__(self, motion: str) -> float:
        return self._rates[motion]

    def __iter__(self) -> Iterator[str]:
        return iter(self._rates)

    def __len__(self) -> int:
        return len(self._rates)

    def __hash__(self) -> int:
        return hash(frozenset(self._rates.items()))

    def __repr__(self) -> str:
        return f"MotionRates({len(self._rates)} motions)"


def _as_rates(m: MotionsLike) -> MotionRates | None:
    if m is None or isinstance(m, MotionRates):
        return m
    if isinstance(m, _PATH_TYPES):
        return MotionRates.load(m)
    return MotionRates(m)


def load_utensils(path: PathLike) -> list[str]:
    """Reads a utensil list (one name a line)."""
    return list(_foon.load_utensils(path))


def load_goals(path: PathLike) -> list[Object]:
    """Reads goals: a JSON list of objects, one JSON object, or FOON object blocks (``O``/``S``
    lines), checked as the command line's ``--goals`` file is."""
    return [_object(t) for t in _foon.load_objects(path, "goal")]


def _as_utensils(u: UtensilsLike) -> list[str]:
    if u is None:
        return []
    if isinstance(u, _PATH_TYPES):
        return load_utensils(u)
    try:
        items = list(u)
    except TypeError:
        raise TypeError(
            f"utensils must be a path or an iterable of str, not {type(u).__name__}"
        ) from None
    for i, x in enumerate(items):
        if not isinstance(x, str):
            raise TypeError(f"utensils[{i}] must be a str, not {type(x).__name__}")
    return items


class FunctionalUnit:
    """One step: input objects, a motion, output objects.

    Units of a :class:`TaskTree` or a :class:`Foon` are light views: the motion, the line and
    the objects are read from the index when first asked for.
    """

    __slots__ = ("_foon", "_index", "_inputs", "_outputs", "_raw")

    _foon: Foon | None
    _index: int
    _raw: tuple[str, Sequence[int], Sequence[int], int] | None
    _inputs: tuple[Object, ...] | None
    _outputs: tuple[Object, ...] | None

    def __init__(
        self,
        index: int,
        motion: str,
        inputs: Iterable[Object],
        outputs: Iterable[Object],
        line: int,
        input_ids: Iterable[int] = (),
        output_ids: Iterable[int] = (),
    ) -> None:
        self._foon = None
        self._index = index
        self._raw = (motion, tuple(input_ids), tuple(output_ids), line)
        self._inputs = tuple(inputs)
        self._outputs = tuple(outputs)

    def _read(self) -> tuple[str, Sequence[int], Sequence[int], int]:
        raw = self._raw
        if raw is None:
            assert self._foon is not None
            raw = self._raw = self._foon._native.fu(self._index)
        return raw

    @property
    def index(self) -> int:
        return self._index

    @property
    def motion(self) -> str:
        return self._read()[0]

    @property
    def line(self) -> int:
        return self._read()[3]

    @property
    def input_ids(self) -> tuple[int, ...]:
        return tuple(self._read()[1])

    @property
    def output_ids(self) -> tuple[int, ...]:
        return tuple(self._read()[2])

    @property
    def inputs(self) -> tuple[Object, ...]:
        if self._inputs is None:
            assert self._foon is not None
            self._inputs = tuple(map(self._foon.object, self._read()[1]))
        return self._inputs

    @property
    def outputs(self) -> tuple[Object, ...]:
        if self._outputs is None:
            assert self._foon is not None
            self._outputs = tuple(map(self._foon.object, self._read()[2]))
        return self._outputs

    def _key(self) -> tuple[Any, ...]:
        return (self.index, self.motion, self.inputs, self.outputs, self.line)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, FunctionalUnit) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash((self.index, self.motion, self.line))

    def __reduce__(self) -> tuple[Any, ...]:
        return (
            FunctionalUnit,
            (self.index, self.motion, self.inputs, self.outputs, self.line, self.input_ids,
             self.output_ids),
        )  # fmt: skip

    def __repr__(self) -> str:
        return (
            f"FunctionalUnit(index={self.index!r}, motion={self.motion!r}, "
            f"inputs={self.inputs!r}, outputs={self.outputs!r}, line={self.line!r})"
        )


def _unit_view(foon: Foon) -> Callable[[int], FunctionalUnit]:
    """A maker of light unit views of ``foon`` (nothing is read until asked for)."""
    cls = FunctionalUnit

    def view(i: int) -> FunctionalUnit:
        u: FunctionalUnit = _new(cls)
        u._foon = foon
        u._index = i
        u._raw = u._inputs = u._outputs = None
        return u

    return view


class TaskTree:
    """The result of planning one goal. Objects and lists are built from the core's result
    when first read."""

    __slots__ = ("_kept", "_plan", "foon", "planner")

    def __init__(self, foon: Foon, plan: _foon.Plan, planner: Planner | None = None) -> None:
        self.foon = foon
        self.planner = planner
        self._plan = plan
        self._kept: dict[str, Any] = {}

    def __repr__(self) -> str:
        state = "solved" if self.solved else "unsolved"
        n = len(self.units)
        course = " (course)" if self.compat == "course" else ""
        return f"<TaskTree {self.goal} by {self.method}{course}: {state}, {_count(n, 'unit')}>"

    def __reduce__(self) -> tuple[Any, ...]:
        return (TaskTree, (self.foon, self._plan, self.planner))

    def __eq__(self, other: object) -> bool:
        """The same FOON and the same result (the planning time aside)."""
        return isinstance(other, TaskTree) and self._plan == other._plan and self.foon == other.foon

    def __hash__(self) -> int:
        return hash((self._plan.goal, self._plan.method, tuple(self.units)))

    def _objects(self, name: str, ids: list[int]) -> list[Object]:
        try:
            return self._kept[name]  # type: ignore[no-any-return]
        except KeyError:
            v = self._kept[name] = [self.foon.object(o) for o in ids]
            return v

    @property
    def goal(self) -> Object:
        return self.foon.object(self._plan.goal)

    @property
    def goal_id(self) -> int:
        return self._plan.goal

    @property
    def method(self) -> str:
        return self._plan.method

    @property
    def compat(self) -> str:
        """``"course"`` or ``"sound"``."""
        return self._plan.compat

    @property
    def count(self) -> str:
        """``"nodes"`` or ``"ingredients"``."""
        return self._plan.count

    @property
    def level(self) -> int:
        """The identity level kitchen items and the goal were matched at (1, 2 or 3): the tree
        is sound at that level (METHODS.md, "Hierarchy levels")."""
        return 3 if self.planner is None else self.planner.level

    @property
    def solved(self) -> bool:
        return self._plan.solved

    @property
    def units(self) -> list[int]:
        """FU indices (0-based, file order after de-duplication), in output order."""
        try:
            return self._kept["units"]  # type: ignore[no-any-return]
        except KeyError:
            v = self._kept["units"] = self._plan.units
            return v

    @property
    def unresolved(self) -> list[Object]:
        """Course methods: objects reached that are neither in the kitchen nor produced."""
        return self._objects("unresolved", self._plan.unresolved)

    @property
    def missing(self) -> list[Object]:
        """Failed sound methods: raw items a tree would need that the kitchen lacks."""
        return self._objects("missing", self._plan.missing)

    @property
    def cycle(self) -> list[Object]:
        """Failed sound methods blocked only by cycles: one blocking cycle (first = last)."""
        return self._objects("cycle", self._plan.cycle)

    @property
    def cycle_units(self) -> list[int]:
        """The units of that cycle."""
        try:
            return self._kept["cycle_units"]  # type: ignore[no-any-return]
        except KeyError:
            v = self._kept["cycle_units"] = self._plan.cycle_units
            return v

    @property
    def height(self) -> int | None:
        """Parallel steps of the tree (the goal's rank using only its units)."""
        return self._plan.height

    @property
    def success(self) -> float | None:
        """Product of the motion success rates of the units (None without a rate table)."""
        return self._plan.success

    @property
    def unrated_motion(self) -> str | None:
        """The motion of the first unit of the tree that has no rate in the rate table given
        (None when every motion has one, or when no table was given)."""
        u = self._plan.unrated
        return None if u is None else self.foon._native.fu(u)[0]

    @property
    def cost(self) -> float | None:
        """The optimal methods' objective value (None for the others)."""
        return self._plan.cost

    @property
    def bound(self) -> float | None:
        """``optimal-shared``: the proven bound on :attr:`cost` (a lower bound on the unit
        count, an upper bound on the success; None for the other methods)."""
        return self._plan.bound

    @property
    def proven(self) -> bool | None:
        """``optimal-shared``: whether :attr:`cost` is proven optimal (False when a limit
        stopped the search first; None for the other methods)."""
        return self._plan.proven

    @property
    def gap(self) -> float | None:
        """``optimal-shared``: ``abs(cost - bound)``, 0 when proven."""
        return self._plan.gap

    @property
    def objective(self) -> str | None:
        """``optimal-shared``: what :attr:`cost` and :attr:`bound` measure, ``"units"`` (the
        number of distinct units) or ``"success"`` (the product of their rates); None for
        the other methods."""
        return self._plan.objective

    @property
    def leaf_inputs(self) -> int:
        """Distinct kitchen items the units need."""
        return self._plan.leaf_inputs

    @property
    def expanded(self) -> int:
        """Objects expanded by the search."""
        return self._plan.expanded

    @property
    def peak_frontier(self) -> int:
        """Largest frontier (open list) during the search."""
        return self._plan.peak_frontier

    @property
    def seconds(self) -> float:
        """Time spent planning, in seconds."""
        return self._plan.seconds

    def __len__(self) -> int:
        return len(self.units)

    def __iter__(self) -> Iterator[FunctionalUnit]:
        """The units, in output order, as light views (see :class:`FunctionalUnit`)."""
        return map(_unit_view(self.foon), self.units)

    @property
    def fu_count(self) -> int:
        return len(self.units)

    def to_text(self) -> str:
        """The tree in the course output file form (``//`` then each FU)."""
        return self.foon._native.tree_text(self.units)

    def explanation(self) -> str:
        """One line saying why the goal could not be made (empty when solved)."""
        return _foon.explanation(self.foon._native, self._plan)

    def _planner(self) -> Planner:
        if self.planner is None:
            self.planner = self.foon.planner()
        return self.planner

    def write(
        self,
        format: str,
        *,
        title: str | None = None,
        max_nodes: int | None = None,
        cost_scale: int | None = None,
    ) -> str | bytes:
        """The tree in ``format`` (a name of :data:`FORMATS`: text, json, dot, svg, png, pdf,
        html, steps, pddl, graphml): ``str`` for text formats, ``bytes`` for png and pdf.
        svg, png, pdf and html run Graphviz's ``dot`` (:class:`OutputError` when it is
        missing); ``max_nodes`` raises the size above which pictures are refused."""
        data = _foon.write_tree(
            self._planner()._native,
            self._plan,
            format,
            title=title,
            max_nodes=max_nodes,
            cost_scale=cost_scale,
        )
        return _out(data, format)

    def to_dot(self, *, title: str | None = None) -> str:
        """The tree as Graphviz DOT in the FOON visual language (motions red squares,
        objects green circles, the goal purple, kitchen items with a double border)."""
        return str(self.write("dot", title=title))

    def to_svg(self, *, title: str | None = None) -> str:
        """The tree's picture as SVG (runs Graphviz's ``dot``)."""
        return str(self.write("svg", title=title))

    def to_pddl(self, *, cost_scale: int | None = None) -> tuple[str, str]:
        """The tree as a PDDL (domain, problem): one action per unit of the tree, the
        kitchen as the initial state, the goal as the goal; with motion rates, action costs
        ``round(-ln(rate) * cost_scale)`` (default 1000; 0: none)."""
        return _foon.split_pddl(str(self.write("pddl", cost_scale=cost_scale)))

    def steps(self) -> list[str]:
        """The numbered plain-English steps, in execution order."""
        return str(self.write("steps")).splitlines()

    def to_networkx(self) -> Any:
        """The tree as a ``networkx.DiGraph``: the object-motion bipartite graph with the
        attributes of its GraphML (``write("graphml")``). Needs the optional extra
        ``foon[networkx]`` (:class:`ImportError` without it)."""
        from foon import _networkx

        return _networkx.from_graphml(str(self.write("graphml")), "TaskTree.to_networkx()")

    def _repr_svg_(self) -> str | None:
        """Jupyter shows a tree as its picture (nothing when Graphviz is missing)."""
        try:
            return self.to_svg()
        except OutputError:
            return None

    def to_dict(self) -> dict[str, Any]:
        """The machine-readable form (what ``foon plan --format json`` prints for a goal):
        the result and figures, the kitchen items used (``leaves``), the rate each unit used
        (``rates``), the units in the lab's JSON dialect (``functional_units``) and the
        FOON's file (``source``); see ``schema/foon.schema.json``."""
        import json

        d: dict[str, Any] = json.loads(self.to_json())
        return d

    def to_json(self, indent: int | None = 2) -> str:
        """:meth:`to_dict` as JSON text (written by the core; ``indent`` other than 2
        re-indents it)."""
        text = str(self.write("json")).removesuffix("\n")
        if indent == 2:
            return text
        import json

        return json.dumps(json.loads(text), indent=indent)

    def is_valid(self, kitchen: KitchenLike = None, utensils: UtensilsLike = None) -> bool:
        """Whether the tree's units, in some order, make the goal from the kitchen (the one
        planned with, unless another kitchen or utensil list is given)."""
        p = self.planner
        if p is None or kitchen is not None or utensils is not None:
            p = self.foon.planner(
                kitchen if kitchen is not None else (p.kitchen if p else None),
                utensils=utensils if utensils is not None else (p.utensils if p else None),
            )
        valid, _, _ = p._native.check_tree(self.units, self.goal_id)
        return bool(valid)


class Blocked(_Frozen):
    """The first unit of a tree file that cannot run in the order written."""

    __slots__ = ("line", "missing", "position")

    position: int
    line: int
    missing: list[Object]

    def __init__(self, position: int, line: int, missing: list[Object]) -> None:
        _set(self, "position", position)
        _set(self, "line", line)
        _set(self, "missing", missing)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Blocked) and (self.position, self.line, self.missing) == (
            other.position,
            other.line,
            other.missing,
        )

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return f"Blocked(position={self.position!r}, line={self.line!r}, missing={self.missing!r})"


class TreeCheck(_Frozen):
    """What :meth:`Foon.verify` found."""

    __slots__ = ("blocked", "foreign_units", "goal_absent", "goal_made", "units", "valid")

    valid: bool
    units: int
    goal_made: bool
    goal_absent: bool
    blocked: Blocked | None
    #: (position, line) of units that are not units of the FOON.
    foreign_units: list[tuple[int, int]]

    def __init__(
        self,
        valid: bool,
        units: int,
        goal_made: bool,
        goal_absent: bool,
        blocked: Blocked | None,
        foreign_units: list[tuple[int, int]],
    ) -> None:
        for k, v in zip(self.__slots__, (blocked, foreign_units, goal_absent, goal_made, units,
                                         valid), strict=True):  # fmt: skip
            _set(self, k, v)

    def _key(self) -> tuple[Any, ...]:
        return tuple(getattr(self, k) for k in self.__slots__)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, TreeCheck) and self._key() == other._key()

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return (
            f"TreeCheck(valid={self.valid!r}, units={self.units!r}, goal_made={self.goal_made!r}, "
            f"goal_absent={self.goal_absent!r}, blocked={self.blocked!r}, "
            f"foreign_units={self.foreign_units!r})"
        )


class Foon:
    """A parsed FOON: an immutable compact index, safe to share between threads. It compares
    equal to a FOON with the same content and pickles: a FOON opened from a ``.foonidx``
    index file as its path and fingerprint (unpickling opens the file again, and fails
    clearly when it is gone or changed), any other as its index bytes and load report (unit
    indices, object ids, lines, sources and warnings survive)."""

    __slots__ = ("__weakref__", "_native")

    def __init__(self, native: _foon.Foon) -> None:
        self._native = native

    @classmethod
    def load(cls, path: PathLike, *, strict: bool = False, progress: bool = False) -> Foon:
        """Reads a FOON file of any dialect, or opens a ``.foonidx`` index file (told by its
        first bytes, whatever its name; a file named ``.foonidx`` that is not a whole index
        is an error; memory-mapped, not copied). Annotation faults are
        reported as :class:`FoonWarning` (errors with ``strict=True``). ``progress``: draw a
        bar of the bytes read on stderr while a large file is parsed (for a terminal)."""
        f = cls(_foon.Foon.load(path, strict=strict, progress=progress))
        _emit_warnings(f._native.warnings())
        return f

    @classmethod
    def load_sources(
        cls, paths: Iterable[PathLike], *, strict: bool = False, progress: bool = False
    ) -> Foon:
        """Builds one index from several FOON files and folders (any dialect each; a folder
        stands for its ``.txt`` and ``.json`` files, sorted by name), in the given order; a
        unit found again keeps its first copy and records each source and line."""
        f = cls(_foon.Foon.load_sources(list(paths), strict=strict, progress=progress))
        _emit_warnings(f._native.warnings())
        return f

    def write_index(self, path: PathLike) -> None:
        """Writes the index as a ``.foonidx`` file, atomically (a temporary file in the same
        folder, then renamed); never over one of the FOON's inputs."""
        self._native.write_index(path)

    @property
    def fingerprint(self) -> str:
        """The content fingerprint (32 hexadecimal digits): equal for the same index
        whether it was parsed from text or opened from an index file."""
        return str(self._native.fingerprint)

    @property
    def index_path(self) -> str | None:
        """The ``.foonidx`` file this FOON was opened from, if any."""
        return self._native.index_path

    def verify_checksum(self) -> None:
        """Verifies the data checksum of a FOON opened from an index file
        (:class:`FoonError` when it does not match)."""
        self._native.verify_checksum()

    @classmethod
    def from_text(
        cls, text: str | bytes, *, strict: bool = False, path: PathLike | None = None
    ) -> Foon:
        """Parses FOON text; ``path`` only names the source in messages."""
        f = cls(_foon.Foon.from_text(text, strict=strict, path=path))
        _emit_warnings(f._native.warnings())
        return f

    def __reduce__(self) -> tuple[Any, ...]:
        return (Foon, (self._native,))

    def __copy__(self) -> Foon:
        return self

    def __deepcopy__(self, memo: object) -> Foon:
        return self

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Foon) and self._native == other._native

    def __hash__(self) -> int:
        return hash(self._native)

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
        where = f" from {src}" if src else ""
        return (
            f"<Foon {_count(self.fu_count, 'unit')}, {_count(self.object_count, 'object')}{where}>"
        )

    def stats(self) -> dict[str, int]:
        """Counts: functional units, objects, produced objects, motions, ..."""
        return dict(self._native.stats())

    @property
    def warnings(self) -> list[tuple[str | None, int, int, str, str]]:
        """Load warnings as ``(path, line, column, kind, message)``."""
        return list(self._native.warnings())

    def object(self, i: int) -> Object:
        """Object ``i`` (ids in first-seen order), in its first written form."""
        return _object(self._native.object(i))

    def objects(self) -> Iterator[Object]:
        return (self.object(i) for i in range(self.object_count))

    def fu(self, i: int) -> FunctionalUnit:
        """Functional unit ``i`` (file order after dropping faulty and duplicate units)."""
        u = _unit_view(self)(i)
        u._read()  # an index out of range fails here
        return u

    def fu_text(self, i: int) -> str:
        return self._native.fu_text(i)

    def sources(self, i: int) -> list[tuple[str, int]]:
        """Every (source path, line) where unit ``i`` was found, in reading order, its kept
        copy first (``""`` names text given in memory)."""
        return _foon.fu_sources(self._native, i)

    def support(self, i: int) -> int:
        """The number of distinct sources that hold unit ``i``."""
        return int(_foon.fu_support(self._native, i))

    def to_text(self) -> str:
        """The whole FOON in the course text form."""
        return self._native.to_text()

    def to_json(self) -> str:
        """The whole FOON in the lab's JSON dialect (a list of ``{"input_nodes",
        "motion_node", "output_nodes"}``), with in-motion flags and motion metadata when the
        source has them: :func:`load` reads it back to an equal FOON."""
        return str(self.write("json"))

    def write(
        self,
        format: str,
        *,
        goal: GoalLike | None = None,
        depth: int | None = None,
        units: Iterable[int] | None = None,
        kitchen: KitchenLike = None,
        utensils: UtensilsLike = None,
        motions: MotionsLike = None,
        title: str | None = None,
        max_nodes: int | None = None,
        cost_scale: int | None = None,
    ) -> str | bytes:
        """The FOON in ``format`` (text, json, dot, svg, png, pdf, pddl, graphml): all of it,
        the ``units`` given, or with ``goal`` and ``depth`` the units within ``depth`` steps
        of the goal (0: the units that make or use it), the goal drawn purple. A ``kitchen``
        marks its items in pictures and is PDDL's initial state; ``motions`` gives the rates
        written (GraphML, PDDL action costs). ``str`` for text formats, ``bytes`` for png and
        pdf."""
        if depth is not None and goal is None:
            raise ValueError("depth needs a goal (the units within depth steps of it)")
        focus = None if goal is None else self.goal_id(goal)
        planner = None
        if kitchen is not None or utensils is not None or motions is not None:
            planner = self.planner(kitchen, utensils=utensils, motions=motions)._native
        data = _foon.write_foon(
            self._native,
            format,
            units=None if units is None else [int(u) for u in units],
            focus=focus,
            depth=depth,
            planner=planner,
            title=title,
            max_nodes=max_nodes,
            cost_scale=cost_scale,
        )
        return _out(data, format)

    def to_pddl(
        self,
        goal: GoalLike,
        kitchen: KitchenLike,
        *,
        utensils: UtensilsLike = None,
        motions: MotionsLike = None,
        depth: int | None = None,
        cost_scale: int | None = None,
    ) -> tuple[str, str]:
        """A PDDL (domain, problem) for making ``goal`` from ``kitchen``: one action per unit
        of the goal's ancestry that can run (within ``depth`` steps of the goal if given),
        the kitchen as the initial state; with ``motions``, action costs."""
        text = self.write(
            "pddl",
            goal=goal,
            depth=depth,
            kitchen=kitchen,
            utensils=utensils,
            motions=motions,
            cost_scale=cost_scale,
        )
        return _foon.split_pddl(str(text))

    def to_dot(
        self, *, goal: GoalLike | None = None, depth: int | None = None, title: str | None = None
    ) -> str:
        """The FOON (or the neighbourhood of ``goal``) as Graphviz DOT."""
        return str(self.write("dot", goal=goal, depth=depth, title=title))

    def to_networkx(
        self,
        *,
        goal: GoalLike | None = None,
        depth: int | None = None,
        units: Iterable[int] | None = None,
        kitchen: KitchenLike = None,
        utensils: UtensilsLike = None,
    ) -> Any:
        """The FOON (or the part :meth:`write` selects with the same arguments) as a
        ``networkx.DiGraph``: the object-motion bipartite graph with the attributes of its
        GraphML. Needs the optional extra ``foon[networkx]`` (:class:`ImportError` without
        it)."""
        from foon import _networkx

        text = self.write(
            "graphml", goal=goal, depth=depth, units=units, kitchen=kitchen, utensils=utensils
        )
        return _networkx.from_graphml(str(text), "Foon.to_networkx()")

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

    def goal_id(self, goal: GoalLike) -> int:
        """Resolves a goal: an object id, an object (or its dict), or a label that only one
        object has. Raises :class:`GoalNotFoundError`."""
        if isinstance(goal, Object):
            return self._native.goal_id(goal._fields())
        if isinstance(goal, Mapping):
            return self._native.goal_id(Object.from_dict(goal)._fields())
        if isinstance(goal, int | str) and not isinstance(goal, bool):
            return self._native.goal_id(goal)
        raise TypeError(
            "goal must be an Object, a mapping, an object id (int) or a label (str), "
            f"not {_type(goal)}"
        )

    def plan(
        self,
        goal: GoalLike,
        kitchen: KitchenLike = None,
        method: Method | str = "ids",
        *,
        compat: Literal["course"] | None = None,
        count: Literal["nodes", "ingredients"] = "nodes",
        motions: MotionsLike = None,
        utensils: UtensilsLike = None,
        default_rate: float | None = None,
        objective: Literal["units", "success"] | None = None,
        node_limit: int | None = None,
        time_limit: float | None = None,
        level: Literal[1, 2, 3] = 3,
    ) -> TaskTree:
        """Plans a task tree for ``goal`` from ``kitchen``.

        ``method``: ``ids`` (default), ``greedy-success``, ``greedy-inputs``,
        ``optimal-success``, ``optimal-units``, ``optimal-inputs``, ``optimal-shared`` or
        ``bfs``. Sound unless ``compat="course"``, which reproduces the course code's trees
        byte for byte. ``objective`` (``units`` by default, or ``success``), ``node_limit``
        and ``time_limit`` (seconds) are the options of ``optimal-shared``. ``level`` (1, 2
        or 3, the identity levels of merging): kitchen items and the goal match every object
        equal to them at that level (METHODS.md, "Hierarchy levels").
        """
        p = self.planner(
            kitchen, motions=motions, utensils=utensils, default_rate=default_rate, level=level
        )
        return p.plan(
            goal,
            method,
            compat=compat,
            count=count,
            objective=objective,
            node_limit=node_limit,
            time_limit=time_limit,
        )

    def plan_many(
        self,
        goals: Iterable[GoalLike],
        kitchen: KitchenLike = None,
        method: Method | str = "ids",
        *,
        compat: Literal["course"] | None = None,
        count: Literal["nodes", "ingredients"] = "nodes",
        motions: MotionsLike = None,
        utensils: UtensilsLike = None,
        default_rate: float | None = None,
        threads: int | None = None,
        objective: Literal["units", "success"] | None = None,
        node_limit: int | None = None,
        time_limit: float | None = None,
        level: Literal[1, 2, 3] = 3,
    ) -> list[TaskTree]:
        """Plans many goals in one call: the kitchen is matched once, the interpreter is
        released, and the goals are spread over ``threads`` threads (see
        :meth:`Planner.plan_many`; ``level`` as for :meth:`plan`)."""
        _check_goals(goals)
        p = self.planner(
            kitchen, motions=motions, utensils=utensils, default_rate=default_rate, level=level
        )
        return p.plan_many(
            goals,
            method,
            compat=compat,
            count=count,
            threads=threads,
            objective=objective,
            node_limit=node_limit,
            time_limit=time_limit,
        )

    def plan_k(
        self,
        goal: GoalLike,
        kitchen: KitchenLike = None,
        k: int = 10,
        method: Method | str = "optimal-units",
        *,
        diverse: bool = False,
        motions: MotionsLike = None,
        utensils: UtensilsLike = None,
        default_rate: float | None = None,
    ) -> list[RankedTree]:
        """The ``k`` best trees of ``goal`` (see :meth:`Planner.plan_k`)."""
        p = self.planner(kitchen, motions=motions, utensils=utensils, default_rate=default_rate)
        return p.plan_k(goal, k, method, diverse=diverse)

    def paths(
        self,
        goal: GoalLike,
        kitchen: KitchenLike = None,
        *,
        max_trees: int | None = None,
        max_height: int | None = None,
        utensils: UtensilsLike = None,
    ) -> Iterator[RankedTree]:
        """Every valid tree of ``goal`` up to the limits, lazily (see :meth:`Planner.paths`)."""
        p = self.planner(kitchen, utensils=utensils)
        return p.paths(goal, max_trees=max_trees, max_height=max_height)

    def explain(
        self,
        goal: GoalLike,
        kitchen: KitchenLike = None,
        method: Method | str | None = None,
        *,
        count: Literal["nodes", "ingredients"] = "nodes",
        motions: MotionsLike = None,
        utensils: UtensilsLike = None,
        default_rate: float | None = None,
        level: Literal[1, 2, 3] = 3,
    ) -> GoalExplanation:
        """Why ``goal`` can or cannot be made from ``kitchen``: whether it is in the
        kitchen, derivable (its rank and the best tree of ``method``, a sound method;
        default ``optimal-success`` with rates, else ``optimal-units``) or blocked (the
        shopping list, what blocks each producer, the blocking cycle and what would unblock
        it). See METHODS.md, "Explaining a goal"; ``level`` as for :meth:`plan`."""
        p = self.planner(
            kitchen, motions=motions, utensils=utensils, default_rate=default_rate, level=level
        )
        return p.explain(goal, method, count=count)

    def find_similar(self, text: str, k: int = 10) -> list[Similar]:
        """The ``k`` objects most similar to a free-text query such as ``"chopped onion in
        bowl"`` (label, states and container), best first. The index is built on the first
        call, once per FOON."""
        from foon import _explain

        return _explain.find_similar(self, text, k)

    def planner(
        self,
        kitchen: KitchenLike = None,
        *,
        motions: MotionsLike = None,
        utensils: UtensilsLike = None,
        default_rate: float | None = None,
        level: Literal[1, 2, 3] = 3,
    ) -> Planner:
        """Prepares the kitchen, utensils and motion rates once, for many plans."""
        return Planner(
            self, kitchen, motions=motions, utensils=utensils, default_rate=default_rate,
            level=level,
        )  # fmt: skip

    def split(
        self,
        goal: GoalLike,
        kitchen: KitchenLike = None,
        profiles: Profiles | Mapping[str, Any] | None = None,
        max_human: int = 1,
        *,
        robot: str = "robot",
        human: str = "human",
        utensils: UtensilsLike = None,
        fixed_tree: bool = False,
    ) -> SplitResult:
        """The robot/human split: for each budget m = 0..``max_human``, the tree and the
        assignment of at most m of its steps to the human that maximise the tree's success
        over all valid trees (tree cost: a sub-goal used twice is made, and counted, twice).
        ``profiles[robot]`` gives the robot's rates, ``profiles[human]`` the human's (every
        rate 1 when absent). ``fixed_tree=True`` adds the lab's method (the best robot tree,
        its m lowest-rate units to the human). See ``docs/METHODS.md``."""
        return self.planner(kitchen, utensils=utensils).split(
            goal, profiles, max_human, robot=robot, human=human, fixed_tree=fixed_tree
        )

    def ranks(self, kitchen: KitchenLike = None, utensils: UtensilsLike = None) -> list[int | None]:
        """Rank of every object from the kitchen: the fewest parallel steps that make it
        (None when it cannot be made)."""
        return self.planner(kitchen, utensils=utensils).ranks()

    def derivable_many(
        self,
        kitchens: Iterable[KitchenLike],
        goals: Iterable[GoalLike],
        *,
        utensils: UtensilsLike = None,
        level: Literal[1, 2, 3] = 3,
        threads: int | None = None,
    ) -> list[list[bool]]:
        """Whether each goal can be made in each kitchen: ``result[k][g]`` for kitchen
        ``k`` and goal ``g`` (in the order given). Up to 64 kitchens are decided in one
        forward chaining over the FOON (one bit per kitchen per object), batches of 64 on
        ``threads`` threads; no kitchen is prepared for planning (METHODS.md, "Many kitchens
        at once"). ``level`` as for :meth:`plan`."""
        out: list[list[bool]] = self._many(kitchens, goals, utensils, level, threads, False)
        return out

    def ranks_many(
        self,
        kitchens: Iterable[KitchenLike],
        goals: Iterable[GoalLike],
        *,
        utensils: UtensilsLike = None,
        level: Literal[1, 2, 3] = 3,
        threads: int | None = None,
    ) -> list[list[int | None]]:
        """As :meth:`derivable_many`, each goal's rank in each kitchen (the fewest parallel
        steps that make it, as :meth:`ranks` gives; None when it cannot be made there)."""
        out: list[list[int | None]] = self._many(kitchens, goals, utensils, level, threads, True)
        return out

    def _many(
        self,
        kitchens: Iterable[KitchenLike],
        goals: Iterable[GoalLike],
        utensils: UtensilsLike,
        level: Literal[1, 2, 3],
        threads: int | None,
        ranks: bool,
    ) -> Any:
        _check_level(level)
        _check_goals(goals)
        if isinstance(kitchens, str | bytes | Kitchen):
            raise TypeError(f"kitchens must be an iterable of kitchens, not {_type(kitchens)}")
        natives = [_as_kitchen(k)._native for k in kitchens]
        ids = [self.goal_id(g) for g in goals]
        return _foon.derivable_many(
            self._native, natives, ids, _as_utensils(utensils), level, ranks, threads
        )

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
        d = self._native.verify_tree(
            t._native,
            _as_kitchen(kitchen)._native,
            _as_utensils(utensils),
            _as_object(goal, "goal")._tuple(),
        )
        blocked = None
        if d["blocked"] is not None:
            pos, line, missing = d["blocked"]
            blocked = Blocked(pos, line, [_object(m) for m in missing])
        return TreeCheck(
            valid=d["valid"],
            units=d["units"],
            goal_made=d["goal_made"],
            goal_absent=d["goal_absent"],
            blocked=blocked,
            foreign_units=[tuple(x) for x in d["foreign_units"]],
        )


def _check_level(level: object) -> None:
    if isinstance(level, bool) or level not in (1, 2, 3):
        raise ValueError(f"level must be 1, 2 or 3, not {level!r}")


def _check_goals(goals: object) -> None:
    if isinstance(goals, str | bytes | Mapping | Object):
        raise TypeError(
            "goals must be an iterable of goals (objects, object ids or labels), not a single "
            f"{_type(goals)}; use plan() for one goal"
        )
    if not hasattr(goals, "__iter__"):
        raise TypeError(f"goals must be an iterable of goals, not {_type(goals)}")


class Planner:
    """A FOON with a kitchen, utensils and motion rates prepared once: plan any number of
    goals without paying for the preparation again (it is what :meth:`Foon.plan` builds
    for each call). It pickles (the preparation is redone on loading)."""

    __slots__ = ("__weakref__", "_changes", "_kitchen", "_native", "default_rate", "foon",
                 "level", "motions", "utensils")  # fmt: skip

    def __init__(
        self,
        foon: Foon,
        kitchen: KitchenLike = None,
        *,
        motions: MotionsLike = None,
        utensils: UtensilsLike = None,
        default_rate: float | None = None,
        level: Literal[1, 2, 3] = 3,
    ) -> None:
        if not isinstance(foon, Foon):
            raise TypeError(f"foon must be a Foon, not {_type(foon)}")
        _check_level(level)
        self.level = level
        self.foon = foon
        self._kitchen: Kitchen | None = _as_kitchen(kitchen)
        # A planner made by `with_changes` at level 3: a kitchen and the (add, remove) steps
        # from it, applied when `kitchen` is first read.
        self._changes: tuple[Kitchen, tuple[tuple[Kitchen, Kitchen], ...]] | None = None
        self.motions = _as_rates(motions)
        self.utensils = _as_utensils(utensils)
        self.default_rate = default_rate
        self._native = _foon.Planner(
            foon._native,
            self.kitchen._native,
            self.utensils,
            None if self.motions is None else list(self.motions.items()),
            default_rate,
            level,
        )

    @property
    def kitchen(self) -> Kitchen:
        """The kitchen. For a planner made by :meth:`with_changes` it is built when first
        asked for (planning never needs it)."""
        k = self._kitchen
        if k is None:
            assert self._changes is not None
            start, steps = self._changes
            k = _kitchen(start._native.with_steps([(a._native, r._native) for a, r in steps]))
            self._kitchen, self._changes = k, None
        return k

    def __repr__(self) -> str:
        rates = "no rates" if self.motions is None else _count(len(self.motions), "motion rate")
        return (
            f"<Planner {self.foon!r}: {_count(len(self.kitchen), 'kitchen item')}, "
            f"{_count(len(self.utensils), 'utensil')}, {rates}>"
        )

    def __reduce__(self) -> tuple[Any, ...]:
        return (
            _restore_planner,
            (self.foon, self.kitchen, self.motions, self.utensils, self.default_rate, self.level),
        )

    def _key(self) -> tuple[Any, ...]:
        return (self.foon, self.kitchen, self.motions, self.utensils, self.default_rate,
                self.level)  # fmt: skip

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Planner) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash((self.foon, self.kitchen, self.motions, tuple(self.utensils),
                     self.default_rate, self.level))  # fmt: skip

    def plan(
        self,
        goal: GoalLike,
        method: Method | str = "ids",
        *,
        compat: Literal["course"] | None = None,
        count: Literal["nodes", "ingredients"] = "nodes",
        objective: Literal["units", "success"] | None = None,
        node_limit: int | None = None,
        time_limit: float | None = None,
    ) -> TaskTree:
        """Plans one goal (see :meth:`Foon.plan`)."""
        raw = self._native.plan(
            [self.goal_id(goal)],
            method,
            compat or "sound",
            count,
            1,
            objective,
            node_limit,
            time_limit,
        )
        return TaskTree(self.foon, raw[0], self)

    def plan_many(
        self,
        goals: Iterable[GoalLike],
        method: Method | str = "ids",
        *,
        compat: Literal["course"] | None = None,
        count: Literal["nodes", "ingredients"] = "nodes",
        threads: int | None = None,
        objective: Literal["units", "success"] | None = None,
        node_limit: int | None = None,
        time_limit: float | None = None,
    ) -> list[TaskTree]:
        """Plans many goals, in order, spread over ``threads`` worker threads. ``threads`` is
        always honoured (1 plans on one thread), capped to the available parallelism of the
        process and to the number of goals; ``None`` means the ``FOON_THREADS`` environment
        variable, else all cores. The trees are the same for every thread count. Ctrl-C stops
        the batch (``KeyboardInterrupt``)."""
        _check_goals(goals)
        ids = [self.goal_id(g) for g in goals]
        raw = self._native.plan(
            ids, method, compat or "sound", count, threads, objective, node_limit, time_limit
        )
        return [TaskTree(self.foon, d, self) for d in raw]

    def plan_k(
        self,
        goal: GoalLike,
        k: int,
        method: Method | str = "optimal-units",
        *,
        diverse: bool = False,
    ) -> list[RankedTree]:
        """The ``k`` valid trees of lowest cost for an ``optimal-*`` method, in cost order,
        each a distinct set of units (fewer when there are fewer; none when the goal cannot be
        made). ``diverse``: each tree after the first is the best one under weights that
        penalise the units of the earlier trees (see METHODS.md, "The k best trees")."""
        from . import _kbest

        return _kbest.plan_k(self, self.goal_id(goal), k, method, diverse)

    def paths(
        self, goal: GoalLike, *, max_trees: int | None = None, max_height: int | None = None
    ) -> Iterator[RankedTree]:
        """Every valid tree of ``goal`` (fewest units first), lazily, each set of units once,
        leaving out those higher than ``max_height`` and stopping after ``max_trees``."""
        from . import _kbest

        return _kbest.paths(self, self.goal_id(goal), max_trees, max_height)

    def explain(
        self,
        goal: GoalLike,
        method: Method | str | None = None,
        *,
        count: Literal["nodes", "ingredients"] = "nodes",
    ) -> GoalExplanation:
        """Explains one goal (see :meth:`Foon.explain`)."""
        if method is None:
            rated = self.motions is not None or self.default_rate is not None
            method = "optimal-success" if rated else "optimal-units"
        from foon import _explain

        return _explain.explain(self, self.goal_id(goal), str(method), count)

    def goal_id(self, goal: GoalLike) -> int:
        """The goal's object id (see :meth:`Foon.goal_id`); below level 3, the object that
        stands for it at the level (METHODS.md, "Hierarchy levels"): an object id is that
        object, a label stands for the label-only object."""
        if isinstance(goal, str):
            return int(_foon.goal_at_level(self._native, goal, self.level))
        if isinstance(goal, Object | Mapping):
            o = _as_object(goal, "goal")
            return int(_foon.goal_at_level(self._native, o._tuple(), self.level))
        return self.foon.goal_id(goal)

    def ranks(self) -> list[int | None]:
        """Rank of every object: the fewest parallel steps that make it from the kitchen
        (None when it cannot be made)."""
        return list(self._native.ranks())

    def finish_updates(self) -> None:
        """Runs to the end what a planner from :meth:`with_changes` updates on use: the
        costs and choices of the optimal methods (and of explanations) that the planner it
        was derived from had computed, which a plan otherwise updates only as far as its
        goal needs. :meth:`plan_many` on several threads does this first; call it before
        planning many goals one by one (or from several threads) for even plan times. Any
        other planner has nothing to run; the results never depend on it."""
        self._native.finish_updates()

    def split(
        self,
        goal: GoalLike,
        profiles: Profiles | Mapping[str, Any] | None = None,
        max_human: int = 1,
        *,
        robot: str = "robot",
        human: str = "human",
        fixed_tree: bool = False,
    ) -> SplitResult:
        """The robot/human split over this planner's kitchen and utensils (see
        :meth:`Foon.split`; the planner's own motion rates are not used)."""
        from foon._split import split

        return split(
            self,
            goal,
            {} if profiles is None else profiles,
            max_human,
            robot=robot,
            human=human,
            fixed_tree=fixed_tree,
        )

    def with_changes(
        self,
        add: Iterable[ObjectLike] | None = None,
        remove: Iterable[ObjectLike] | None = None,
    ) -> Planner:
        """A planner for this kitchen without the items ``remove`` and with the items ``add``
        (:meth:`Kitchen.without`, then :meth:`Kitchen.with_items`), over the same FOON,
        motion rates, utensils and level. It is prepared incrementally: what this planner
        has computed (ranks, the choices of ``ids``, the costs and choices of the optimal
        methods and of explanations) is updated for the change instead of computed again,
        which costs what the change reaches rather than the whole FOON; its plans equal
        those of ``Planner(foon, new_kitchen, ...)`` (docs/METHODS.md, "Incremental
        kitchens"). The ranks and choices of ``ids`` are updated at once; the optimal
        methods' costs on use, as far as the goals planned need (:meth:`finish_updates`
        runs them to the end)."""
        adding, removing = _as_items(add, "add"), _as_items(remove, "remove")
        new = object.__new__(Planner)
        new.level = self.level
        new.foon = self.foon
        # At level 3 the change is applied as items; the new kitchen is built on first use
        # (from the first kitchen of a chain of changes: no planner of the chain is kept).
        if self.level == 3:
            steps: tuple[tuple[Kitchen, Kitchen], ...] = ()
            if self._kitchen is not None:
                start = self._kitchen
            else:
                assert self._changes is not None
                start, steps = self._changes
            new._kitchen, new._changes = None, (start, (*steps, (adding, removing)))
        else:
            new._kitchen, new._changes = self.kitchen.without(removing).with_items(adding), None
        new.motions = self.motions
        new.utensils = list(self.utensils)
        new.default_rate = self.default_rate
        new._native = _foon.planner_with_changes(
            self._native,
            adding._native,
            removing._native,
            None if new._kitchen is None else new._kitchen._native,
        )
        return new


def _restore_planner(
    foon: Foon,
    kitchen: Kitchen,
    motions: MotionRates | None,
    utensils: list[str],
    default_rate: float | None,
    level: Literal[1, 2, 3] = 3,
) -> Planner:
    return Planner(
        foon, kitchen, motions=motions, utensils=utensils, default_rate=default_rate, level=level
    )


class Finding(_Frozen):
    """One problem found by :func:`check` (its fields are also its ``__dict__``)."""

    path: str | None
    line: int
    column: int
    severity: Literal["error", "warning", "note"]
    code: str
    message: str

    def __init__(
        self,
        path: str | None,
        line: int,
        column: int,
        severity: Literal["error", "warning", "note"],
        code: str,
        message: str,
    ) -> None:
        _set(self, "path", path)
        _set(self, "line", line)
        _set(self, "column", column)
        _set(self, "severity", severity)
        _set(self, "code", code)
        _set(self, "message", message)

    def _key(self) -> tuple[Any, ...]:
        return (self.path, self.line, self.column, self.severity, self.code, self.message)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Finding) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def __repr__(self) -> str:
        return (
            f"Finding(path={self.path!r}, line={self.line!r}, column={self.column!r}, "
            f"severity={self.severity!r}, code={self.code!r}, message={self.message!r})"
        )

    def __str__(self) -> str:
        # Line 0: a finding about the file as a whole (a corrupt index file, an I/O error).
        at = f"{self.path or '<string>'}" + (f":{self.line}:{self.column}" if self.line else "")
        return f"{at}: {self.severity}: {self.message} [{self.code}]"


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
    but never produced nor in it; with motion rates, motions without a rate (and, for a rate
    file, its own faults, such as a motion with two rates). Files of object blocks (kitchens,
    goals) are checked as such."""
    try:
        ps = [paths] if isinstance(paths, _PATH_TYPES) else list(paths)
    except TypeError:
        raise TypeError(
            f"paths must be a path or an iterable of paths, not {type(paths).__name__}"
        ) from None
    # A rate file is read by the linter itself, so its own faults are findings too.
    rates_file = motions if isinstance(motions, _PATH_TYPES) else None
    rates = None if rates_file is not None else _as_rates(motions)
    raw = _foon.check(
        ps,
        None if kitchen is None else _as_kitchen(kitchen)._native,
        None if rates is None else list(rates.items()),
        _as_utensils(utensils),
        rates_file,
    )
    return [Finding(*f) for f in raw]  # type: ignore[arg-type]


def load(path: PathLike, *, strict: bool = False, progress: bool = False) -> Foon:
    """Reads a FOON file of any dialect, or opens a ``.foonidx`` (see :meth:`Foon.load`)."""
    return Foon.load(path, strict=strict, progress=progress)


class Example(_Frozen):
    """The small example FOON shipped with the package, with its kitchen, motion rates,
    utensils and goals (the first goal is the default one)."""

    __slots__ = ("foon", "goals", "kitchen", "motions", "paths", "utensils")

    foon: Foon
    kitchen: Kitchen
    motions: MotionRates
    utensils: list[str]
    goals: list[Object]
    paths: dict[str, Path]

    def __init__(
        self,
        foon: Foon,
        kitchen: Kitchen,
        motions: MotionRates,
        utensils: list[str],
        goals: list[Object],
        paths: dict[str, Path],
    ) -> None:
        _set(self, "foon", foon)
        _set(self, "kitchen", kitchen)
        _set(self, "motions", motions)
        _set(self, "utensils", utensils)
        _set(self, "goals", goals)
        _set(self, "paths", paths)

    def __repr__(self) -> str:
        return f"<Example {self.foon!r}, {len(self.goals)} goals>"


_EXAMPLE_FILES = (
    ("foon", "example.foon"),
    ("kitchen", "kitchen.json"),
    ("motions", "motion.txt"),
    ("utensils", "utensils.txt"),
    ("goals", "goals.json"),
)


def example() -> Example:
    """Loads the embedded example (see ``foon/data/README.md``)."""
    from pathlib import Path

    data = Path(__file__).parent / "data"
    paths = {k: data / name for k, name in _EXAMPLE_FILES}
    return Example(
        load(paths["foon"]),
        Kitchen.load(paths["kitchen"]),
        MotionRates.load(paths["motions"]),
        load_utensils(paths["utensils"]),
        load_goals(paths["goals"]),
        paths,
    )
