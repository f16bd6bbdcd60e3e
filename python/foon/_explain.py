"""The typed results of :meth:`foon.Foon.explain` and :meth:`foon.Foon.find_similar`
(computed in the core; this module only names the fields)."""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

from foon import _foon

if TYPE_CHECKING:
    from foon import Foon, Object, Planner, TaskTree

Status = Literal["in-kitchen", "derivable", "blocked"]
BlockKind = Literal["missing", "cycle", "not-derivable"]

#: The objective of the shopping list (the core's failure explanation).
SHOPPING_OBJECTIVE = "optimal-inputs from the kitchen plus every raw item"


@dataclass(frozen=True)
class Blocker:
    """A needed input of a producer of the goal that cannot be made from the kitchen."""

    object: Object
    object_id: int
    kind: BlockKind
    #: Whether buying raw items would make it (derivable from the kitchen plus every raw
    #: item).
    buyable: bool

    def to_dict(self) -> dict[str, Any]:
        return {
            "object": self.object.to_dict(),
            "object_id": self.object_id,
            "kind": self.kind,
            "buyable": self.buyable,
        }


@dataclass(frozen=True)
class ProducerBlock:
    """A producer of the goal and what blocks it."""

    unit: int
    motion: str
    line: int
    blockers: tuple[Blocker, ...]

    def to_dict(self) -> dict[str, Any]:
        return {
            "unit": self.unit,
            "motion": self.motion,
            "line": self.line,
            "blockers": [b.to_dict() for b in self.blockers],
        }


@dataclass(frozen=True)
class Unblock:
    """An object of the blocking cycle whose addition to the kitchen unblocks the goal
    (``alone``), or does so together with raw items."""

    object: Object
    object_id: int
    alone: bool

    def to_dict(self) -> dict[str, Any]:
        return {"object": self.object.to_dict(), "object_id": self.object_id, "alone": self.alone}


@dataclass(frozen=True)
class GoalExplanation:
    """Why a goal can or cannot be made from a kitchen (see METHODS.md, "Explaining a
    goal")."""

    goal: Object
    goal_id: int
    status: Status
    #: The method whose best tree is reported (``tree``).
    objective: str
    rank: int | None
    #: The best tree for ``objective`` (status ``in-kitchen`` or ``derivable``).
    tree: TaskTree | None
    #: Blocked: whether the goal is derivable from the kitchen plus every raw item.
    buyable: bool
    #: Blocked and buyable: the raw items to add (see ``SHOPPING_OBJECTIVE``).
    shopping: tuple[Object, ...]
    producers: tuple[ProducerBlock, ...]
    #: Blocked and not buyable: one blocking cycle from the goal (``cycle[i]`` is made by
    #: ``cycle_units[i]``, which needs ``cycle[i + 1]``; the last object repeats one).
    cycle: tuple[Object, ...]
    cycle_ids: tuple[int, ...]
    cycle_units: tuple[int, ...]
    unblock: tuple[Unblock, ...]
    #: The explanation for people (several lines).
    text: str = field(repr=False)
    _native: _foon.Explanation | None = field(default=None, repr=False, compare=False)

    @property
    def derivable(self) -> bool:
        return self.status != "blocked"

    def __getstate__(self) -> dict[str, Any]:
        # The core's copy is not pickled: a copy or an unpickled explanation has none to draw.
        return {k: v for k, v in self.__dict__.items() if k != "_native"}

    def __setstate__(self, state: dict[str, Any]) -> None:
        for k, v in state.items():
            object.__setattr__(self, k, v)
        object.__setattr__(self, "_native", None)

    def write(
        self, format: str, *, title: str | None = None, max_nodes: int | None = None
    ) -> str | bytes:
        """The blocking part as a picture in ``format`` (dot, svg, png, pdf, html; str, or
        bytes for png and pdf): the goal (purple), its producers (red squares), their
        blocking inputs (green circles, marked by kind) and the blocking cycle (METHODS.md,
        "Explaining a goal"). A goal that is not blocked is drawn as its best tree. svg,
        png, pdf and html run Graphviz's ``dot``."""
        from foon import _out

        if self._native is None:
            raise ValueError(
                "this explanation was copied or unpickled: explain the goal again to draw it"
            )
        return _out(self._native.write(format, title=title, max_nodes=max_nodes), format)

    def to_dot(self, *, title: str | None = None) -> str:
        """The blocking part as Graphviz DOT (see :meth:`write`)."""
        return str(self.write("dot", title=title))

    def to_dict(self) -> dict[str, Any]:
        """The JSON form (``foon explain --json``; fields documented in METHODS.md)."""
        t = self.tree
        return {
            "goal": self.goal.to_dict(),
            "goal_id": self.goal_id,
            "status": self.status,
            "objective": self.objective,
            "rank": self.rank,
            "tree": None
            if t is None
            else {
                "units": t.units,
                "unit_count": len(t.units),
                "height": t.height,
                "success": t.success,
                "cost": t.cost,
            },
            "buyable": self.buyable,
            "shopping_objective": SHOPPING_OBJECTIVE,
            "shopping": [o.to_dict() for o in self.shopping],
            "producers": [p.to_dict() for p in self.producers],
            "cycle": [o.to_dict() for o in self.cycle],
            "cycle_ids": list(self.cycle_ids),
            "cycle_units": list(self.cycle_units),
            "unblock": [u.to_dict() for u in self.unblock],
        }


def explain(planner: Planner, goal_id: int, method: str, count: str) -> GoalExplanation:
    from foon import TaskTree

    f = planner.foon
    (status, rank, plan, buyable, shopping, producers, cycle, cycle_units, unblock, text,
     native) = _foon.explain(planner._native, goal_id, method, count)  # fmt: skip
    units = {u.index: u for u in (f.fu(p[0]) for p in producers)}
    return GoalExplanation(
        goal=f.object(goal_id),
        goal_id=goal_id,
        status=status,
        objective=method,
        rank=rank,
        tree=None if plan is None else TaskTree(f, plan, planner),
        buyable=buyable,
        shopping=tuple(f.object(o) for o in shopping),
        producers=tuple(
            ProducerBlock(
                unit=u,
                motion=units[u].motion,
                line=units[u].line,
                blockers=tuple(Blocker(f.object(o), o, kind, b) for o, kind, b in bs),
            )
            for u, bs in producers
        ),
        cycle=tuple(f.object(o) for o in cycle),
        cycle_ids=tuple(cycle),
        cycle_units=tuple(cycle_units),
        unblock=tuple(Unblock(f.object(o), o, alone) for o, alone in unblock),
        text=text,
        _native=native,
    )


@dataclass(frozen=True)
class Similar:
    """One object found by :meth:`foon.Foon.find_similar`."""

    object: Object
    object_id: int
    score: float

    def to_dict(self) -> dict[str, Any]:
        return {"object": self.object.to_dict(), "object_id": self.object_id, "score": self.score}


_indexes: weakref.WeakKeyDictionary[Foon, _foon.FindIndex] = weakref.WeakKeyDictionary()


def find_similar(foon: Foon, text: str, k: int) -> list[Similar]:
    if not isinstance(text, str):
        raise TypeError(f"text must be a str, not {type(text).__name__}")
    index = _indexes.get(foon)
    if index is None:
        index = _foon.FindIndex(foon._native)
        _indexes[foon] = index
    return [Similar(foon.object(o), o, s) for o, s in index.find(text, k)]
