"""Incremental kitchens: a kitchen changed by a few items, prepared from the base kitchen's
preparation against prepared from scratch.

    python benchmarks/incremental.py [--units 1M] [--seeds 1,2,3] [--delta 10] [--repeat 3]
                                     [--work DIR]

Build the wheel in release mode first (`maturin build --release`, installed in its own venv).
`foon synth` writes a FOON of `--units` units, its kitchen and motion table (seed 1, cached in
the work folder). The base planner (that kitchen, those rates) computes everything a plan of
each kind needs: the ranks, the choices of `ids` and the costs and choices of the three
optimal objectives. For each seed, four deltas of `--delta` items: additions of raw items
(objects without a producer, outside the kitchen: what a kitchen gains), removals (kitchen
items), half of each, and additions of made objects (objects with a producer, outside the
kitchen: each lowers the tree cost of everything made from it, so a large part of the FOON
changes, and the update costs about as much as a preparation from scratch). Side by side, in
one process, best of `--repeat`:

- **from scratch**: `Planner(foon, new_kitchen, motions=...)`, then a plan with `ids` and one
  with `optimal-units` (which computes the ranks, the `ids` choices and the three optimal
  objectives: what the base had);
- **incremental**: `base.with_changes(add=..., remove=...)` (the kitchen's difference applied
  to the base's preparation), then the same two plans (read from what it updated: the ranks
  and `ids` choices at once, `optimal-units`' costs as far as the goal needs);
- **to the end**: the same, then `finish_updates()` (every optimal objective the base had,
  updated over the whole FOON: what the base had, as from scratch).

The planners give the same ranks and the same plans for sampled goals with every method
(checked, on a planner from `with_changes` whose updates run goal by goal). Prints a
Markdown table and the command.
"""

from __future__ import annotations

import argparse
import random
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import foon
from scale import fmt_n, fmt_s, parse_size

SEED = 1
METHODS = ("ids", "optimal-success", "optimal-units", "optimal-inputs")

T = TypeVar("T")


def best(repeat: int, run: Callable[[], T]) -> tuple[float, T]:
    times: list[float] = []
    out: T | None = None
    for _ in range(repeat):
        # The previous run's result is freed before the clock starts, not timed with this run.
        out = None
        t = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - t)
    assert out is not None
    return min(times), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--units", default="1M")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--delta", type=int, default=10)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--check-goals", type=int, default=200)
    ap.add_argument("--work")
    ap.add_argument("--write-ids", action="store_true",
                    help="also write each seed's drawn object ids to the work folder "
                         "(raw<seed>.ids, rem<seed>.ids, made<seed>.ids: one id per line, "
                         "for examples/delta_time.rs)")  # fmt: skip
    args = ap.parse_args()
    n = parse_size(args.units)
    work = Path(args.work or tempfile.mkdtemp(prefix="foon-incremental-"))
    work.mkdir(parents=True, exist_ok=True)
    name = fmt_n(n)
    text = work / f"synth-{name}.txt"
    kitchen_file = work / f"synth-{name}-kitchen.json"
    goals_file = work / f"synth-{name}-goals.json"
    motions_file = work / f"synth-{name}-motions.txt"
    if not text.exists():
        subprocess.run(
            [sys.executable, "-m", "foon", "synth", "--units", str(n), "--seed", str(SEED),
             "-o", str(text), "--kitchen", str(kitchen_file), "--goals", str(goals_file),
             "--motions", str(motions_file), "-q"],
            check=True,
        )  # fmt: skip
    f = foon.Foon.load(text)
    kitchen = foon.Kitchen.load(kitchen_file)
    motions = foon.MotionRates.load(motions_file)
    goals = [f.goal_id(g) for g in foon.load_goals(goals_file)]

    base = foon.Planner(f, kitchen, motions=motions)
    solved = [g for g in goals if base.plan(g, "ids").solved]
    warm_goal = solved[0] if solved else goals[0]

    def warm(p: foon.Planner) -> foon.Planner:
        p.plan(warm_goal, "ids")
        p.plan(warm_goal, "optimal-units")
        return p

    warm(base)
    items = list(kitchen)
    inside = {f.find(o) for o in items}
    raw = [o for o in range(f.object_count) if o not in inside and not f.producers(o)]
    made = [o for o in range(f.object_count) if o not in inside and f.producers(o)]
    rows = []
    for seed in [int(s) for s in args.seeds.split(",")]:
        rnd = random.Random(seed)
        half = args.delta // 2
        adds = [f.object(o) for o in rnd.sample(raw, args.delta)]
        removes = rnd.sample(items, args.delta)
        made_ids = rnd.sample(made, args.delta)
        made_adds = [f.object(o) for o in made_ids]
        if args.write_ids:
            for stem, ids in (
                ("raw", [f.find(o) for o in adds]),
                ("rem", [f.find(o) for o in removes]),
                ("made", made_ids),
            ):
                (work / f"{stem}{seed}.ids").write_text("".join(f"{o}\n" for o in ids))
        for kind, add, remove in (
            ("additions (raw items)", adds, []),
            ("removals", [], removes),
            ("mixed", adds[:half], removes[: args.delta - half]),
            ("additions (made objects)", made_adds, []),
        ):
            new_kitchen = kitchen.without(remove).with_items(add)

            def scratch(k: foon.Kitchen = new_kitchen) -> foon.Planner:
                return warm(foon.Planner(f, k, motions=motions))

            def incremental(
                a: list[foon.Object] = add, r: list[foon.Object] = remove
            ) -> foon.Planner:
                return warm(base.with_changes(add=a, remove=r))

            def whole(a: list[foon.Object] = add, r: list[foon.Object] = remove) -> foon.Planner:
                p = warm(base.with_changes(add=a, remove=r))
                p.finish_updates()
                return p

            t_scratch, fresh = best(args.repeat, scratch)
            t_inc, inc = best(args.repeat, incremental)
            t_whole, _ = best(args.repeat, whole)
            # The same results (goal by goal, through the updates run as far as each needs).
            assert inc == fresh and inc.ranks() == fresh.ranks()
            sample = random.Random(seed).sample(range(f.object_count), args.check_goals)
            for m in METHODS:
                a = [(t.solved, t.units, t.cost) for t in (inc.plan(g, m) for g in sample)]
                b = [(t.solved, t.units, t.cost) for t in fresh.plan_many(sample, m)]
                assert a == b, (kind, m)
            rows.append((seed, kind, len(add), len(remove), t_scratch, t_inc, t_whole))
            print(f"seed {seed} {kind}: {fmt_s(t_scratch)} / {fmt_s(t_inc)} / {fmt_s(t_whole)}",
                  file=sys.stderr)  # fmt: skip

    print(f"\n{name}-unit synthetic FOON ({f.object_count:,} objects), its kitchen "
          f"({len(items):,} items) and motion rates; deltas of {args.delta} items; best of "
          f"{args.repeat}.\n")  # fmt: skip
    print("| seed | delta | added | removed | from scratch | incremental | speed-up "
          "| to the end | speed-up |")  # fmt: skip
    print("|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for seed, kind, a, r, ts, ti, tw in rows:
        print(f"| {seed} | {kind} | {a} | {r} | {fmt_s(ts)} | {fmt_s(ti)} | {ts / ti:.0f}x "
              f"| {fmt_s(tw)} | {ts / tw:.0f}x |")  # fmt: skip
    print(f"\n`python benchmarks/incremental.py --units {args.units} --seeds {args.seeds} "
          f"--delta {args.delta} --repeat {args.repeat}`")  # fmt: skip


if __name__ == "__main__":
    main()
