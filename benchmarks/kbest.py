"""The k best trees on the 25 course goals: k = 1, 10 and 100 per goal, one run each, against
one optimal plan of the same prepared planner.

    python benchmarks/kbest.py [--data ../shared/data/foon] [--method optimal-success]

The planner is prepared once and warmed (the objective's costs over the whole FOON are
computed on its first plan), so an optimal plan only reads its tree from them; it is timed as
the median of 5 calls, and so is each ``plan_k`` (one call from Python, the results built as
``RankedTree`` objects; one call before the timings imports its Python module). Prints one
Markdown row per goal (units of the optimal tree, trees found for k = 100, the times, and
k = 10 over one plan) and the totals. Build in release mode first (``maturin build
--release`` and install the wheel)."""

from __future__ import annotations

import argparse
from dataclasses import dataclass

import foon
from _course import Course, data_arg, median_time

METHODS = ("optimal-success", "optimal-units", "optimal-inputs")
KS = (1, 10, 100)


@dataclass
class KBestTimes:
    """One goal and method: the plan's time and units (None: unsolved), and per k its time
    and the number of trees found."""

    plan: float
    units: int | None
    times: dict[int, float]
    found: dict[int, int]


def warm(p: foon.Planner, goal: foon.Object, method: str) -> None:
    """The objective's costs over the whole FOON, and the Python side of ``plan_k``."""
    p.plan(goal, method)
    p.plan_k(goal, 1, method)


def measure(p: foon.Planner, g: foon.Object, method: str, ks: tuple[int, ...] = KS) -> KBestTimes:
    tree = p.plan(g, method)
    plan = median_time(lambda: p.plan(g, method))
    times = {k: median_time(lambda k=k: p.plan_k(g, k, method)) for k in ks}  # type: ignore[misc]
    found = {k: len(p.plan_k(g, k, method)) for k in ks}
    return KBestTimes(plan, len(tree.units) if tree.solved else None, times, found)


def table(c: Course, p: foon.Planner, method: str) -> list[str]:
    """The Markdown table of one method (and the totals)."""
    warm(p, c.goals[0], method)
    k_hi = KS[-1]
    out = [f"method {method}; times in µs (median of 5)", "",
           f"| goal | units | trees (k={k_hi}) | plan | "
           + " | ".join(f"k={k}" for k in KS) + " | k=10 / plan | k=100 / plan |",
           "|---|---:|---:|---:|" + "---:|" * (len(KS) + 2)]  # fmt: skip
    tot_plan, tot = 0.0, dict.fromkeys(KS, 0.0)
    worst = 0.0
    for g in c.goals:
        m = measure(p, g, method)
        tot_plan += m.plan
        for k in KS:
            tot[k] += m.times[k]
        if m.units is not None:
            worst = max(worst, m.times[10] / m.plan)
        cells = " | ".join(f"{m.times[k] * 1e6:.1f}" for k in KS)
        units = "unsolved" if m.units is None else str(m.units)
        out.append(f"| {g.label} | {units} | {m.found[k_hi]} | {m.plan * 1e6:.1f} | {cells} | "
                   f"{m.times[10] / m.plan:.1f} | {m.times[k_hi] / m.plan:.1f} |")  # fmt: skip
    cells = " | ".join(f"{tot[k] * 1e6:.1f}" for k in KS)
    out.append(f"| **total** | | | {tot_plan * 1e6:.1f} | {cells} | {tot[10] / tot_plan:.1f} | "
               f"{tot[k_hi] / tot_plan:.1f} |")  # fmt: skip
    out += ["", f"largest k=10 / plan over solved goals: {worst:.1f}"]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    data_arg(ap)
    ap.add_argument("--method", default="optimal-success", choices=METHODS)
    args = ap.parse_args()
    c = Course.load(args.data)
    print("\n".join(table(c, c.planner(), args.method)))


if __name__ == "__main__":
    main()
