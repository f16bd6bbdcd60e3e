"""foon benchmarks: the Rust core against pure-Python baselines, side by side in one run.

    python benchmarks/run.py [--data ../shared/data/foon] [--repeat 5] [--only SECTION]

Prints Markdown tables (ratios are what matter: machines are noisy). Build the wheel in
release mode first (scripts/test does; or `maturin develop --release`)."""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests"))

import course_parser
import foon
import foon_reference as ref
from workloads import (
    can_measure_memory,
    chain_text,
    expo_units,
    ladder_kitchen,
    ladder_text,
    load_memory,
    units_text,
)


def timeit(fn: Callable[[], object], repeat: int) -> float:
    """Median wall time of `repeat` runs (one warm-up run first)."""
    fn()
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def fmt(s: float) -> str:
    return f"{s * 1000:.2f} ms" if s < 1 else f"{s:.2f} s"


def bench_parse(data: Path, repeat: int) -> None:
    path = str(data / "FOON.txt")
    text = (data / "FOON.txt").read_text(encoding="utf-8")
    rust = timeit(lambda: foon.load(path), repeat)
    dict_py = timeit(lambda: ref.parse(text), max(1, repeat // 2))
    course_py = timeit(lambda: course_parser.parse(path), 1)
    kept, objs, prods = course_parser.parse(path)
    f = foon.load(path)
    assert (len(kept), len(objs), len(prods)) == (
        f.fu_count,
        f.object_count,
        f.stats()["produced_objects"],
    )
    print("\n### Parsing the course FOON.txt (2,376 units, 4,305 objects)\n")
    print("| parser | time | foon is faster by |")
    print("|---|---:|---:|")
    print(f"| foon (Rust core, from Python) | {fmt(rust)} | 1x |")
    print(
        f"| pure Python, course rules (list lookups, as the course scripts) | {fmt(course_py)} "
        f"| {course_py / rust:,.0f}x |"
    )
    print(
        f"| pure Python, dict lookups (tests/foon_reference.py) | {fmt(dict_py)} "
        f"| {dict_py / rust:,.0f}x |"
    )


def ref_plan_all(rf: ref.RefFoon, goals: list[foon.Object], *args: object) -> list[ref.RefResult]:
    """The reference's plans of `goals` (the remaining arguments as `ref.plan` takes them)."""
    return [ref.plan(rf, g.identity(), *args) for g in goals]


PLAN_CASES: list[tuple[str, str | None]] = [
    ("bfs", "course"),
    ("greedy-success", "course"),
    ("greedy-inputs", "course"),
    ("ids", None),
    ("greedy-success", None),
    ("greedy-inputs", None),
    ("optimal-success", None),
    ("optimal-units", None),
    ("optimal-inputs", None),
]


def bench_plan(data: Path, repeat: int) -> None:
    f = foon.load(data / "FOON.txt")
    kitchen = foon.Kitchen.load(data / "kitchen.json")
    motions = foon.MotionRates.load(data / "motion.txt")
    utensils = foon.load_utensils(data / "utensils.txt")
    goals = [
        foon.Object.from_dict(d) for d in json.loads((data / "goal_nodes_25.json").read_text())
    ]
    rf = ref.parse((data / "FOON.txt").read_text(encoding="utf-8"))
    rk = ref.read_kitchen_json((data / "kitchen.json").read_text())
    ru = ref.read_utensils((data / "utensils.txt").read_text())
    rr = ref.read_rates((data / "motion.txt").read_text())
    cases = PLAN_CASES
    n = len(goals)
    cores = os.cpu_count() or 1
    prep = timeit(lambda: f.planner(kitchen, motions=motions, utensils=utensils), repeat)
    planner = f.planner(kitchen, motions=motions, utensils=utensils)
    ids = [f.goal_id(g) for g in goals]
    print("\n### Planning the 25 course goals (course kitchen), plans per second\n")
    print(
        f"Preparing the planner (matching the 1,174-item kitchen, container rule, rates) takes "
        f"{fmt(prep)} once; `Foon.plan` does it on every call, `Foon.planner()` once.\n"
    )
    big = ids * 40  # the 25 goals 40 times over: 1,000 plans a call (nothing is cached)
    print(
        "Each call plans the 25 goals (`Planner.plan_many`); the batch column plans them 40 "
        "times over in one call (1,000 plans), which is how throughput is measured.\n"
    )
    print(
        f"| method | foon, 1 thread | foon, {cores} threads | foon, {cores} threads, batch "
        "of 1,000 | pure-Python reference | foon (1 thread) is faster by |"
    )
    print("|---|---:|---:|---:|---:|---:|")
    for method, compat in cases:
        one = timeit(partial(planner.plan_many, ids, method, compat=compat, threads=1), repeat)  # type: ignore[arg-type]
        allc = timeit(partial(planner.plan_many, ids, method, compat=compat), repeat)  # type: ignore[arg-type]
        batch = timeit(partial(planner.plan_many, big, method, compat=compat), max(1, repeat // 2))  # type: ignore[arg-type]
        name = f"{method}" + (" (course)" if compat else "")
        py = timeit(partial(ref_plan_all, rf, goals, rk, ru, rr, method, compat), 1)
        print(
            f"| {name} | {n / one:,.0f} | {n / allc:,.0f} | {len(big) / batch:,.0f} "
            f"| {n / py:,.0f} | {py / one:,.0f}x |"
        )


def bench_foon_size(data: Path, copies: int, repeat: int) -> None:
    """The 25 course goals planned on the course FOON and on a FOON made of it and copies-1
    renamed copies of it (labels suffixed, so the copies share nothing with the kitchen or the
    goals): the same trees, so any difference is what the size of the FOON costs a plan."""
    text = (data / "FOON.txt").read_text(encoding="utf-8")
    big = text + "".join(re.sub(r"^O\t(.*)$", rf"O\t\1 copy{k}", text, flags=re.MULTILINE)
                         for k in range(1, copies))  # fmt: skip
    small_foon, big_foon = foon.Foon.from_text(text), foon.Foon.from_text(big)
    kitchen = foon.Kitchen.load(data / "kitchen.json")
    motions = foon.MotionRates.load(data / "motion.txt")
    utensils = foon.load_utensils(data / "utensils.txt")
    goals = [
        foon.Object.from_dict(d) for d in json.loads((data / "goal_nodes_25.json").read_text())
    ]
    planners = []
    for f in (small_foon, big_foon):
        p = f.planner(kitchen, motions=motions, utensils=utensils)
        planners.append((p, [f.goal_id(g) for g in goals]))
    print(
        f"\n### Plans per second and the size of the FOON: the course FOON and {copies} copies "
        f"of it ({small_foon.object_count:,} and {big_foon.object_count:,} objects)\n"
    )
    print(f"| method | course FOON, 1 thread | {copies} copies, 1 thread | ratio |")
    print("|---|---:|---:|---:|")
    for method, compat in PLAN_CASES:
        trees = [
            [t.units for t in p.plan_many(ids, method, compat=compat)]  # type: ignore[arg-type]
            for p, ids in planners
        ]
        assert trees[0] == trees[1], method  # the same trees on both FOONs
        rates = [len(ids) / timeit(partial(p.plan_many, ids, method, compat=compat, threads=1),  # type: ignore[arg-type]
                                   repeat)
                 for p, ids in planners]  # fmt: skip
        name = f"{method}" + (" (course)" if compat else "")
        print(f"| {name} | {rates[0]:,.0f} | {rates[1]:,.0f} | {rates[0] / rates[1]:.2f}x |")


SCALE_METHODS = (("bfs", "course"), ("ids", None), ("greedy-inputs", None), ("optimal-units", None))


def bench_scale(n: int, small: int, repeat: int) -> None:
    """A generated chain of n units (each needs the previous one's output): parse it, then
    plan its last object, which needs all n units. The pure-Python reference is timed on the
    same text for parsing, and on a chain of `small` units for planning (its course loop, like
    the course code, tests list membership and is quadratic)."""
    text = chain_text(n)
    data = text.encode()
    parse = timeit(lambda: foon.Foon.from_text(data), max(1, repeat // 2))
    ref_parse = timeit(lambda: ref.parse(text), 1)
    f = foon.Foon.from_text(data)
    p = f.planner([foon.Object("item", ("s0",))], default_rate=0.5)
    goal = f.goal_id(foon.Object("item", (f"s{n}",)))
    print(f"\n### A chain of {n:,} units ({len(data) / 1e6:.1f} MB), planned to its end\n")
    print("| step | foon | pure-Python reference | foon is faster by |")
    print("|---|---:|---:|---:|")
    print(f"| parse | {fmt(parse)} | {fmt(ref_parse)} | {ref_parse / parse:,.0f}x |")
    for method, compat in SCALE_METHODS:
        t = timeit(partial(p.plan, goal, method, compat=compat), max(1, repeat // 2))  # type: ignore[arg-type]
        assert len(p.plan(goal, method, compat=compat).units) == n  # type: ignore[arg-type]
        print(f"| plan, {method}{' (course)' if compat else ''} | {fmt(t)} | | |")
    stext = chain_text(small)
    sf = foon.Foon.from_text(stext)
    sp = sf.planner([foon.Object("item", ("s0",))], default_rate=0.5)
    sgoal = sf.goal_id(foon.Object("item", (f"s{small}",)))
    rf = ref.parse(stext)
    kitchen = [("item", ("s0",), (), None)]
    rgoal = ("item", (f"s{small}",), (), None)
    print(f"\nPlanning a chain of {small:,} units, side by side:\n")
    print("| method | foon | pure-Python reference | foon is faster by |")
    print("|---|---:|---:|---:|")
    for method, compat in SCALE_METHODS:
        if method.startswith("optimal"):
            continue
        t = timeit(partial(sp.plan, sgoal, method, compat=compat), repeat)  # type: ignore[arg-type]
        r = timeit(partial(ref.plan, rf, rgoal, kitchen, set(), None, method, compat), 1)
        print(f"| {method}{' (course)' if compat else ''} | {fmt(t)} | {fmt(r)} | {r / t:,.0f}x |")


LADDER_CASES: list[tuple[str, str | None]] = [
    ("bfs", "course"), ("ids", None), ("greedy-success", None), ("greedy-inputs", None),
    ("optimal-success", None), ("optimal-units", None), ("optimal-inputs", None)]  # fmt: skip


LADDER_SHAPES: list[tuple[str, Callable[[int], str]]] = [
    ("A ladder (two rungs a level, each made in two ways; the last level needs the goal)",
     lambda n: ladder_text(n, objects=2)),
    ("A ladder on which every path fails differently (`expo_units`: dead regions)",
     lambda n: units_text(expo_units(n))),
    ("The same, with the only way out on the path (`expo_units(through_path=True)`: dead for the path)",
     lambda n: units_text(expo_units(n, through_path=True)))]  # fmt: skip


def bench_ladder(sizes: list[int], repeat: int, methods: list[str] | None = None) -> None:
    """Two adversarial shapes of tests/workloads.py, planned for the dish with every method:
    the ladder with two rungs a level (each made in two ways from both rungs of the next level,
    the last level needing the dish, which is on the path; the dish made last from kitchen
    items), and `expo_units` (the bottom rung made from any `a` of the path or from the dish:
    every path fails with another set of dependencies). `expanded` is the number of objects the
    search expanded; a search that forgot its failures expanded 2 ** levels on the first, and
    one that only remembers them 2 ** (levels + 2) - 2 on the second."""
    kitchen = [foon.Object(label, (state,)) for label, state in ladder_kitchen(2)]
    cases = [c for c in LADDER_CASES if methods is None or c[0] in methods]
    for title, text_of in LADDER_SHAPES:
        print(f"\n### {title}\n")
        print("| levels | units | " + " | ".join(
            f"{m}{' (course)' if c else ''}" for m, c in cases) + " |")  # fmt: skip
        print("|---:|---:|" + "---:|" * len(cases))
        for n in sizes:
            f = foon.Foon.from_text(text_of(n))
            planner = f.planner(kitchen, default_rate=0.5)
            goal = f.goal_id(foon.Object("dish", ("done",)))
            cells = []
            for method, compat in cases:
                t = timeit(partial(planner.plan, goal, method, compat=compat), repeat)  # type: ignore[arg-type]
                tree = planner.plan(goal, method, compat=compat)  # type: ignore[arg-type]
                assert tree.solved, (method, n)
                cells.append(f"{t * 1e6:,.1f} µs ({tree.expanded:,})")
            print(f"| {n:,} | {f.fu_count:,} | " + " | ".join(cells) + " |")


def container_text(n: int, held: bool) -> str:
    """One unit with n inputs: `bowl` holding `egg{i}`, and (held) `egg{i}` in the bowl next to
    it, which the container rule skips; else n holders with nothing in the bowl, which it must
    all check."""
    pair = "O\tbowl\nS\tcontains\t{{egg{i}}}\n" + ("O\tegg{i}\nS\tin\t[bowl]\n" if held else "")
    count = n // 2 if held else n
    return "".join(pair.format(i=i) for i in range(count)) + "M\tmix\nO\tbatter\nS\tmixed\n//\n"


def bench_container(n: int, repeat: int) -> None:
    """The container rule on one unit with n inputs (`Foon.plan` prepares the planner, which
    applies the rule, on every call)."""
    print(f"\n### The container rule on one unit with {n:,} inputs (utensil `bowl`)\n")
    print("| the unit's inputs | plan (container rule included) |")
    print("|---|---:|")
    goal = foon.Object("batter", ("mixed",))
    for held in (True, False):
        f = foon.Foon.from_text(container_text(n, held))
        t = timeit(partial(f.plan, goal, [], "ids", utensils=["bowl"]), repeat)
        what = (
            "bowls holding an egg, each egg in the bowl" if held else "bowls holding an egg, no egg"
        )
        print(f"| {what} | {fmt(t)} |")


def bench_memory(data: Path, n: int) -> None:
    """Peak memory of loading a file, against its size, for foon and the reference parser."""
    if not can_measure_memory():
        print("\n(memory: needs /proc, skipped)")
        return
    biggest = max((data / "lab_history").glob("*.txt"), key=lambda q: q.stat().st_size)
    with tempfile.TemporaryDirectory() as tmp:
        chain = Path(tmp) / f"chain_{n}.foon"
        chain.write_text(chain_text(n))
        files = [("course FOON.txt", data / "FOON.txt"),
                 (f"lab_history/{biggest.name}", biggest),
                 (f"a chain of {n:,} units", chain)]  # fmt: skip
        print("\n### Memory: loading a file (peak resident memory added, fresh process)\n")
        print("| file | size | foon index | foon peak | reference peak | foon uses less by |")
        print("|---|---:|---:|---:|---:|---:|")
        for name, path in files:
            size = path.stat().st_size
            index, peak = load_memory("foon", path)
            _, ref_peak = load_memory("reference", path)
            mb = 1 << 20
            print(
                f"| {name} | {size / mb:.1f} MiB | {index / mb:.1f} MiB ({index / size:.1f}x) "
                f"| {peak / mb:.1f} MiB ({peak / size:.1f}x) "
                f"| {ref_peak / mb:.1f} MiB ({ref_peak / size:.1f}x) | {ref_peak / peak:.1f}x |"
            )


def bench_api(repeat: int) -> None:
    """Costs of the Python API that grow with the calls or the output: one plan of one goal
    through a prepared planner (the fixed cost of a call), reading every unit of a 200,000-unit
    tree (`list(tree)`, light views), and the peak memory of `foon plan --format json` for
    100,001 goals (streamed; half of them in the kitchen, each other one a unit away), in a
    fresh process."""
    import resource
    import subprocess

    ex = foon.example()
    p = ex.foon.planner(ex.kitchen, motions=ex.motions, utensils=ex.utensils)
    g = ex.foon.goal_id(ex.goals[0])
    calls = 2_000

    def many_plans() -> None:
        for _ in range(calls):
            p.plan(g, "ids")

    per_call = timeit(many_plans, repeat) / calls
    n = 200_000
    f = foon.Foon.from_text(chain_text(n))
    tree = f.plan(foon.Object("item", (f"s{n}",)), [foon.Object("item", ("s0",))], "ids")
    per_unit = timeit(lambda: list(tree), repeat) / len(tree)
    print("\n### Python API costs\n")
    print("| what | time |")
    print("|---|---:|")
    print(
        f"| `Planner.plan` of one goal (embedded example, ids) | {per_call * 1e6:.1f} µs a call |"
    )
    print(f"| `list(tree)` of a {len(tree):,}-unit tree | {per_unit * 1e6:.2f} µs a unit |")
    with tempfile.TemporaryDirectory() as d:
        m = 100_000
        foon_file = Path(d) / "chain.foon"
        foon_file.write_text(chain_text(m))
        goals = Path(d) / "goals.json"
        goals.write_text(json.dumps([{"label": "item", "states": [f"s{i}"]} for i in range(m + 1)]))
        kitchen = Path(d) / "kitchen.json"
        # Every other object in the kitchen: each goal is one unit away (or in the kitchen), so
        # the run measures the output, not the planning.
        kitchen.write_text(
            json.dumps([{"label": "item", "states": [f"s{i}"]} for i in range(0, m + 1, 2)])
        )
        argv = [sys.executable, "-m", "foon", "plan", "--foon", str(foon_file), "--kitchen",
                str(kitchen), "--goals", str(goals), "--format", "json", "-q"]  # fmt: skip
        t = time.perf_counter()
        subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        wall = time.perf_counter() - t
        peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024
    print(f"| `foon plan --format json`, {m + 1:,} goals on a {m:,}-unit chain | "
          f"{fmt(wall)}, peak RSS {peak / 2**20:,.0f} MB |")  # fmt: skip


def pydot_picture(tree: foon.TaskTree) -> str:
    """The baseline: the picture as scripts build it today, with pydot (one node per object
    and motion, the same shapes and colours, edges input -> motion -> output)."""
    import pydot

    g = pydot.Dot("foon", graph_type="digraph")
    seen: set[int] = set()
    for k, u in enumerate(tree):
        m = f"m{u.index}"
        g.add_node(pydot.Node(m, shape="square", style="filled", fillcolor="red",
                              label=f"{k + 1}. {u.motion}"))  # fmt: skip
        for ids, objs, into in ((u.input_ids, u.inputs, True), (u.output_ids, u.outputs, False)):
            for o, obj in zip(ids, objs, strict=True):
                if o not in seen:
                    seen.add(o)
                    fill = "purple" if o == tree.goal_id else "green"
                    g.add_node(pydot.Node(f"o{o}", shape="circle", style="filled",
                                          fillcolor=fill, label=str(obj)))  # fmt: skip
                g.add_edge(pydot.Edge(f"o{o}", m) if into else pydot.Edge(m, f"o{o}"))
    return str(g.to_string())


def bench_pictures(data: Path, repeat: int) -> None:
    """Writing the pictures of the 25 course goals (optimal-success trees): the DOT text from
    the core (`TaskTree.write("dot")`, and `foon plan --format dot --out DIR` as a whole
    command, start-up and planning included) against building them with pydot; then what
    Graphviz's own `dot` adds to make SVG files (`--format svg`)."""
    import shutil
    import subprocess

    f = foon.load(data / "FOON.txt")
    kitchen = foon.Kitchen.load(data / "kitchen.json")
    motions = foon.MotionRates.load(data / "motion.txt")
    utensils = foon.load_utensils(data / "utensils.txt")
    goals = foon.load_goals(data / "goal_nodes_25.json")
    trees = f.plan_many(goals, kitchen, "optimal-success", motions=motions, utensils=utensils)
    trees = [t for t in trees if t.solved]
    core = timeit(lambda: [t.write("dot") for t in trees], repeat)
    base = timeit(lambda: [pydot_picture(t) for t in trees], repeat)
    print(f"\n### Pictures of the {len(trees)} solved course goals (optimal-success)\n")
    print("| what | time | vs pydot |")
    print("|---|---:|---:|")
    print(f"| pydot (the usual script) | {fmt(base)} | 1.0x |")
    print(f'| `TaskTree.write("dot")` | {fmt(core)} | {base / core:.0f}x faster |')
    argv = [sys.executable, "-m", "foon", "plan", "--foon", str(data / "FOON.txt"), "--kitchen",
            str(data / "kitchen.json"), "--motions", str(data / "motion.txt"), "--utensils",
            str(data / "utensils.txt"), "--goals", str(data / "goal_nodes_25.json"),
            "--method", "optimal-success", "-q"]  # fmt: skip
    for fmt_name in ("dot", "svg"):
        if fmt_name == "svg" and shutil.which("dot") is None:
            print("| `foon plan --format svg --out DIR` | (Graphviz not installed) | |")
            continue

        def whole(kind: str = fmt_name) -> None:
            with tempfile.TemporaryDirectory() as d:
                subprocess.run(
                    [*argv, "--format", kind, "--out", d], check=False, stderr=subprocess.DEVNULL
                )

        t = timeit(whole, max(1, repeat // 2))
        what = "start-up and planning included" if fmt_name == "dot" else "Graphviz included"
        print(f"| `foon plan --format {fmt_name} --out DIR` ({what}) | {fmt(t)} | |")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--data", type=Path, default=HERE.parent.parent / "shared" / "data" / "foon")
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument(
        "--only",
        choices=[
            "parse",
            "plan",
            "size",
            "scale",
            "ladder",
            "container",
            "memory",
            "api",
            "pictures",
        ],
    )
    p.add_argument(
        "--ladder",
        type=int,
        nargs="+",
        default=[28, 200, 2_000],
        help="rungs of the ladders in the ladder section",
    )
    p.add_argument("--methods", nargs="+", help="only these methods in the ladder section")
    p.add_argument(
        "--copies", type=int, default=100, help="copies of the course FOON in the FOON-size section"
    )
    p.add_argument("--chain", type=int, default=300_000, help="units in the scaling chain")
    p.add_argument(
        "--small-chain",
        type=int,
        default=2_000,
        help="units in the chain planned side by side with the reference",
    )
    a = p.parse_args()
    print(
        f"foon {foon.__version__}, Python {platform.python_version()}, "
        f"{platform.machine()}, {os.cpu_count()} cores"
    )
    if a.only in (None, "parse"):
        bench_parse(a.data, a.repeat)
    if a.only in (None, "plan"):
        bench_plan(a.data, a.repeat)
    if a.only in (None, "size"):
        bench_foon_size(a.data, a.copies, a.repeat)
    if a.only in (None, "scale"):
        bench_scale(a.chain, a.small_chain, a.repeat)
    if a.only in (None, "ladder"):
        bench_ladder(a.ladder, a.repeat, a.methods)
    if a.only in (None, "container"):
        bench_container(40_000, a.repeat)
    if a.only in (None, "memory"):
        bench_memory(a.data, a.chain)
    if a.only in (None, "api"):
        bench_api(a.repeat)
    if a.only in (None, "pictures"):
        bench_pictures(a.data, a.repeat)


if __name__ == "__main__":
    main()
