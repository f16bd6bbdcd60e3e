"""Pure-Python reference for the k best trees and the bounded enumeration (slow, obviously
correct): every valid tree of a small FOON by brute force over choice assignments.

A tree is a choice of one producer for each object outside the kitchen that the choices reach
from the goal, with no object reaching itself through the choices (docs/METHODS.md, "The k best
trees"). Its cost is the tree cost of the definition: a leaf costs ``leaf``, an object
``w(f) + cost(x1) + cost(x2) + ...`` over the needed inputs of its choice f, in input order.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import foon_reference as ref


class TooMany(Exception):
    """The FOON has more trees than the enumeration budget."""


@dataclass(frozen=True)
class Tree:
    choice: tuple[tuple[int, int], ...]  # (object, unit), sorted by object
    units: frozenset[int]
    order: tuple[int, ...]  # depth-first post-order


def weights(
    method: str, rates: dict[str, float] | None
) -> tuple[Callable[[ref.RefFU], float], float]:
    """(unit weight, leaf cost) of an optimal method."""
    if method == "optimal-success":
        assert rates is not None
        return (
            lambda fu: 0.0 - math.log(rates[fu.motion]) if rates[fu.motion] > 0 else math.inf
        ), 0.0
    if method == "optimal-units":
        return (lambda fu: 1.0), 0.0
    assert method == "optimal-inputs"
    return (lambda fu: 0.0), 1.0


def all_trees(
    rf: ref.RefFoon, goal: int, k: set[int], utensils: set[str], budget: int = 4000
) -> list[Tree]:
    """Every acyclic choice assignment of the goal's closure, each once."""
    needed = {f: ref.needed_inputs(rf, f, utensils) for f in range(len(rf.fus))}
    out: list[Tree] = []
    steps = [0]

    def first_open(assign: dict[int, int]) -> int | bool | None:
        """The first object (pre-order from the goal) with no choice yet; None when complete;
        False when the choices reached so far have a cycle."""
        on_path: set[int] = set()
        seen: set[int] = set()
        found: list[int] = []

        def visit(o: int) -> bool:
            if o in k:
                return True
            if o in on_path:
                return False
            if o in seen:
                return True
            seen.add(o)
            if o not in assign:
                if not found:
                    found.append(o)
                return True
            on_path.add(o)
            for x in needed[assign[o]]:
                if not visit(x):
                    return False
            on_path.discard(o)
            return True

        if not visit(goal):
            return False
        return found[0] if found else None

    def rec(assign: dict[int, int]) -> None:
        steps[0] += 1
        if steps[0] > budget:
            raise TooMany
        o = first_open(assign)
        if o is False:
            return
        if o is None:
            order = ref._emit_tree(rf, goal, k, assign, utensils)
            out.append(Tree(tuple(sorted(assign.items())), frozenset(order), tuple(order)))
            return
        assert isinstance(o, int)
        for f in rf.producers(o):
            assign[o] = f
            rec(assign)
            del assign[o]

    if goal in k:
        return [Tree((), frozenset(), ())]
    rec({})
    return out


def cost(
    rf: ref.RefFoon,
    t: Tree,
    goal: int,
    k: set[int],
    utensils: set[str],
    weight: Callable[[int], float],
    leaf: float,
) -> float:
    """The tree cost of an assignment (a shared sub-goal counted once per use)."""
    choice = dict(t.choice)
    memo: dict[int, float] = {}

    def c(o: int) -> float:
        if o in k:
            return leaf
        if o not in memo:
            f = choice[o]
            v = weight(f)
            for x in ref.needed_inputs(rf, f, utensils):
                v += c(x)
            memo[o] = v
        return memo[o]

    return c(goal)


def best_by_set(
    rf: ref.RefFoon,
    trees: list[Tree],
    goal: int,
    k: set[int],
    utensils: set[str],
    weight: Callable[[int], float],
    leaf: float,
) -> dict[frozenset[int], float]:
    """For each set of units, the lowest cost of an assignment that gives it (finite only)."""
    best: dict[frozenset[int], float] = {}
    for t in trees:
        v = cost(rf, t, goal, k, utensils, weight, leaf)
        if math.isfinite(v) and (t.units not in best or v < best[t.units]):
            best[t.units] = v
    return best


def iter_sets(trees: list[Tree]) -> Iterator[frozenset[int]]:
    seen: set[frozenset[int]] = set()
    for t in trees:
        if t.units not in seen:
            seen.add(t.units)
            yield t.units
