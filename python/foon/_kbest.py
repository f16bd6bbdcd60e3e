"""The k best trees (:meth:`foon.Planner.plan_k`) and the bounded enumeration of trees
(:meth:`foon.Planner.paths`): typed results over the core's plans."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from . import _foon

if TYPE_CHECKING:
    from . import Planner, TaskTree


class RankedTree:
    """One tree of a k-best list or of an enumeration: its ``rank`` (1 is the first), its
    ``cost`` (the objective's figure: success probability, unit count or kitchen-input count)
    and the :class:`foon.TaskTree` itself (built from the core's plan when first read)."""

    __slots__ = ("_plan", "_planner", "_tree", "cost", "rank")

    def __init__(self, rank: int, cost: float, tree: TaskTree) -> None:
        self.rank = rank
        self.cost = cost
        self._tree: TaskTree | None = tree
        self._plan: _foon.Plan | None = None
        self._planner: Planner | None = None

    @property
    def tree(self) -> TaskTree:
        """The tree as a :class:`foon.TaskTree`."""
        t = self._tree
        if t is None:
            from . import TaskTree

            planner = self._planner
            assert planner is not None and self._plan is not None
            t = self._tree = TaskTree(planner.foon, self._plan, planner)
        return t

    @tree.setter
    def tree(self, tree: TaskTree) -> None:
        self._tree = tree

    def __reduce__(self) -> tuple[Any, ...]:
        return (RankedTree, (self.rank, self.cost, self.tree))

    @property
    def units(self) -> list[int]:
        """FU indices in execution order."""
        return self.tree.units

    def __eq__(self, other: object) -> bool:
        return isinstance(other, RankedTree) and (self.rank, self.cost, self.tree) == (
            other.rank,
            other.cost,
            other.tree,
        )

    def __hash__(self) -> int:
        return hash((self.rank, self.cost, tuple(self.units)))

    def __repr__(self) -> str:
        return f"<RankedTree #{self.rank} cost {self.cost:g}: {len(self.units)} units>"

    def to_dict(self) -> dict[str, Any]:
        """Rank, method, cost, height, success and units (indices, execution order)."""
        t = self.tree
        return {
            "rank": self.rank,
            "method": t.method,
            "cost": self.cost,
            "height": t.height,
            "success": t.success,
            "units": t.units,
        }


def _ranked(planner: Planner, plans: Iterator[_foon.Plan]) -> Iterator[RankedTree]:
    for i, p in enumerate(plans, 1):
        yield _lazy(i, p, planner)


def _lazy(rank: int, plan: _foon.Plan, planner: Planner) -> RankedTree:
    """A ranked tree whose :class:`foon.TaskTree` is built when first read."""
    cost = plan.cost
    assert cost is not None
    r = _new(RankedTree)
    r.rank = rank
    r.cost = cost
    r._tree = None
    r._plan = plan
    r._planner = planner
    return r


_new = object.__new__


def plan_k(planner: Planner, goal: int, k: int, method: str, diverse: bool) -> list[RankedTree]:
    plans = _foon.plan_k(planner._native, goal, method, k, diverse)
    return [_lazy(i, p, planner) for i, p in enumerate(plans, 1)]


def paths(
    planner: Planner, goal: int, max_trees: int | None, max_height: int | None
) -> Iterator[RankedTree]:
    it = _foon.Paths(planner._native, goal, max_trees, max_height)
    return _ranked(planner, it)
