"""The k best trees on the 25 course goals: k = 1, 10 and 100 per goal, one run each, against
one optimal plan of the same prepared planner.

    python benchmarks/kbest.py [--data ../shared/data/foon] [--method optimal-success]

The planner is prepared once and warmed (the objective's costs over the whole FOON are
computed on its first plan), so an optimal plan only reads its tree from them; it is timed as
the median of 5 calls. One ``plan_k`` call before the timings imports its Python module. Each ``plan_k`` is one call from Python (the results built as
``RankedTree`` objects). Prints one Markdown row per goal (units of the optimal tree, trees
found for k = 100, the times, and k = 10 over one plan) and the totals. Build in release mode
first (``maturin develop --release``)."""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

import foon

HERE = Path(__file__).resolve().parent


def timed(fn: object) -> tuple[float, object]:
    t = time.perf_counter()
    out = fn()  # type: ignore[operator]
    return time.perf_counter() - t, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=HERE.parent.parent / "shared" / "data" / "foon")
    ap.add_argument("--method", default="optimal-success",
                    choices=("optimal-success", "optimal-units", "optimal-inputs"))  # fmt: skip
    args = ap.parse_args()
    d = args.data
    f = foon.load(d / "FOON.txt")
    p = f.planner(
        foon.Kitchen.load(d / "kitchen.json"),
        motions=foon.MotionRates.load(d / "motion.txt"),
        utensils=foon.load_utensils(d / "utensils.txt"),
    )
    goals = [foon.Object.from_dict(g) for g in json.loads((d / "goal_nodes_25.json").read_text())]
    p.plan(goals[0], args.method)  # the objective's costs, once per planner
    p.plan_k(goals[0], 1, args.method)  # the Python side of plan_k, imported on first use
    print(f"method {args.method}; times in ms")
    print()
    print("| goal | units | trees (k=100) | plan | k=1 | k=10 | k=100 | k=10 / plan |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    totals = [0.0, 0.0, 0.0, 0.0]
    worst = 0.0
    for g in goals:
        plan_s = statistics.median(timed(lambda g=g: p.plan(g, args.method))[0] for _ in range(5))
        tree = p.plan(g, args.method)
        t1, _ = timed(lambda g=g: p.plan_k(g, 1, args.method))
        t10, _ = timed(lambda g=g: p.plan_k(g, 10, args.method))
        t100, r100 = timed(lambda g=g: p.plan_k(g, 100, args.method))
        n = len(r100)  # type: ignore[arg-type]
        ratio = t10 / plan_s
        worst = max(worst, ratio) if tree.solved else worst
        for i, t in enumerate((plan_s, t1, t10, t100)):
            totals[i] += t
        units = len(tree.units) if tree.solved else "unsolved"
        print(f"| {g.label} | {units} | {n} | {plan_s * 1e3:.3f} | {t1 * 1e3:.3f} | "
              f"{t10 * 1e3:.3f} | {t100 * 1e3:.3f} | {ratio:.1f} |")  # fmt: skip
    ms = [f"{t * 1e3:.2f}" for t in totals]
    print(f"| **total** | | | {ms[0]} | {ms[1]} | {ms[2]} | {ms[3]} | "
          f"{totals[2] / totals[0]:.1f} |")  # fmt: skip
    print()
    print(f"largest k=10 / plan over solved goals: {worst:.1f}")


if __name__ == "__main__":
    main()
