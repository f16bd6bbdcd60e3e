"""The robot/human split on the 25 course goals: M = 0..5, per goal, one run.

    python benchmarks/split.py [--data ../shared/data/foon] [--max-human 5]

Build the wheel in release mode first (`maturin build --release` and install it).

The robot's profile is the course `motion.txt`. The human's profile is every rate 1 (the
default: a person never fails a step), so the split gives the human the robot's weakest
steps. For each goal and each M: the time of one `Planner.split` call (CPU time of the
process), the best success with at most M human steps, and the size of the front; and the same
with `fixed_tree=True` at M = top (the lab's method, for comparison of successes). Printed as
Markdown. Successes are as tree cost counts them (a shared sub-goal once per use), so they can
be tiny on goals with much sharing.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass

import foon
from _course import Course, data_arg


@dataclass
class SplitTimes:
    """One goal: the CPU time per M = 0..top, the split at top and the fixed tree's best."""

    times: list[float]
    last: foon.SplitResult
    fixed: float | None


def profiles(c: Course) -> foon.Profiles:
    return foon.Profiles({"robot": c.motions})


def measure(p: foon.Planner, prof: foon.Profiles, g: foon.Object, top: int) -> SplitTimes:
    times: list[float] = []
    last = None
    for m in range(top + 1):
        t0 = time.process_time()
        last = p.split(g, prof, m)
        times.append(time.process_time() - t0)
    assert last is not None
    fixed = p.split(g, prof, top, fixed_tree=True).fixed
    return SplitTimes(times, last, fixed[-1].success if fixed else None)


def table(c: Course, top: int) -> list[str]:
    """The Markdown table (and the totals)."""
    p = c.planner(rated=False)
    prof = profiles(c)
    p.split(c.goals[0], prof, 0)  # the ranks, once per kitchen
    head = " | ".join(f"M={m} ms" for m in range(top + 1))
    out = [f"| goal | {head} | success M=0 | success M={top} | fixed M={top} | front |",
           "|" + "---|" * (top + 6)]  # fmt: skip
    totals = [0.0] * (top + 1)
    for g in c.goals:
        s = measure(p, prof, g, top)
        for m, t in enumerate(s.times):
            totals[m] += t
        cells = " | ".join(f"{t * 1000:.2f}" for t in s.times)
        if not s.last.solved:
            out.append(f"| {g.label} | {cells} | - | - | - | 0 |")
            continue
        b0, bm = s.last.best[0], s.last.best[top]
        fx = "-" if s.fixed is None else f"{s.fixed:.3g}"
        out.append(f"| {g.label} | {cells} | {b0:.3g} | {bm:.3g} | {fx} | {len(s.last.front)} |")
    cells = " | ".join(f"{t * 1000:.1f}" for t in totals)
    out.append(f"| **total** | {cells} | | | | |")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    data_arg(ap)
    ap.add_argument("--max-human", type=int, default=5)
    args = ap.parse_args()
    print("\n".join(table(Course.load(args.data), args.max_human)))


if __name__ == "__main__":
    main()
