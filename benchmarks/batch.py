"""`foon.batch` end to end: files in, Parquet partitions out, locally and on Dask.

    python benchmarks/batch.py [--units 20k] [--queries 100k] [--kitchens 100] [--goals 200]
                               [--chunk 20000] [--sweep 1000,5000,20000] [--methods ids]
                               [--repeat 3] [--local-only] [--work DIR]

The issue's run: `--units 1M --queries 1M --kitchens 1000`. Build the wheel in release mode
first (`maturin build --release`, installed in its own venv with `pyarrow` and
`dask[distributed]`).

`foon synth` writes a FOON, its kitchen and goals (seed 1, cached in the work folder), and
`foon index` its `.foonidx`. The kitchens are that kitchen with 10 random items removed each
(a base-plus-deltas kitchen-set file, one seed per kitchen); the queries pick a kitchen, a
goal (a JSON object) and a method at random (seed 2) and are written as Parquet, sorted by
kitchen (so that a chunk touches few kitchens). Each configuration answers the whole file
with `foon.batch` into its own folder (`resume=False`), best of `--repeat` rounds, the
configurations taking turns (one run of each per round, so that the machine's load falls on
all alike). Every run starts cold, as a new `foon batch` does: a local run in a fresh
process (the index and kitchen set loaded before the clock starts), a Dask run after
a new local cluster (new worker processes), so that no run finds kitchens prepared by an
earlier one in the process's cache. The time is the whole call (reading and checking the
file, planning, writing and hashing the partitions, recording the manifest). Every run gives
the same partitions (checked).

- local, 1 thread and 2 threads (`--chunk`);
- Dask, a local cluster (`foon._dask.local_cluster`: the settings of the cluster that
  `foon batch --engine dask` starts) of 1 and of 2 single-threaded worker processes
  (`--chunk`);
- CPU time of each run: the client's process (for Dask it hosts the scheduler too) and the
  workers' processes, from `getrusage`; on a machine shared with other work the CPU times
  are steadier than the wall times;
- the per-task overhead of Dask against the chunk size (`--sweep`): with 1 worker, the time
  over local 1 thread at the same chunk size, per task and as a share of local, in wall time
  and in CPU time (all processes);
- the bounds for a projection to N machines: no-op tasks per second through the 2-worker
  cluster (the scheduler), and the client process's CPU time per query in the 2-worker run
  (it reads and ships the queries and records the manifest; the workers write the
  partitions), and the projection (the method is printed with it).

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


def spin(_: int) -> float:
    """A fixed pure-CPU loop (no memory traffic), about a second."""
    x = 0
    for i in range(10_000_000):
        x ^= i
    return float(x)


def spin_wall(processes: int) -> float:
    """The wall time of ``processes`` processes each running :func:`spin` at once: the
    control for how much of the cores this run gets (on a shared machine, a scheduler that
    shares the cores between sessions may give 2 processes no more than 1)."""
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(processes) as ex:
        list(ex.map(noop, range(processes)))  # started before the clock
        t0 = time.perf_counter()
        list(ex.map(spin, range(processes)))
        return time.perf_counter() - t0


def cpu_seconds() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def warm() -> None:
    """What a worker imports to plan and write (a local run imports it before its clock)."""
    import foon._arrow
    import foon._batch  # noqa: F401
    import pyarrow.parquet  # noqa: F401


def one_local(argv: list[str]) -> None:
    """`--one-local INDEX KITCHENS QUERIES OUT THREADS CHUNK`: one local run in this fresh
    process; prints its wall and CPU seconds as JSON."""
    index, kset, queries, out, threads, chunk = argv
    f = foon.load(index)
    ks = foon.KitchenSet.load(kset)
    c0, t0 = cpu_seconds(), time.perf_counter()
    foon.batch(queries, foon=f, kitchens=ks, out=out, resume=False, threads=int(threads),
               chunk_size=int(chunk))  # fmt: skip
    print(json.dumps({"wall": time.perf_counter() - t0, "client": cpu_seconds() - c0}))


def run_local(index: Path, kset: Path, queries: Path, out: Path, threads: int, chunk: int
              ) -> dict[str, float]:  # fmt: skip
    res = subprocess.run(
        [sys.executable, __file__, "--one-local", str(index), str(kset), str(queries),
         str(out), str(threads), str(chunk)],
        check=True, capture_output=True, text=True,
    )  # fmt: skip
    r: dict[str, float] = json.loads(res.stdout.strip().splitlines()[-1])
    r["workers"] = 0.0
    r["busiest"] = r["client"]
    return r


def run_dask(f: Any, ks: Any, queries: Path, out: Path, workers: int, chunk: int
             ) -> dict[str, float]:  # fmt: skip
    from distributed import Client
    from foon._dask import local_cluster

    with local_cluster(workers) as cluster, Client(cluster) as client:
        client.wait_for_workers(workers)
        client.run(warm)  # the imports, before the clock as for a local run
        w0 = client.run(cpu_seconds)
        c0, t0 = cpu_seconds(), time.perf_counter()
        foon.batch(queries, foon=f, kitchens=ks, out=out, resume=False, engine="dask",
                   client=client, chunk_size=chunk)  # fmt: skip
        wall, cpu = time.perf_counter() - t0, cpu_seconds() - c0
        w1 = client.run(cpu_seconds)
    per = [w1[a] - w0.get(a, 0.0) for a in w1]
    return {"wall": wall, "client": cpu, "workers": sum(per), "busiest": max(per)}


def main() -> None:
    if sys.argv[1:2] == ["--one-local"]:
        one_local(sys.argv[2:])
        return
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--units", default="20k")
    ap.add_argument("--queries", default="100k")
    ap.add_argument("--kitchens", type=int, default=100)
    ap.add_argument("--goals", type=int, default=200)
    ap.add_argument("--chunk", type=int, default=None, help="default: foon's default")
    ap.add_argument("--sweep", default="1000,5000,20000")
    ap.add_argument("--methods", default="ids")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--work")
    ap.add_argument("--local-only", action="store_true",
                    help="only local 1 and 2 threads (no Dask, no sweep): the table's first "
                         "two rows and the machine check")  # fmt: skip
    args = ap.parse_args()
    from distributed import Client
    from foon._batch import DEFAULT_CHUNK_SIZE
    from foon._dask import local_cluster

    chunk = args.chunk or DEFAULT_CHUNK_SIZE
    work = Path(args.work or tempfile.mkdtemp(prefix="foon-batch-"))
    work.mkdir(parents=True, exist_ok=True)
    index, kset, queries, count = prepare(args, work)
    f = foon.load(index)
    ks = foon.KitchenSet.load(kset)
    outs = work / "out"
    shutil.rmtree(outs, ignore_errors=True)
    outs.mkdir()
    want: pa.Table | None = None

    sizes = [int(x) for x in args.sweep.split(",") if x]
    # (kind, workers or threads, chunk): the main four, then the sweep's pairs.
    configs: dict[str, tuple[str, int, int]] = {
        "local-1": ("local", 1, chunk),
        "local-2": ("local", 2, chunk),
        "dask-1": ("dask", 1, chunk),
        "dask-2": ("dask", 2, chunk),
    }
    if args.local_only:
        configs = {t: configs[t] for t in ("local-1", "local-2")}
        sizes = []
    for c in sizes:
        if c != chunk:
            configs[f"dask-1-{c}"] = ("dask", 1, c)
            configs[f"local-1-{c}"] = ("local", 1, c)
    runs: dict[str, list[dict[str, float]]] = {tag: [] for tag in configs}
    spins: dict[int, list[float]] = {1: [], 2: []}
    for r in range(args.repeat):
        for p in (1, 2):
            spins[p].append(spin_wall(p))
        for tag, (kind, n, c) in configs.items():
            out = outs / tag
            if kind == "local":
                m = run_local(index, kset, queries, out, n, c)
            else:
                m = run_dask(f, ks, queries, out, n, c)
            got = pq.read_table(out)
            if want is None:
                want = got
            assert got.equals(want), tag
            runs[tag].append(m)
            print(f"[round {r + 1}, {tag}: {fmt_s(m['wall'])}, cpu client {m['client']:.2f} s, "
                  f"workers {m['workers']:.2f} s]", file=sys.stderr, flush=True)  # fmt: skip

    def best(tag: str) -> dict[str, float]:
        return min(runs[tag], key=lambda m: m["wall"])

    def cpu_best(tag: str) -> float:
        return min(m["client"] + m["workers"] for m in runs[tag])

    def spread(tag: str) -> str:
        walls = [m["wall"] for m in runs[tag]]
        return f"{fmt_s(min(walls))} to {fmt_s(max(walls))}"

    if args.local_only:
        l1, l2 = best("local-1"), best("local-2")
        print(f"\n### foon.batch, local: {fmt_n(count)} queries, {args.units} units, "
              f"{args.kitchens:,} kitchens, methods {args.methods}, chunks of {chunk:,}; "
              f"cold runs, best of {args.repeat}\n")  # fmt: skip
        print("| engine | time (best) | spread | queries/s | ratio | CPU |")
        print("|---|---|---|---|---|---|")
        for tag, name, m in (
            ("local-1", "local, 1 thread", l1),
            ("local-2", "local, 2 threads", l2),
        ):
            ratio = "1.00x" if tag == "local-1" else f"{l1['wall'] / l2['wall']:.2f}x of 1 thread"
            print(f"| {name} | {fmt_s(m['wall'])} | {spread(tag)} | {count / m['wall']:,.0f} | "
                  f"{ratio} | {fmt_s(m['client'])} |")  # fmt: skip
        pairs = [
            a["wall"] / b["wall"] for a, b in zip(runs["local-1"], runs["local-2"], strict=True)
        ]
        checks = [2 * a / b for a, b in zip(spins[1], spins[2], strict=True)]
        print(f"\nPer round, 1 thread over 2 threads: {', '.join(f'{x:.2f}x' for x in pairs)}; "
              f"the machine check (a pure-CPU loop in 2 processes against 1) in the same "
              f"rounds: {', '.join(f'{x:.2f}x' for x in checks)}.")  # fmt: skip
        print(f"\nCommand: `python benchmarks/batch.py --units {args.units} --queries "
              f"{args.queries} --kitchens {args.kitchens} --chunk {chunk} --methods "
              f"{args.methods} --repeat {args.repeat} --local-only` ({os.cpu_count()} cores)")  # fmt: skip
        return
    n_noop = 2000
    with local_cluster(2) as c2, Client(c2) as client2:
        client2.wait_for_workers(2)
        t0 = time.perf_counter()
        client2.gather(client2.map(noop, range(n_noop), pure=False))
        noop_rate = n_noop / (time.perf_counter() - t0)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

    units = parse_size(args.units)
    print(
        f"\n### foon.batch: {fmt_n(count)} queries, {fmt_n(units)} units "
        f"({f.object_count:,} objects), {args.kitchens:,} kitchens (base minus 10 items "
        f"each), methods {args.methods}, chunks of {chunk:,} ({-(-count // chunk):,} "
        f"partitions); cold runs, best of {args.repeat}\n"
    )
    print("| engine | time (best) | spread | queries/s | ratio | CPU: client (+ scheduler) | "
          "CPU: workers | CPU per query |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|")
    base = {"local-1": "", "local-2": "local-1", "dask-1": "local-1", "dask-2": "dask-1"}
    names = {"local-1": "local, 1 thread", "local-2": "local, 2 threads",
             "dask-1": "Dask, 1 worker process", "dask-2": "Dask, 2 worker processes"}  # fmt: skip
    for tag, name in names.items():
        m = best(tag)
        ratio = "1.00x" if not base[tag] else (
            f"{best(base[tag])['wall'] / m['wall']:.2f}x of {names[base[tag]]}")  # fmt: skip
        cpu = min(runs[tag], key=lambda m: m["client"] + m["workers"])
        wcpu = fmt_s(cpu["workers"]) if cpu["workers"] else "-"
        print(f"| {name} | {fmt_s(m['wall'])} | {spread(tag)} | {count / m['wall']:,.0f} | "
              f"{ratio} | {fmt_s(cpu['client'])} | {wcpu} | "
              f"{(cpu['client'] + cpu['workers']) / count * 1e6:.1f} µs |")  # fmt: skip
    print("\nCPU columns: the run with the least total CPU time.")

    def bound(tag: str) -> float:
        # The least wall time on free cores: the busiest process's CPU time, and half of all.
        return min(max(m["busiest"], (m["client"] + m["workers"]) / 2) for m in runs[tag])

    print(
        f"\nA model from the CPU times, for two free cores (a run takes at least its busiest "
        f"process's CPU time and half of all its processes' CPU time): Dask 2 workers "
        f"{bound('dask-1') / bound('dask-2'):.2f}x of Dask 1, local 2 threads "
        f"{bound('local-1') / min(m['client'] / 2 for m in runs['local-2']):.2f}x of local 1 "
        f"(an estimate, not a measurement)."
    )
    ratios = sorted(2 * a / b for a, b in zip(spins[1], spins[2], strict=True))
    print(
        f"\nMachine check (once per round): the throughput of a pure-CPU loop in 2 "
        f"processes against 1 was {ratios[-1]:.2f}x at best "
        f"({', '.join(f'{x:.2f}x' for x in ratios)}; 2.00x on two free cores). Two workers "
        f"cannot beat one by more than the machine gives two processes."
    )
    print("\n#### Dask per-task overhead against chunk size (1 worker against local 1 thread)\n")
    print("| chunk | tasks | Dask 1 worker | local 1 thread | overhead per task | overhead "
          "share (wall) | overhead share (CPU, all processes) |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    for c in sorted({*sizes, chunk}):
        dt, lt = ("dask-1", "local-1") if c == chunk else (f"dask-1-{c}", f"local-1-{c}")
        d, lo = best(dt)["wall"], best(lt)["wall"]
        dc, lc = cpu_best(dt), cpu_best(lt)
        tasks = -(-count // c)
        print(f"| {c:,} | {tasks:,} | {fmt_s(d)} | {fmt_s(lo)} | "
              f"{(d - lo) / tasks * 1000:+.1f} ms | {(d - lo) / lo * 100:+.1f}% | "
              f"{(dc - lc) / lc * 100:+.1f}% |")  # fmt: skip
    d2 = best("dask-2")
    per_worker = count / d2["wall"] / 2
    sched_q = noop_rate * chunk
    client_cpu = min(m["client"] for m in runs["dask-2"])
    client_q = count / client_cpu
    print("\n#### Projection to N machines (a projection, not a measurement)\n")
    print(
        f"Method: each machine runs W single-threaded workers (W = its cores) at the "
        f"per-worker throughput measured here with 2 workers ({per_worker:,.0f} queries/s, "
        f"Dask 2 workers / 2); the batch's throughput is the least of N * W * that, of the "
        f"scheduler's bound (no-op tasks through the 2-worker cluster, {noop_rate:,.0f} "
        f"tasks/s, times {chunk:,} queries per task = {sched_q:,.0f} queries/s) and of the "
        f"client's bound (its process's CPU time in the 2-worker run, scheduler included: "
        f"{client_cpu / count * 1e6:.2f} µs per query = {client_q:,.0f} queries/s; it "
        f"reads, checks and ships the queries and records the manifest, the workers write "
        f"the partitions). Network transfer of chunks (about 40 bytes per query here) and "
        f"the shared file system's throughput are not modelled."
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
