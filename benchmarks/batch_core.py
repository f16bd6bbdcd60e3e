"""Queries in, results out: `plan_table` throughput, 1 thread against 2.

    python benchmarks/batch_core.py [--units 100k] [--queries 100k] [--kitchens 1000]
                                    [--chunk 10000] [--methods ids] [--repeat 3] [--work DIR]
                                    [--deltas incremental,from-scratch] [--orders ...]

Build the wheel in release mode first (`maturin build --release`, installed in its own venv).
`foon synth` writes a FOON, its kitchen and goals (seed 1, cached in the work folder). The
kitchens are that kitchen with 10 random items removed each (a `KitchenSet.with_deltas`, one
seed per kitchen); the queries pick a kitchen, a goal (a JSON object) and a method at random
(seed 2). The queries are answered `--chunk` rows per `plan_table` call, as a batch engine
would, in two orders (`--orders`): as drawn (each chunk touches most kitchens) and sorted by
kitchen (each chunk touches few); for each order, with the delta kitchens prepared each way of
`--deltas` (from the base kitchen's preparation, or from their own items). For each, 1 and 2
threads run side by side in one process, alternating, best of `--repeat` (wall and, apart,
CPU seconds of the process), after a first run that is not timed (the process's cache of
prepared kitchens then holds what fits in it, for every timed run alike). Every run gives the same table
(checked). With `--baseline`, the same rows are also planned the way a caller would without
batches: one `Planner` per kitchen (built before the clock starts, as the batch's cache holds
its prepared kitchens) and `Planner.plan_many` over each kitchen's rows, one method at a time:
the ratio is what the batch layer (Arrow columns, row checks, grouping) costs or saves.
Prints a Markdown table and the command.
"""

from __future__ import annotations

import argparse
import json
import random
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import foon
import pyarrow as pa
from foon._arrow import plan_table
from scale import fmt_n, fmt_s, parse_size

SEED = 1


