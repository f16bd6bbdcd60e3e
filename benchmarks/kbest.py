"""The k best trees on the 25 course goals: k = 1, 10 and 100 per goal, one run each, against
one optimal plan of the same prepared planner, on the first call and on repeated calls.

    python benchmarks/kbest.py [--data ../shared/data/foon] [--method optimal-success]

Every planner is prepared and warmed first (the objective's costs over the whole FOON are
computed by a plan of the first goal, and the Python side of ``plan_k`` is imported), so an
optimal plan only reads its tree from them. **Cold** is the first call for a goal on such a
planner (``plan_k`` then builds the goal's ancestry, which the planner keeps): the median over
5 fresh planners of one call each (the first plan of the goal for the plan; for k = 10 and
k = 100, planners on which no ``plan_k`` of that goal beyond k = 1 ran, k = 1 never building
the ancestry). **Warm** is the median of 5 repeated calls on one planner (the ancestry kept).
Each ``plan_k`` is one call from Python, the results built as ``RankedTree`` objects. Prints
one Markdown table per state: a row per goal (units of the optimal tree, trees found for
k = 100, the times, and k over one plan of the same state), the totals and the largest
k = 10 / plan over the solved goals. Build in release mode first (``maturin build --release``
and install the wheel)."""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import dataclass

import foon
from _course import Course, data_arg, median_time

METHODS = ("optimal-success", "optimal-units", "optimal-inputs")
KS = (1, 10, 100)
RUNS = 5


@dataclass
class KBestTimes:
    """One goal and method: the plan's time and units (None: unsolved), and per k its time
    and the number of trees found."""

    plan: float
    units: int | None
    times: dict[int, float]
    found: dict[int, int]


def warm(p: foon.Planner, goal: foon.Object, method: str) -> foon.Planner:
    """The objective's costs over the whole FOON, and the Python side of ``plan_k`` (a goal
    in the kitchen would build nothing; ``goal`` is the first course goal, planned for k = 1
    only, which keeps nothing)."""
    p.plan(goal, method)
    p.plan_k(goal, 1, method)
    return p


def once(fn: object) -> float:
    t = time.perf_counter()
    fn()  # type: ignore[operator]
    return time.perf_counter() - t


def measure_warm(
    p: foon.Planner, g: foon.Object, method: str, ks: tuple[int, ...] = KS
) -> KBestTimes:
    tree = p.plan(g, method)
    plan = median_time(lambda: p.plan(g, method))
    times = {k: median_time(lambda k=k: p.plan_k(g, k, method)) for k in ks}  # type: ignore[misc]
    found = {k: len(p.plan_k(g, k, method)) for k in ks}
    return KBestTimes(plan, len(tree.units) if tree.solved else None, times, found)


def measure_cold(c: Course, method: str) -> list[KBestTimes]:
    """Per goal, the medians over ``RUNS`` fresh warmed planners of the first calls: on one
    planner the first plan, k = 1 and k = 10 of each goal in turn; on another k = 100."""
    plan: list[list[float]] = [[] for _ in c.goals]
    times: list[dict[int, list[float]]] = [{k: [] for k in KS} for _ in c.goals]
    found: list[dict[int, int]] = [{} for _ in c.goals]
    units: list[int | None] = [None for _ in c.goals]
    for _ in range(RUNS):
        a = warm(c.planner(), c.goals[0], method)
        b = warm(c.planner(), c.goals[0], method)
        for i, g in enumerate(c.goals):
            # The first goal's k = 1 ran when warming: a repeated call, as is its plan.
            plan[i].append(once(lambda a=a, g=g: a.plan(g, method)))  # type: ignore[misc]
            for k, p in ((1, a), (10, a), (100, b)):
                t = time.perf_counter()
                found[i][k] = len(p.plan_k(g, k, method))
                times[i][k].append(time.perf_counter() - t)
            tree = a.plan(g, method)
            units[i] = len(tree.units) if tree.solved else None
    med = statistics.median
    return [
        KBestTimes(med(plan[i]), units[i], {k: med(times[i][k]) for k in KS}, found[i])
        for i in range(len(c.goals))
    ]


def rows(c: Course, ms: list[KBestTimes], state: str, method: str) -> list[str]:
    """The Markdown table of one state of one method (and the totals)."""
    k_hi = KS[-1]
    out = [f"method {method}, {state}; times in µs (median of {RUNS})", "",
           f"| goal | units | trees (k={k_hi}) | plan | "
           + " | ".join(f"k={k}" for k in KS) + " | k=10 / plan | k=100 / plan |",
           "|---|---:|---:|---:|" + "---:|" * (len(KS) + 2)]  # fmt: skip
    tot_plan, tot = 0.0, dict.fromkeys(KS, 0.0)
    worst, worst_goal = 0.0, ""
    for g, m in zip(c.goals, ms, strict=True):
        tot_plan += m.plan
        for k in KS:
            tot[k] += m.times[k]
        if m.units is not None and m.times[10] / m.plan > worst:
            worst, worst_goal = m.times[10] / m.plan, g.label
        cells = " | ".join(f"{m.times[k] * 1e6:.1f}" for k in KS)
        units = "unsolved" if m.units is None else str(m.units)
        out.append(f"| {g.label} | {units} | {m.found[k_hi]} | {m.plan * 1e6:.1f} | {cells} | "
                   f"{m.times[10] / m.plan:.1f} | {m.times[k_hi] / m.plan:.1f} |")  # fmt: skip
    cells = " | ".join(f"{tot[k] * 1e6:.1f}" for k in KS)
    out.append(f"| **total** | | | {tot_plan * 1e6:.1f} | {cells} | {tot[10] / tot_plan:.1f} | "
               f"{tot[k_hi] / tot_plan:.1f} |")  # fmt: skip
    out += ["", (f"{method}, {state}: k=10 / plan {tot[10] / tot_plan:.1f} in total, "
            f"largest over solved goals {worst:.1f} ({worst_goal})")]  # fmt: skip
    return out


def table(c: Course, p: foon.Planner, method: str) -> list[str]:
    """The Markdown tables of one method: the first calls (fresh planners) and repeated calls
    (on ``p``)."""
    cold = measure_cold(c, method)
    warm(p, c.goals[0], method)
    hot = [measure_warm(p, g, method) for g in c.goals]
    return [*rows(c, cold, "cold (first call)", method), "",
            *rows(c, hot, "warm (repeated calls)", method)]  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    data_arg(ap)
    ap.add_argument("--method", default="optimal-success", choices=METHODS)
    args = ap.parse_args()
    c = Course.load(args.data)
    print("\n".join(table(c, c.planner(), args.method)))


if __name__ == "__main__":
    main()
