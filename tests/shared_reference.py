"""A small, slow, obviously correct reference for ``optimal-shared``: every valid set of FUs
of a small FOON by brute force.

A set of FUs is valid for a goal when, in some order, every FU's needed inputs are in the
kitchen or made by an earlier FU, and the goal is in the kitchen or made
(``foon_reference.is_valid``). The fewest distinct units is the size of the smallest valid
set; the best success is the largest product of motion rates over a valid set. Only FUs whose
needed inputs are all derivable can be in a valid set (the others can never run), so the
enumeration is over those.
"""

from __future__ import annotations

import itertools
import math

import foon_reference as ref


def runnable_fus(foon: ref.RefFoon, kitchen_ids: set[int], utensils: set[str]) -> list[int]:
    """The FUs whose needed inputs are all derivable from the kitchen."""
    d = ref.derivable(foon, kitchen_ids, utensils)
    return [
        f for f in range(len(foon.fus)) if all(x in d for x in ref.needed_inputs(foon, f, utensils))
    ]


def fewest_units(
    foon: ref.RefFoon, goal: int, kitchen_ids: set[int], utensils: set[str]
) -> tuple[int, tuple[int, ...]] | None:
    """The size of the smallest valid set and the first such set (smallest first, then in
    lexicographic order of FU indices), or None when no set is valid (a goal that is not
    derivable has none: derivability is the union of every set's reach)."""
    if goal not in kitchen_ids and goal not in ref.derivable(foon, kitchen_ids, utensils):
        return None
    fus = runnable_fus(foon, kitchen_ids, utensils)
    for k in range(len(fus) + 1):
        for subset in itertools.combinations(fus, k):
            if ref.is_valid(foon, list(subset), goal, kitchen_ids, utensils):
                return k, subset
    return None


def best_success(
    foon: ref.RefFoon,
    goal: int,
    kitchen_ids: set[int],
    utensils: set[str],
    rates: dict[str, float],
) -> float | None:
    """The largest product of motion rates over the valid sets (None when none is valid)."""
    if goal not in kitchen_ids and goal not in ref.derivable(foon, kitchen_ids, utensils):
        return None
    fus = runnable_fus(foon, kitchen_ids, utensils)
    best: float | None = None
    for k in range(len(fus) + 1):
        for subset in itertools.combinations(fus, k):
            if ref.is_valid(foon, list(subset), goal, kitchen_ids, utensils):
                p = math.prod(rates[foon.fus[f].motion] for f in subset)
                if best is None or p > best:
                    best = p
    return best


def distinct_success(foon: ref.RefFoon, units: list[int], rates: dict[str, float]) -> float:
    """The product of motion rates over the distinct FUs of ``units``."""
    return math.prod(rates[foon.fus[f].motion] for f in set(units))
