"""A slow, obviously correct reference for the robot/human split (``docs/METHODS.md``, "The
robot/human split"): it enumerates every tree of a small FOON, with every assignment of its
steps to the robot or the human, and keeps the best cost for each number of human steps.

A *tree* here is a derivation: the goal is made by one of its producers, each needed input of
that producer by a tree of its own (a kitchen object is a leaf), so a sub-goal used twice is
made twice, each time in any way (tree cost). Its cost is computed as the core does, in the
same order: the step's own weight ``0.0 - ln(rate)`` (robot or human), plus the inputs' costs
in input order. Trees that make an object inside a tree of that same object are skipped: cut
at the inner one, they give a tree that costs no more with no more human steps, so the best
costs are the same.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable

import foon_reference as ref


class TooBig(Exception):
    """The enumeration passed its limit (the FOON is too large for brute force)."""


def weight(rate: float) -> float:
    return 0.0 - math.log(rate) if rate > 0 else math.inf


def best_costs(
    rf: ref.RefFoon,
    kitchen: set[int],
    utensils: set[str],
    robot: Callable[[int], float],
    human: Callable[[int], float],
    goal: int,
    max_human: int,
    limit: int = 20_000,
) -> list[float]:
    """Per budget m = 0..max_human: the least cost of a tree of ``goal`` with at most m
    human steps (inf when there is none)."""
    work = 0

    def trees(o: int, path: frozenset[int]) -> set[tuple[int, float]]:
        """(human steps, cost) of every tree of o that does not make an object of ``path``."""
        nonlocal work
        if o in kitchen:
            return {(0, 0.0)}
        out: set[tuple[int, float]] = set()
        inner = path | {o}
        for f in rf.producers(o):
            ins = ref.needed_inputs(rf, f, utensils)
            if any(x in inner for x in ins):
                continue
            below = [sorted(trees(x, inner)) for x in ins]
            for own_h, w in ((0, weight(robot(f))), (1, weight(human(f)))):
                for combo in itertools.product(*below):
                    work += 1
                    if work > limit:
                        raise TooBig
                    h = own_h + sum(ch for ch, _ in combo)
                    if h > max_human:
                        continue
                    c = w
                    for _, cc in combo:
                        c = c + cc
                    if c != math.inf:
                        out.add((h, c))
        return out

    found = trees(goal, frozenset())
    return [min((c for h, c in found if h <= m), default=math.inf) for m in range(max_human + 1)]


def front(costs: list[float]) -> list[int]:
    """The budgets that improve on every smaller one."""
    out, last = [], math.inf
    for m, c in enumerate(costs):
        if c < last:
            out.append(m)
            last = c
    return out


def fixed_tree(
    steps: list[tuple[int, int]],
    robot: Callable[[int], float],
    human: Callable[[int], float],
    m: int,
) -> tuple[list[tuple[int, str, int]], float]:
    """The lab's method on a tree given as its makings (unit, times) in execution order: the
    m step instances of lowest robot rate (ties: the earlier making) go to the human. The
    makings split between both (the human's part first), and the success: exp(-cost), the
    cost summing times * weight in that order."""
    order = sorted(range(len(steps)), key=lambda i: (robot(steps[i][0]), i))
    to_human = [0] * len(steps)
    left = m
    for i in order:
        to_human[i] = min(left, steps[i][1])
        left -= to_human[i]
    out, cost = [], 0.0
    for i, (u, times) in enumerate(steps):
        h, r = to_human[i], times - to_human[i]
        if h:
            cost += h * weight(human(u))
            out.append((u, "human", h))
        if r:
            cost += r * weight(robot(u))
            out.append((u, "robot", r))
    return out, math.exp(-cost)
