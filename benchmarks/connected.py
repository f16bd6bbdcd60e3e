"""Planning on connected merged FOONs: cost per tree unit against the course FOON.

    python benchmarks/connected.py [--data ../shared/data/foon] [--sizes 10k,100k,300k,1M]
                                   [--family shared,raw] [--goals 100]

Build the wheel in release mode first (`maturin develop --release`).

Two families of FOONs are built from copies of the course FOON (raw items and utensils keep
their names, so they are shared by every copy):

- `shared`: every intermediate (an object with a producer in the course FOON) is shared by
  five consecutive copies (a window that starts at a different copy for each object), so a
  shared intermediate has about five producing copies from different recipes and a goal's
  ancestry is a large part of the FOON;
- `raw`: every intermediate is private to its copy (raw items are shared by all recipes), so
  the ancestry of a goal stays the size of the course's.

The kitchen is the course kitchen, its intermediates copied as the objects are. Goals: the 25
course goals in copies spread over the FOON. For every method: plans per second (one thread,
best of `--repeat` batches), mean tree size, cost per tree unit, what the first batch costs
more than the next ones (what the method computes once per kitchen), the preparation of the
planner, and the explanation of a failing goal (the goals of a sparse kitchen, every other raw
kitchen item dropped). Times are CPU time of the process (see `clock`). Printed as Markdown.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

import foon

HERE = Path(__file__).resolve().parent
COURSE_UNITS = 2376
WINDOW = 5

CASES: list[tuple[str, str | None]] = [
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


def clock() -> float:
    """CPU time of this process: every plan runs on the calling thread (`threads=1`), and
    the machines these figures come from are shared, so wall time would count other work."""
    return time.process_time()


def parse_size(s: str) -> int:
    s = s.strip().lower()
    mult = {"k": 1000, "m": 1_000_000}.get(s[-1], 1)
    return int(float(s.rstrip("km")) * mult)


class Course:
    def __init__(self, data: Path) -> None:
        self.foon = foon.load(data / "FOON.txt")
        self.kitchen = foon.Kitchen.load(data / "kitchen.json")
        self.motions = foon.MotionRates.load(data / "motion.txt")
        self.utensils = foon.load_utensils(data / "utensils.txt")
        self.goals = [
            foon.Object.from_dict(d) for d in json.loads((data / "goal_nodes_25.json").read_text())
        ]
        f = self.foon
        self.inter = {o for o in range(f.object_count) if f.producers(o)}
        # Each FU's text split into object blocks (the lines of each object) and its motion.
        self.blocks: list[tuple[list[int], list[str]]] = []
        for i in range(f.fu_count):
            u = f.fu(i)
            ids = list(u.input_ids) + list(u.output_ids)
            parts: list[str] = []
            for line in f.fu_text(i).split("\n"):
                if line.startswith(("O\t", "M\t", "//")):
                    parts.append(line)
                else:
                    parts[-1] += "\n" + line
            self.blocks.append((ids, parts))


def tag(family: str, copy: int, o: int) -> str:
    """The state that names object `o` (an intermediate) in copy `copy`."""
    if family == "raw":
        return f"copy {copy}"
    return f"share {(copy + o % WINDOW) // WINDOW}"


def build(c: Course, family: str, copies: int) -> str:
    out: list[str] = []
    for k in range(copies):
        for ids, parts in c.blocks:
            j = 0
            for p in parts:
                if p.startswith("O\t"):
                    o = ids[j]
                    j += 1
                    if o in c.inter:
                        head, _, rest = p.partition("\n")
                        p = f"{head}\nS\t{tag(family, k, o)}" + (f"\n{rest}" if rest else "")
                out.append(p)
    return "\n".join(out) + "\n"


def tagged(o: foon.Object, t: str) -> foon.Object:
    return foon.Object(o.label, [t, *o.states], o.ingredients, o.container)


def kitchen_for(c: Course, family: str, copies: int, items: list[foon.Object]) -> foon.Kitchen:
    out: list[foon.Object] = []
    for item in items:
        i = c.foon.find(item)
        if i is None or i not in c.inter:
            out.append(item)
        else:
            out.extend(tagged(item, t) for t in sorted({tag(family, k, i) for k in range(copies)}))
    return foon.Kitchen(out)


def goals_for(c: Course, family: str, copies: int, n: int) -> list[foon.Object]:
    spots = max(1, -(-n // len(c.goals)))
    picks = sorted({k * copies // spots for k in range(spots)})
    out = []
    for k in picks:
        for g in c.goals:
            i = c.foon.find(g)
            out.append(g if i is None or i not in c.inter else tagged(g, tag(family, k, i)))
    return out[:n] if len(out) >= n else out


def measure(name: str, f: foon.Foon, c: Course, kitchen: foon.Kitchen,
            sparse: foon.Kitchen, goals: list[foon.Object], repeat: int) -> None:  # fmt: skip
    t = clock()
    p = f.planner(kitchen, motions=c.motions, utensils=c.utensils)
    prep = clock() - t
    ids = [f.goal_id(g) for g in goals]
    print(f"\n#### {name}: {f.fu_count:,} units, {f.object_count:,} objects, "
          f"{len(kitchen):,} kitchen items; planner prepared in {prep * 1000:.0f} ms\n")  # fmt: skip
    print("| method | computed once (ms) | plans/s | mean tree | µs per tree unit | solved |")
    print("|---|---:|---:|---:|---:|---:|")
    for method, compat in CASES:
        # The first batch computes what the method needs once per kitchen; the best of the
        # next `repeat` batches is the plan rate.
        t = clock()
        p.plan_many(ids, method, compat=compat, threads=1)  # type: ignore[arg-type]
        cold = clock() - t
        dt = float("inf")
        for _ in range(repeat):
            t = clock()
            trees = p.plan_many(ids, method, compat=compat, threads=1)  # type: ignore[arg-type]
            dt = min(dt, clock() - t)
        units = sum(len(tr.units) for tr in trees)
        mean = units / len(trees)
        per_unit = dt / units * 1e6 if units else float("nan")
        solved = sum(tr.solved for tr in trees)
        label = method + (" (course)" if compat else "")
        print(f"| {label} | {max(0.0, cold - dt) * 1000:.1f} | {len(trees) / dt:,.0f} | "
              f"{mean:.1f} | {per_unit:.2f} | {solved}/{len(trees)} |")  # fmt: skip
    # The failure path: a sparse kitchen, goals it cannot make.
    t = clock()
    sp = f.planner(sparse, motions=c.motions, utensils=c.utensils)
    sprep = clock() - t
    t = clock()
    first = sp.plan_many(ids, "ids", threads=1)
    sfirst = clock() - t
    failing = [g for g, tr in zip(ids, first, strict=True) if not tr.solved]
    if failing:
        times = []
        for g in failing:
            t = clock()
            sp.plan(g, "optimal-units")
            times.append(clock() - t)
        print(f"\nSparse kitchen ({len(sparse):,} items): prepared in {sprep * 1000:.0f} ms, "
              f"first batch {sfirst * 1000:.1f} ms; {len(failing)} failing goals, explanation "
              f"median {statistics.median(times) * 1000:.3f} ms, "
              f"max {max(times) * 1000:.3f} ms")  # fmt: skip
    else:
        print("\nSparse kitchen: no goal fails")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, default=HERE.parent.parent / "shared" / "data" / "foon")
    ap.add_argument("--sizes", default="10k,100k,300k,1M")
    ap.add_argument("--family", default="shared,raw")
    ap.add_argument("--goals", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    c = Course(a.data)
    items = list(c.kitchen)
    raw_items = [o for o in items if (i := c.foon.find(o)) is None or i not in c.inter]
    dropped = set(raw_items[::2])
    sparse_items = [o for o in items if o not in dropped]
    print("### Planning on connected FOONs (one thread)")
    course_goals = (c.goals * -(-a.goals // len(c.goals)))[: a.goals]
    measure("course FOON", c.foon, c, c.kitchen, foon.Kitchen(sparse_items), course_goals, a.repeat)
    for fam in a.family.split(","):
        for s in a.sizes.split(","):
            copies = max(1, round(parse_size(s) / COURSE_UNITS))
            t = time.perf_counter()
            f = foon.Foon.from_text(build(c, fam, copies))
            load = time.perf_counter() - t
            print(f"\n(`{fam}`, {copies} copies: built and parsed in {load:.1f} s)")
            measure(f"`{fam}` {s}", f, c, kitchen_for(c, fam, copies, items),
                    kitchen_for(c, fam, copies, sparse_items), goals_for(c, fam, copies, a.goals),
                    a.repeat)  # fmt: skip


if __name__ == "__main__":
    main()
