"""The robot/human split on the 25 course goals: M = 0..5, per goal, one run.

    python benchmarks/split.py [--data ../shared/data/foon] [--max-human 5]

Build the wheel in release mode first (`maturin develop --release`).

The robot's profile is the course `motion.txt`. The human's profile is every rate 1 (the
default: a person never fails a step), so the split gives the human the robot's weakest
steps. For each goal and each M: the time of one `Planner.split` call (CPU time of the
process), the best success with at most M human steps, and the size of the front; and the same
with `fixed_tree=True` at M = 5 (the lab's method, for comparison of successes). Printed as
Markdown. Successes are as tree cost counts them (a shared sub-goal once per use), so they can
be tiny on goals with much sharing.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import foon

HERE = Path(__file__).resolve().parent


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=HERE.parent.parent / "shared" / "data" / "foon")
    ap.add_argument("--max-human", type=int, default=5)
    args = ap.parse_args()
    d = args.data
    f = foon.load(d / "FOON.txt")
    kitchen = foon.Kitchen.load(d / "kitchen.json")
    motions = foon.MotionRates.load(d / "motion.txt")
    utensils = foon.load_utensils(d / "utensils.txt")
    goals = [foon.Object.from_dict(g) for g in json.loads((d / "goal_nodes_25.json").read_text())]
    planner = f.planner(kitchen, utensils=utensils)
    profiles = foon.Profiles({"robot": motions})
    planner.split(goals[0], profiles, 0)  # the ranks, once per kitchen
    top = args.max_human
    head = " | ".join(f"M={m} ms" for m in range(top + 1))
    print(f"| goal | {head} | success M=0 | success M={top} | fixed M={top} | front |")
    print("|" + "---|" * (top + 6))
    totals = [0.0] * (top + 1)
    for g in goals:
        times, last = [], None
        for m in range(top + 1):
            t0 = time.process_time()
            last = planner.split(g, profiles, m)
            times.append(time.process_time() - t0)
        assert last is not None
        for m, t in enumerate(times):
            totals[m] += t
        fixed = planner.split(g, profiles, top, fixed_tree=True).fixed
        cells = " | ".join(f"{t * 1000:.2f}" for t in times)
        if not last.solved:
            print(f"| {g.label} | {cells} | - | - | - | 0 |")
            continue
        b0, bm = last.best[0], last.best[top]
        fx = fixed[-1].success if fixed else None
        print(f"| {g.label} | {cells} | {b0:.3g} | {bm:.3g} | "
              f"{'-' if fx is None else f'{fx:.3g}'} | {len(last.front)} |")  # fmt: skip
    cells = " | ".join(f"{t * 1000:.1f}" for t in totals)
    print(f"| **total** | {cells} | | | | |")


if __name__ == "__main__":
    main()