def run(
    f: foon.Foon, ks: foon.KitchenSet, q: pa.Table, chunk: int, threads: int, deltas: str
) -> tuple[float, float, pa.Table]:
    """Wall and CPU seconds (the process's, every thread) of the run, and its table."""
    t, c = time.perf_counter(), time.process_time()
    parts = [
        plan_table(f, ks, q.slice(i, chunk), threads=threads, deltas=deltas)
        for i in range(0, q.num_rows, chunk)
    ]
    return time.perf_counter() - t, time.process_time() - c, pa.concat_tables(parts)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--units", default="100k")
    ap.add_argument("--queries", default="100k")
    ap.add_argument("--kitchens", type=int, default=1000)
    ap.add_argument("--goals", type=int, default=200)
    ap.add_argument("--chunk", type=int, default=10_000)
    ap.add_argument("--methods", default="ids")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--baseline", action="store_true")
    ap.add_argument("--deltas", default="incremental",
                    help="how delta kitchens are prepared, comma-separated: incremental, "
                         "from-scratch")  # fmt: skip
    ap.add_argument("--orders", default="as drawn,sorted by kitchen")
    ap.add_argument("--work")
    args = ap.parse_args()
    work = Path(args.work or tempfile.mkdtemp(prefix="foon-batch-"))
    work.mkdir(parents=True, exist_ok=True)
    n = parse_size(args.units)
    name = fmt_n(n)
    text = work / f"synth-{name}.txt"
    kitchen, goals = work / f"synth-{name}-kitchen.json", work / f"synth-{name}-goals.json"
    if not text.exists():
        subprocess.run(
            [sys.executable, "-m", "foon", "synth", "--units", str(n), "--seed", str(SEED),
             "-o", str(text), "--kitchen", str(kitchen), "--goals", str(goals),
             "--goal-count", str(args.goals), "-q"],
            check=True,
        )  # fmt: skip
    f = foon.Foon.load(text)
    base = foon.Kitchen.load(kitchen)
    items = list(base)
    deltas = {}
    for k in range(args.kitchens):
        rnd = random.Random(k)
        deltas[f"k{k}"] = ((), rnd.sample(items, min(10, len(items))))
    ks = foon.KitchenSet.with_deltas(base, deltas)
    goal_texts = [json.dumps(g.to_dict()) for g in foon.load_goals(goals)]
    methods = args.methods.split(",")
    rnd = random.Random(2)
    count = parse_size(args.queries)
    rows = [
        (str(i), f"k{rnd.randrange(args.kitchens)}", rnd.choice(goal_texts), rnd.choice(methods))
        for i in range(count)
    ]
    drawn = pa.table({c: [r[j] for r in rows] for j, c in
                      enumerate(("query_id", "kitchen_id", "goal", "method"))})  # fmt: skip
    grouped = drawn.take(pa.array(sorted(range(count), key=lambda i: rows[i][1])))
    out = []
    tables: dict[str, pa.Table] = {}
    base_best = {1: float("inf"), 2: float("inf")}
    base_cpu = {1: float("inf"), 2: float("inf")}
    if args.baseline:
        planners = {k: f.planner(ks[k]) for k in ks.ids}
        by_kitchen: dict[tuple[str, str], list[foon.Object]] = {}
        objects = {t: foon.Object.from_dict(json.loads(t)) for t in goal_texts}
        for _, kid, goal, method in rows:
            by_kitchen.setdefault((kid, method), []).append(objects[goal])
        for p in planners.values():
            p.plan_many(list(objects.values()), methods[0], threads=1)
        for _ in range(args.repeat):
            for threads in (1, 2):
                t, c = time.perf_counter(), time.process_time()
                for (kid, method), gs in by_kitchen.items():
                    planners[kid].plan_many(gs, method, threads=threads)
                s = time.perf_counter() - t
                base_best[threads] = min(base_best[threads], s)
                base_cpu[threads] = min(base_cpu[threads], time.process_time() - c)
                print(f"[plan_many, {threads} thread(s): {fmt_s(s)}]", file=sys.stderr, flush=True)
    orders = {"as drawn": drawn, "sorted by kitchen": grouped}
    for order in args.orders.split(","):
        q = orders[order]
        for deltas in args.deltas.split(","):
            best = {1: float("inf"), 2: float("inf")}
            cpu = {1: float("inf"), 2: float("inf")}
            # A first run, not timed: the cache filled.
            want = run(f, ks, q, args.chunk, 2, deltas)[2]
            for _ in range(args.repeat):
                for threads in (1, 2):
                    s, c, t = run(f, ks, q, args.chunk, threads, deltas)
                    best[threads] = min(best[threads], s)
                    cpu[threads] = min(cpu[threads], c)
                    assert t.equals(want), (order, deltas, threads)
                    print(f"[{order}, deltas {deltas}, {threads} thread(s): {fmt_s(s)}, "
                          f"CPU {fmt_s(c)}]", file=sys.stderr, flush=True)  # fmt: skip
            if tables.setdefault(order, want) is not want:
                assert want.equals(tables[order]), (order, deltas)
            solved = want.column("solved").to_pylist().count(True)
            out.append((f"{order}, deltas {deltas}", best, cpu, solved))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(
        f"\n### plan_table: {fmt_n(count)} queries, {name} units ({f.object_count:,} objects), "
        f"{args.kitchens} kitchens, chunks of {args.chunk:,}, methods {args.methods}\n"
    )
    print("| order | solved | 1 thread | 2 threads | queries/s, 1 | queries/s, 2 | 2 / 1 "
          "| CPU, 1 | CPU, 2 |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|")
    if args.baseline:
        out.insert(0, ("plan_many per kitchen (baseline)", base_best, base_cpu, out[0][3]))
    for order, best, cpu, solved in out:
        print(
            f"| {order} | {solved:,} | {fmt_s(best[1])} | {fmt_s(best[2])} | "
            f"{count / best[1]:,.0f} | {count / best[2]:,.0f} | {best[1] / best[2]:.2f}x | "
            f"{fmt_s(cpu[1])} | {fmt_s(cpu[2])} |"
        )
    print(f"\nPeak resident memory of the process: {peak:,.0f} MB.")
    print(
        f"\nCommand: `python benchmarks/batch_core.py --units {args.units} --queries "
        f"{args.queries} --kitchens {args.kitchens} --chunk {args.chunk} --methods "
        f"{args.methods} --deltas {args.deltas}{' --baseline' if args.baseline else ''}`"
    )


if __name__ == "__main__":
    main()
