"""Scale: synthetic merged FOONs from 10k to 10M units, from text and from a `.foonidx`.

    python benchmarks/scale.py [--sizes 10k,100k,1M,10M] [--goals 200] [--work DIR] [--keep]

Build the wheel in release mode first (`maturin develop --release`, or install the wheel that
`scripts/test` builds). For each size, `foon synth` writes the FOON, its kitchen and goals
(seed 1); then each measurement runs in a fresh Python process, so that its peak memory is its
own:

- **text**: `foon.load` of the text (parse + index), wall time and peak RSS;
- **index**: `foon index` of the text, the `.foonidx` size;
- **open**: `foon.load` of the `.foonidx` (a memory map), wall time and the anonymous memory it
  adds (RssAnon: the mapped file itself is not counted);
- **plan** (from the mapped index): planner preparation with the kitchen, then for every method
  the first batch over the goals (which includes what the method computes once per kitchen)
  and a second batch (plans per second, 1 and 2 threads), the mean size of the trees returned (solved or not: a course plan returns the units it chose), and a goal that
  cannot be made (a sparse kitchen: every second raw item dropped) with its explanation;
- the growth exponent of time and memory between consecutive sizes (log ratio of the figures
  over log ratio of the sizes: 1 is linear).

Prints Markdown.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

SEED = 1
HERE = Path(__file__).resolve().parent


def parse_size(s: str) -> int:
    s = s.strip().lower().replace("_", "")
    mult = {"k": 10**3, "m": 10**6}.get(s[-1:], 1)
    return int(float(s[:-1]) * mult) if mult > 1 else int(s)


def fmt_n(n: int) -> str:
    for unit, div in (("M", 10**6), ("k", 10**3)):
        if n >= div and n % div == 0:
            return f"{n // div}{unit}"
    return f"{n:,}"


def fmt_s(s: float) -> str:
    if s < 1e-3:
        return f"{s * 1e6:.0f} µs"
    return f"{s * 1000:.1f} ms" if s < 1 else f"{s:.2f} s"


def fmt_mb(b: float) -> str:
    return f"{b / 2**20:,.0f} MB"


# --- measurements, each in its own process ----------------------------------------------------


def _status(field: str) -> int:
    """A field of /proc/self/status in bytes (0 where there is none)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith(field + ":"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def _peak() -> int:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def worker(task: dict[str, Any]) -> dict[str, Any]:
    import foon

    kind = task["kind"]
    if kind == "text":
        base = _peak()
        t = time.perf_counter()
        f = foon.load(task["path"])
        dt = time.perf_counter() - t
        return {"seconds": dt, "peak": _peak(), "base": base, "units": f.fu_count}
    if kind == "open":
        anon = _status("RssAnon")
        t = time.perf_counter()
        f = foon.load(task["path"])
        dt = time.perf_counter() - t
        return {"seconds": dt, "anon": _status("RssAnon") - anon, "units": f.fu_count}
    if kind == "plan":
        return plan_worker(task)
    if kind == "course":
        return course_worker(task)
    raise ValueError(kind)


# Every method in its default (sound) form, and the course-compatible greedy methods (`bfs`
# exists only in the course form).
METHODS: list[tuple[str, str | None]] = [
    *((m, None) for m in ("bfs", "ids", "greedy-success", "greedy-inputs")),
    ("greedy-success", "course"),
    ("greedy-inputs", "course"),
    *((m, None) for m in ("optimal-success", "optimal-units", "optimal-inputs")),
]


def method_name(method: str, compat: str | None) -> str:
    return method + (" (course)" if compat == "course" else "")


def bench_methods(planner: Any, goals: list[Any], repeat: int) -> dict[str, Any]:
    """First batch, then plans per second (1 and 2 threads) and mean tree size per method."""
    import foon

    out: dict[str, Any] = {}
    for method, compat in METHODS:
        name = method_name(method, compat)
        t = time.perf_counter()
        try:
            trees = planner.plan_many(goals, method, compat=compat, threads=1)
        except foon.FoonError as e:
            out[name] = {"error": str(e)}
            continue
        first = time.perf_counter() - t
        rows: dict[str, Any] = {"first": first}
        for threads in (1, 2):
            best = math.inf
            for _ in range(repeat):
                t = time.perf_counter()
                planner.plan_many(goals, method, compat=compat, threads=threads)
                best = min(best, time.perf_counter() - t)
            rows[f"pps{threads}"] = len(goals) / best
        solved = [tr for tr in trees if tr.solved]
        rows["solved"] = len(solved)
        # Every tree a plan returns counts, solved or not: a course plan that does not reach
        # the kitchen still returns (and pays for) the units its loop chose.
        rows["mean_units"] = sum(len(tr) for tr in trees) / max(len(trees), 1)
        out[name] = rows
    return out


def prepare_everything(
    f: Any, items: list[Any], goals: list[Any], motions: Any, utensils: Any = None
) -> dict[str, float]:
    """Preparation with everything a planner computes once per kitchen: the planner, ranks
    and the `ids` choice, each optimal objective, and the shopping costs of explanations. The
    kitchen is `items` without its first raw item (an object without a producer), so that this
    item is a goal that cannot be made (its explanation computes the shopping costs)."""
    import foon

    raw = 0
    for i, item in enumerate(items):
        o = f.find(item)
        if o is not None and not f.producers(o):
            raw = i
            break
    kitchen = foon.Kitchen(items[:raw] + items[raw + 1 :])
    parts: dict[str, float] = {}
    t = time.perf_counter()
    planner = f.planner(kitchen, motions=motions, utensils=utensils)
    parts["prepare"] = time.perf_counter() - t
    t = time.perf_counter()
    for g in goals:
        if planner.plan(g, "ids").solved:
            break
    parts["ranks + ids"] = time.perf_counter() - t
    for m in ("optimal-success", "optimal-units", "optimal-inputs"):
        t = time.perf_counter()
        planner.plan(g, m)
        parts[m] = time.perf_counter() - t
    t = time.perf_counter()
    tr = planner.plan(items[raw], "optimal-units")
    tr.explanation()
    parts["shopping"] = time.perf_counter() - t
    parts["total"] = sum(parts.values())
    return parts


def plan_worker(task: dict[str, Any]) -> dict[str, Any]:
    import foon

    f = foon.load(task["path"])
    kitchen = foon.Kitchen.load(task["kitchen"])
    goals = foon.load_goals(task["goals"])
    motions = foon.synth_motions()
    t = time.perf_counter()
    planner = f.planner(kitchen, motions=motions)
    prep = time.perf_counter() - t
    out: dict[str, Any] = {"prepare": prep}
    out["methods"] = bench_methods(planner, goals, task["repeat"])
    del planner
    items = list(kitchen)
    out["everything"] = prepare_everything(f, items, goals, motions)
    # The failure path: a sparse kitchen, a goal of it that cannot be made, its explanation.
    sparse = foon.Kitchen(items[::2])
    t = time.perf_counter()
    sp = f.planner(sparse, motions=motions)
    out["sparse_prepare"] = time.perf_counter() - t
    failing = None
    for g in goals:
        tr = sp.plan(g, "optimal-units")
        if not tr.solved:
            failing = g
            break
    if failing is not None:
        best = math.inf
        for _ in range(task["repeat"]):
            t = time.perf_counter()
            tr = sp.plan(failing, "optimal-units")
            tr.explanation()
            best = min(best, time.perf_counter() - t)
        out["failure"] = best
    return out


def course_worker(task: dict[str, Any]) -> dict[str, Any]:
    """The course FOON with the course kitchen, motion rates, utensils and its 25 goals."""
    import foon

    data = Path(task["data"])
    f = foon.load(data / "FOON.txt")
    kitchen = foon.Kitchen.load(data / "kitchen.json")
    motions = foon.MotionRates.load(data / "motion.txt")
    utensils = foon.load_utensils(data / "utensils.txt")
    goals = [
        foon.Object.from_dict(d) for d in json.loads((data / "goal_nodes_25.json").read_text())
    ]
    t = time.perf_counter()
    planner = f.planner(kitchen, motions=motions, utensils=utensils)
    out: dict[str, Any] = {"n": f.fu_count, "prepare": time.perf_counter() - t}
    out["methods"] = bench_methods(planner, goals, task["repeat"])
    out["everything"] = prepare_everything(f, list(kitchen), goals, motions, utensils)
    return out


def run_worker(task: dict[str, Any]) -> dict[str, Any]:
    p = subprocess.run(
        [sys.executable, __file__, "--worker", json.dumps(task)],
        capture_output=True,
        text=True,
        check=False,
    )
    if p.returncode != 0:
        raise SystemExit(f"worker {task['kind']} failed:\n{p.stderr}")
    result: dict[str, Any] = json.loads(p.stdout.strip().splitlines()[-1])
    return result


# --- the run ---------------------------------------------------------------------------------


def foon_cmd(*args: str) -> None:
    subprocess.run([sys.executable, "-m", "foon", *args], check=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="10k,100k,1M,10M")
    ap.add_argument("--goals", type=int, default=200, help="goals per size")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--work", help="folder for the generated files (default: a temporary one)")
    ap.add_argument("--keep", action="store_true", help="keep the generated files")
    ap.add_argument(
        "--data",
        default=str(HERE.parent.parent / "shared" / "data" / "foon"),
        help="the course data (FOON.txt, kitchen.json, motion.txt, utensils.txt, goals)",
    )
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        print(json.dumps(worker(json.loads(args.worker))))
        return
    sizes = [parse_size(s) for s in args.sizes.split(",")]
    work = Path(args.work or tempfile.mkdtemp(prefix="foon-scale-"))
    work.mkdir(parents=True, exist_ok=True)
    rows: list[dict[str, Any]] = []
    course = run_worker({"kind": "course", "data": args.data, "repeat": args.repeat})
    print("[course done]", file=sys.stderr, flush=True)
    try:
        for n in sizes:
            name = fmt_n(n)
            text, idx = work / f"synth-{name}.txt", work / f"synth-{name}.foonidx"
            kitchen, goals = work / f"synth-{name}-kitchen.json", work / f"synth-{name}-goals.json"
            if not text.exists():
                foon_cmd(
                    "synth",
                    "--units",
                    str(n),
                    "--seed",
                    str(SEED),
                    "-o",
                    str(text),
                    "--kitchen",
                    str(kitchen),
                    "--goals",
                    str(goals),
                    "--goal-count",
                    str(args.goals),
                    "-q",
                )
            r: dict[str, Any] = {"n": n, "bytes": text.stat().st_size}
            # 10M units from text need several GB: measured once, like every size.
            r["text"] = run_worker({"kind": "text", "path": str(text)})
            t = time.perf_counter()
            foon_cmd("index", str(text), "-o", str(idx), "-q")
            r["index_seconds"] = time.perf_counter() - t
            r["index_bytes"] = idx.stat().st_size
            opens = [run_worker({"kind": "open", "path": str(idx)}) for _ in range(args.repeat)]
            r["open"] = min(opens, key=lambda o: o["seconds"])
            r["plan"] = run_worker(
                {
                    "kind": "plan",
                    "path": str(idx),
                    "kitchen": str(kitchen),
                    "goals": str(goals),
                    "repeat": args.repeat,
                }
            )
            rows.append(r)
            print(f"[{name} done]", file=sys.stderr, flush=True)
            if not args.keep:
                text.unlink()
    finally:
        if not args.keep and not args.work:
            shutil.rmtree(work, ignore_errors=True)
    report(rows, course)


def per_unit(x: dict[str, Any]) -> float:
    """µs per tree unit on one thread (NaN for a method that failed)."""
    if "pps1" not in x:
        return math.nan
    return float(1e6 / (x["pps1"] * max(x["mean_units"], 1)))


def report(rows: list[dict[str, Any]], course: dict[str, Any]) -> None:
    print("\n### Loading: text against the `.foonidx`\n")
    print(
        "| units | text | parse + index | peak RSS | `.foonidx` | `foon index` | open | memory added by open |"
    )
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(
            f"| {fmt_n(r['n'])} | {fmt_mb(r['bytes'])} | {fmt_s(r['text']['seconds'])} "
            f"| {fmt_mb(r['text']['peak'])} | {fmt_mb(r['index_bytes'])} "
            f"| {fmt_s(r['index_seconds'])} | {fmt_s(r['open']['seconds'])} "
            f"| {fmt_mb(r['open']['anon'])} |"
        )
    if len(rows) > 1:
        print(
            "\nGrowth exponents between consecutive sizes (1 = linear; n log n from 10k to 10M "
            "is about 1.1):\n"
        )
        print("| sizes | parse + index time | peak RSS | open time |")
        print("|---|---:|---:|---:|")
        for a, b in itertools.pairwise(rows):
            k = math.log(b["n"] / a["n"])

            def e(x: float, y: float, k: float = k) -> float:
                return math.log(max(y, 1e-9) / max(x, 1e-9)) / k

            print(
                f"| {fmt_n(a['n'])} → {fmt_n(b['n'])} "
                f"| {e(a['text']['seconds'], b['text']['seconds']):.2f} "
                f"| {e(a['text']['peak'], b['text']['peak']):.2f} "
                f"| {e(a['open']['seconds'], b['open']['seconds']):.2f} |"
            )
    print("\n### Planning from the mapped index (plans per second; goals spread over the FOON)\n")
    print(
        "| units | preparation | method | first batch | plans/s, 1 thread | 2 threads | mean units returned | µs per tree unit |"
    )
    print("|---:|---:|---|---:|---:|---:|---:|---:|")
    table = [("course", course), *((fmt_n(r["n"]), r["plan"]) for r in rows)]
    for label, p in table:
        for m, x in p["methods"].items():
            if "error" in x:
                print(f"| {label} | {fmt_s(p['prepare'])} | {m} | error: {x['error']} | | | | |")
                continue
            print(
                f"| {label} | {fmt_s(p['prepare'])} | {m} | {fmt_s(x['first'])} "
                f"| {x['pps1']:,.0f} | {x['pps2']:,.0f} | {x['mean_units']:.1f} "
                f"| {per_unit(x):.2f} |"
            )
    print("\n### µs per tree unit (1 thread) against the course FOON (its kitchen and 25 goals)\n")
    sizes = [fmt_n(r["n"]) for r in rows]
    print("| method | course | " + " | ".join(sizes) + f" | {sizes[-1]} / course |")
    print("|---|---:|" + "---:|" * (len(sizes) + 1))
    for m, x in course["methods"].items():
        base = per_unit(x)
        cells = [per_unit(r["plan"]["methods"].get(m, {})) for r in rows]
        print(
            f"| {m} | {base:.2f} | "
            + " | ".join(f"{c:.2f}" for c in cells)
            + f" | {cells[-1] / base:.2f} |"
        )
    print("\n### Preparation, everything (the planner and all it computes once per kitchen)\n")
    parts = list(course["everything"])
    print("| FOON | " + " | ".join(parts) + " |")
    print("|---|" + "---:|" * len(parts))
    for label, p in table:
        ev = p["everything"]
        print(f"| {label} | " + " | ".join(fmt_s(ev[k]) for k in parts) + " |")
    print("\n### The failure path (sparse kitchen: every second raw item dropped)\n")
    print("| units | preparing the sparse kitchen | failing goal planned and explained |")
    print("|---:|---:|---:|")
    for r in rows:
        p = r["plan"]
        fail = fmt_s(p["failure"]) if "failure" in p else "(every goal derivable)"
        print(f"| {fmt_n(r['n'])} | {fmt_s(p['sparse_prepare'])} | {fail} |")
    print(f"\n(machine: {os.cpu_count()} cores; Python {sys.version.split()[0]})")


if __name__ == "__main__":
    main()
