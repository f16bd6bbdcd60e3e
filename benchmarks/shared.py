"""``optimal-shared`` on the 25 course goals: per goal, one run, the distinct units of the
``optimal-units`` tree (the first incumbent) and of the ``optimal-shared`` tree, whether it is
proven optimal, the search nodes and the time of the plan.

    python benchmarks/shared.py [--data ../shared/data/foon] [--objective units|success]

Prints one Markdown table. Build in release mode first (``maturin develop --release``).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import foon

HERE = Path(__file__).resolve().parent


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=HERE.parents[1] / "shared" / "data" / "foon")
    ap.add_argument("--objective", choices=["units", "success"], default="units")
    args = ap.parse_args()
    f = foon.load(args.data / "FOON.txt")
    kitchen = foon.Kitchen.load(args.data / "kitchen.json")
    motions = foon.MotionRates.load(args.data / "motion.txt")
    utensils = foon.load_utensils(args.data / "utensils.txt")
    goals = [
        foon.Object.from_dict(d)
        for d in json.loads((args.data / "goal_nodes_25.json").read_text(encoding="utf-8"))
    ]
    planner = f.planner(kitchen, motions=motions, utensils=utensils)
    print(f"objective: {args.objective}")
    print("| goal | optimal-units | optimal-shared | proven | nodes | seconds |")
    print("|---|---:|---:|---|---:|---:|")
    worst = 0.0
    for g in goals:
        units = planner.plan(g, "optimal-units")
        if not units.solved:
            print(f"| {g.label} | - | - | - | - | - |")
            continue
        t0 = time.perf_counter()
        shared = planner.plan(g, "optimal-shared", objective=args.objective)
        dt = time.perf_counter() - t0
        worst = max(worst, dt)
        print(
            f"| {g.label} | {len(units.units)} | {len(shared.units)} | {shared.proven} | "
            f"{shared.expanded} | {dt:.4f} |"
        )
    print(f"\nslowest goal: {worst:.4f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
