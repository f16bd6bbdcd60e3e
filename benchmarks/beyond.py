"""Explanations, the split, the k best trees and optimal-shared in one run, on the 25 course goals
(course FOON, kitchen, motion rates and utensils): per goal, ``explain``; the robot/human split
for M = 0..5 (and the lab's fixed-tree method); the k best trees for k = 1, 10 and 100 of each
optimal objective with the ratio to one optimal plan; and ``optimal-shared`` (time, units,
proven).

    python benchmarks/beyond.py [--data ../shared/data/foon] [--max-human 5]

Prints Markdown tables and the command line. Build the wheel in release mode first
(``maturin build --release`` and install it). The machine may be shared: read the ratios,
which are measured side by side in this one run, rather than the absolute times."""

from __future__ import annotations

import argparse
import platform
import shlex
import sys

import foon
import kbest
import shared
import split
from _course import Course, data_arg, median_time


def explain_table(c: Course, p: foon.Planner) -> list[str]:
    """``Planner.explain`` per goal: the status, the shopping list's and the cycle's length, and
    the median time of 5 calls against one plan of the same method."""
    method = "optimal-units"
    p.explain(c.goals[0], method)
    out = ["| goal | status | shopping | cycle | explain ms | plan ms | explain / plan |",
           "|---|---|---:|---:|---:|---:|---:|"]  # fmt: skip
    te = tp = 0.0
    for g in c.goals:
        e = p.explain(g, method)
        t = median_time(lambda g=g: p.explain(g, method))  # type: ignore[misc]
        tpl = median_time(lambda g=g: p.plan(g, method))  # type: ignore[misc]
        te, tp = te + t, tp + tpl
        missing = len(e.shopping) if e.shopping else "-"
        cycle = len(e.cycle) if e.cycle else "-"
        out.append(f"| {g.label} | {e.status} | {missing} | {cycle} | {t * 1e3:.3f} | "
                   f"{tpl * 1e3:.3f} | {t / tpl:.1f} |")  # fmt: skip
    out.append(f"| **total** | | | | {te * 1e3:.2f} | {tp * 1e3:.2f} | {te / tp:.1f} |")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    data_arg(ap)
    ap.add_argument("--max-human", type=int, default=5)
    args = ap.parse_args()
    c = Course.load(args.data)
    p = c.planner()
    print(f"`{shlex.join(['python', *sys.argv])}` (foon {foon.__version__}, Python "
          f"{platform.python_version()}, {platform.machine()})")  # fmt: skip
    print("\n### explain (method optimal-units)\n")
    print("\n".join(explain_table(c, p)))
    print(f"\n### split, M = 0..{args.max_human} (CPU ms per call)\n")
    print("\n".join(split.table(c, args.max_human)))
    for method in kbest.METHODS:
        print(f"\n### k best, {method}\n")
        print("\n".join(kbest.table(c, p, method)))
    print("\n### optimal-shared\n")
    print("\n".join(shared.table(c, p, "units")))


if __name__ == "__main__":
    main()
