"""``optimal-shared`` on the 25 course goals: per goal, one run, the distinct units of the
``optimal-units`` tree (the first incumbent) and of the ``optimal-shared`` tree, whether it is
proven optimal, the search nodes and the time of the plan.

    python benchmarks/shared.py [--data ../shared/data/foon] [--objective units|success]

Prints one Markdown table. Build in release mode first (``maturin build --release`` and
install the wheel).
"""

from __future__ import annotations

import argparse

import foon
from _course import Course, data_arg, timed


def measure(p: foon.Planner, g: foon.Object, objective: str) -> tuple[float, foon.TaskTree]:
    """The time of one ``optimal-shared`` plan, and the plan."""
    return timed(lambda: p.plan(g, "optimal-shared", objective=objective))  # type: ignore[arg-type]


def table(c: Course, p: foon.Planner, objective: str) -> list[str]:
    out = [f"objective: {objective}",
           "| goal | optimal-units | optimal-shared | proven | nodes | seconds |",
           "|---|---:|---:|---|---:|---:|"]  # fmt: skip
    worst = 0.0
    for g in c.goals:
        units = p.plan(g, "optimal-units")
        if not units.solved:
            out.append(f"| {g.label} | - | - | - | - | - |")
            continue
        dt, shared = measure(p, g, objective)
        worst = max(worst, dt)
        out.append(f"| {g.label} | {len(units.units)} | {len(shared.units)} | {shared.proven} | "
                   f"{shared.expanded} | {dt:.4f} |")  # fmt: skip
    out.append(f"\nslowest goal: {worst:.4f} s")
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    data_arg(ap)
    ap.add_argument("--objective", choices=["units", "success"], default="units")
    args = ap.parse_args()
    c = Course.load(args.data)
    print("\n".join(table(c, c.planner(), args.objective)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
