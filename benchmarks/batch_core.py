"""Queries in, results out: `plan_table` throughput, 1 thread against 2.

    python benchmarks/batch_core.py [--units 100k] [--queries 100k] [--kitchens 1000]
                                    [--chunk 10000] [--methods ids] [--repeat 3] [--work DIR]

Build the wheel in release mode first (`maturin build --release`, installed in its own venv).
`foon synth` writes a FOON, its kitchen and goals (seed 1, cached in the work folder). The
kitchens are that kitchen with 10 random items removed each (a `KitchenSet.with_deltas`, one
seed per kitchen); the queries pick a kitchen, a goal (a JSON object) and a method at random
(seed 2). The queries are answered `--chunk` rows per `plan_table` call, as a batch engine
would, in two orders: as drawn (each chunk touches most kitchens) and sorted by kitchen (each
chunk touches few). For each order, 1 and 2 threads run side by side in one process,
alternating, best of `--repeat`, after a first run that is not timed (the process's cache of
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
    f: foon.Foon, ks: foon.KitchenSet, q: pa.Table, chunk: int, threads: int
) -> tuple[float, pa.Table]:
    t = time.perf_counter()
    parts = [
        plan_table(f, ks, q.slice(i, chunk), threads=threads) for i in range(0, q.num_rows, chunk)
    ]
    return time.perf_counter() - t, pa.concat_tables(parts)


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
    base_best = {1: float("inf"), 2: float("inf")}
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
                t = time.perf_counter()
                for (kid, method), gs in by_kitchen.items():
                    planners[kid].plan_many(gs, method, threads=threads)
                s = time.perf_counter() - t
                base_best[threads] = min(base_best[threads], s)
                print(f"[plan_many, {threads} thread(s): {fmt_s(s)}]", file=sys.stderr, flush=True)
    for order, q in (("as drawn", drawn), ("sorted by kitchen", grouped)):
        best = {1: float("inf"), 2: float("inf")}
        want = run(f, ks, q, args.chunk, 2)[1]  # a first run, not timed: the cache filled
        for _ in range(args.repeat):
            for threads in (1, 2):
                s, t = run(f, ks, q, args.chunk, threads)
                best[threads] = min(best[threads], s)
                assert t.equals(want), (order, threads)
                print(f"[{order}, {threads} thread(s): {fmt_s(s)}]", file=sys.stderr, flush=True)
        solved = want.column("solved").to_pylist().count(True)
        out.append((order, best, solved))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(
        f"\n### plan_table: {fmt_n(count)} queries, {name} units ({f.object_count:,} objects), "
        f"{args.kitchens} kitchens, chunks of {args.chunk:,}, methods {args.methods}\n"
    )
    print("| order | solved | 1 thread | 2 threads | queries/s, 1 | queries/s, 2 | 2 / 1 |")
    print("|---|---|---|---|---|---|---|")
    if args.baseline:
        out.insert(0, ("plan_many per kitchen (baseline)", base_best, out[0][2]))
    for order, best, solved in out:
        print(
            f"| {order} | {solved:,} | {fmt_s(best[1])} | {fmt_s(best[2])} | "
            f"{count / best[1]:,.0f} | {count / best[2]:,.0f} | {best[1] / best[2]:.2f}x |"
        )
    print(f"\nPeak resident memory of the process: {peak:,.0f} MB.")
    print(
        f"\nCommand: `python benchmarks/batch_core.py --units {args.units} --queries "
        f"{args.queries} --kitchens {args.kitchens} --chunk {args.chunk} --methods "
        f"{args.methods}{' --baseline' if args.baseline else ''}`"
    )


if __name__ == "__main__":
    main()
