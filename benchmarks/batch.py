"""`foon.batch` end to end: files in, Parquet partitions out, locally and on Dask.

    python benchmarks/batch.py [--units 20k] [--queries 100k] [--kitchens 100] [--goals 200]
                               [--chunk 20000] [--sweep 1000,5000,20000] [--methods ids]
                               [--repeat 2] [--work DIR]

The issue's run: `--units 1M --queries 1M --kitchens 1000`. Build the wheel in release mode
first (`maturin build --release`, installed in its own venv with `pyarrow` and
`dask[distributed]`).

`foon synth` writes a FOON, its kitchen and goals (seed 1, cached in the work folder), and
`foon index` its `.foonidx`. The kitchens are that kitchen with 10 random items removed each
(a base-plus-deltas kitchen-set file, one seed per kitchen); the queries pick a kitchen, a
goal (a JSON object) and a method at random (seed 2) and are written as Parquet, sorted by
kitchen (so that a chunk touches few kitchens). Each configuration answers the whole file
with `foon.batch` into its own folder (`resume=False`), best of `--repeat` rounds after one
that is not timed, the configurations taking turns (one run of each per round, so that the
machine's load falls on all alike); the time is the whole call (reading and checking the
file, planning, writing and hashing the partitions). Every run gives the same partitions
(checked).

- local, 1 thread and 2 threads (`--chunk`);
- Dask, a `LocalCluster` of 1 and of 2 single-threaded worker processes (`--chunk`);
- the per-task overhead of Dask against the chunk size (`--sweep`): with 1 worker, the time
  over local 1 thread at the same chunk size, per task and as a share of local;
- the scheduler's bound: no-op tasks per second through the same 2-worker cluster, and the
  client's cost per query of writing and hashing partitions (it is the only writer);
- a projection to N machines (the method is printed with it).

Prints Markdown tables and the command.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import foon
import pyarrow as pa
import pyarrow.parquet as pq
from scale import fmt_n, fmt_s, parse_size

SEED = 1


def prepare(args: argparse.Namespace, work: Path) -> tuple[Path, Path, Path, int]:
    n = parse_size(args.units)
    name = fmt_n(n)
    text = work / f"synth-{name}.txt"
    index = work / f"synth-{name}.foonidx"
    kitchen, goals = work / f"synth-{name}-kitchen.json", work / f"synth-{name}-goals.json"
    if not index.exists():
        subprocess.run(
            [sys.executable, "-m", "foon", "synth", "--units", str(n), "--seed", str(SEED),
             "-o", str(text), "--kitchen", str(kitchen), "--goals", str(goals),
             "--goal-count", str(args.goals), "-q"],
            check=True,
        )  # fmt: skip
        subprocess.run(
            [sys.executable, "-m", "foon", "index", str(text), "-o", str(index)],
            check=True,
            stdout=subprocess.DEVNULL,
        )
    items = json.loads(kitchen.read_text())
    deltas = {}
    for k in range(args.kitchens):
        rnd = random.Random(k)
        deltas[f"k{k:05d}"] = {"remove": rnd.sample(items, min(10, len(items)))}
    kset = work / f"kitchens-{name}-{args.kitchens}.json"
    kset.write_text(json.dumps({"base": kitchen.name, "kitchens": deltas}))
    count = parse_size(args.queries)
    queries = work / f"queries-{name}-{args.kitchens}-{count}-{args.methods}.parquet"
    if not queries.exists():
        goal_texts = [json.dumps(g.to_dict()) for g in foon.load_goals(goals)]
        methods = args.methods.split(",")
        rnd = random.Random(2)
        rows = [
            (f"k{rnd.randrange(args.kitchens):05d}", rnd.choice(goal_texts), rnd.choice(methods))
            for _ in range(count)
        ]
        rows.sort(key=lambda r: r[0])
        t = pa.table({
            "query_id": [str(i) for i in range(count)],
            "kitchen_id": [r[0] for r in rows],
            "goal": [r[1] for r in rows],
            "method": [r[2] for r in rows],
        })  # fmt: skip
        pq.write_table(t, queries, row_group_size=65536)
    return index, kset, queries, count


def noop(x: int) -> int:
    return x


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--units", default="20k")
    ap.add_argument("--queries", default="100k")
    ap.add_argument("--kitchens", type=int, default=100)
    ap.add_argument("--goals", type=int, default=200)
    ap.add_argument("--chunk", type=int, default=None, help="default: foon's default")
    ap.add_argument("--sweep", default="1000,5000,20000")
    ap.add_argument("--methods", default="ids")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--work")
    args = ap.parse_args()
    from distributed import Client, LocalCluster
    from foon._batch import DEFAULT_CHUNK_SIZE

    chunk = args.chunk or DEFAULT_CHUNK_SIZE
    work = Path(args.work or tempfile.mkdtemp(prefix="foon-batch-"))
    work.mkdir(parents=True, exist_ok=True)
    index, kset, queries, count = prepare(args, work)
    f = foon.load(index)
    ks = foon.KitchenSet.load(kset)
    outs = work / "out"
    shutil.rmtree(outs, ignore_errors=True)
    want: pa.Table | None = None

    sizes = [int(x) for x in args.sweep.split(",") if x]
    c1 = LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None)
    c2 = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    client1, client2 = Client(c1), Client(c2)
    client1.wait_for_workers(1)
    client2.wait_for_workers(2)
    configs: dict[str, dict[str, Any]] = {
        "local-1": {"chunk_size": chunk, "threads": 1},
        "local-2": {"chunk_size": chunk, "threads": 2},
        "dask-1": {"chunk_size": chunk, "engine": "dask", "client": client1},
        "dask-2": {"chunk_size": chunk, "engine": "dask", "client": client2},
    }
    for c in sizes:
        configs[f"dask-1-{c}"] = {"chunk_size": c, "engine": "dask", "client": client1}
        configs[f"local-1-{c}"] = {"chunk_size": c, "threads": 1}
    best = dict.fromkeys(configs, float("inf"))
    # Round 0 is not timed (page cache, prepared-kitchen cache, worker start-up); then every
    # configuration once per round, so that the machine's load falls on all of them alike.
    for r in range(args.repeat + 1):
        for tag, kw in configs.items():
            out = outs / tag
            t = time.perf_counter()
            foon.batch(queries, foon=f, kitchens=ks, out=out, resume=False, **kw)
            s = time.perf_counter() - t
            got = pq.read_table(out)
            if want is None:
                want = got
            assert got.equals(want), tag
            if r:
                best[tag] = min(best[tag], s)
            print(f"[round {r}, {tag}: {fmt_s(s)}]", file=sys.stderr, flush=True)
    local = {1: best["local-1"], 2: best["local-2"]}
    dask = {1: best["dask-1"], 2: best["dask-2"]}
    sweep = {c: (best[f"dask-1-{c}"], best[f"local-1-{c}"]) for c in sizes}
    n = 2000
    t0 = time.perf_counter()
    client2.gather(client2.map(noop, range(n), pure=False))
    noop_rate = n / (time.perf_counter() - t0)
    for x in (client1, client2, c1, c2):
        x.close()
    # The client's share: writing and hashing one partition of results.
    part = want.slice(0, min(chunk, want.num_rows)) if want is not None else None
    assert part is not None
    tmp = work / "write-probe.parquet"
    t0 = time.perf_counter()
    for _ in range(3):
        pq.write_table(part, tmp)
        from foon._batch import _sha256

        _sha256(str(tmp))
    write_per_query = (time.perf_counter() - t0) / 3 / part.num_rows
    tmp.unlink()
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

    units = parse_size(args.units)
    print(
        f"\n### foon.batch: {fmt_n(count)} queries, {fmt_n(units)} units "
        f"({f.object_count:,} objects), {args.kitchens:,} kitchens (base minus 10 items "
        f"each), methods {args.methods}, chunks of {chunk:,}; best of {args.repeat}\n"
    )
    print("| engine | time | queries/s | ratio |")
    print("|---|---|---|---|")
    print(f"| local, 1 thread | {fmt_s(local[1])} | {count / local[1]:,.0f} | 1.00x |")
    print(f"| local, 2 threads | {fmt_s(local[2])} | {count / local[2]:,.0f} | "
          f"{local[1] / local[2]:.2f}x of local 1 |")  # fmt: skip
    print(f"| Dask, 1 worker process | {fmt_s(dask[1])} | {count / dask[1]:,.0f} | "
          f"{local[1] / dask[1]:.2f}x of local 1 |")  # fmt: skip
    print(f"| Dask, 2 worker processes | {fmt_s(dask[2])} | {count / dask[2]:,.0f} | "
          f"{dask[1] / dask[2]:.2f}x of Dask 1 |")  # fmt: skip
    print("\n#### Dask per-task overhead against chunk size (1 worker against local 1 thread)\n")
    print("| chunk | tasks | Dask 1 worker | local 1 thread | overhead per task | overhead "
          "share |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for c, (d, lo) in sweep.items():
        tasks = -(-count // c)
        print(f"| {c:,} | {tasks:,} | {fmt_s(d)} | {fmt_s(lo)} | "
              f"{(d - lo) / tasks * 1000:+.1f} ms | {(d - lo) / lo * 100:+.1f}% |")  # fmt: skip
    per_worker = count / dask[2] / 2
    sched_q = noop_rate * chunk
    client_q = 1 / write_per_query
    print("\n#### Projection to N machines (a projection, not a measurement)\n")
    print(
        f"Method: each machine runs W single-threaded workers (W = its cores) at the "
        f"per-worker throughput measured here with 2 workers ({per_worker:,.0f} queries/s, "
        f"Dask 2 workers / 2); the batch's throughput is the least of N * W * that, of the "
        f"scheduler's bound (no-op tasks through the 2-worker cluster, {noop_rate:,.0f} "
        f"tasks/s, times {chunk:,} queries per task = {sched_q:,.0f} queries/s) and of the "
        f"client's bound (it alone writes and hashes the partitions: "
        f"{write_per_query * 1e6:.2f} us per query = {client_q:,.0f} queries/s). Network "
        f"transfer of chunks and answers and the reading of the query file are not modelled."
    )
    print("\n| machines x workers | projected queries/s | bound | 1M queries in |")
    print("|---|---|---|---|")
    for n, w in ((1, 2), (4, 8), (16, 32), (64, 32), (256, 32)):
        q = min(n * w * per_worker, sched_q, client_q)
        bound = ("workers" if q == n * w * per_worker
                 else "scheduler" if q == sched_q else "client")  # fmt: skip
        print(f"| {n} x {w} | {q:,.0f} | {bound} | {fmt_s(1_000_000 / q)} |")
    print(f"\nPeak resident memory of the client process (the mapped index included): "
          f"{peak:,.0f} MB.")  # fmt: skip
    print(
        f"\nCommand: `python benchmarks/batch.py --units {args.units} --queries {args.queries} "
        f"--kitchens {args.kitchens} --chunk {chunk} --sweep {args.sweep} --methods "
        f"{args.methods} --repeat {args.repeat}` ({os.cpu_count()} cores)"
    )


if __name__ == "__main__":
    main()
