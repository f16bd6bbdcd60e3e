"""Many kitchens at once: the 64-kitchen pass against 64 separate preparations.

    python benchmarks/kitchens_many.py [--sizes 100k,1M] [--kitchens 64] [--work DIR]
                                       [--clock wall|cpu]

Build the wheel in release mode first (`maturin build --release`, installed in its own venv).
For each size, `foon synth` writes a FOON, its kitchen and goals (seed 1, cached in the work
folder); the kitchens are that kitchen with a random tenth of its items dropped (one seed per
kitchen). Three ways to answer "is each goal derivable (its rank) in each kitchen", all in one
process, in the core (the Python side only converts the small answers), best of `--repeat`:

- **separate**: each kitchen prepared from scratch (`Prepared::with_objects`: container rule,
  needed-by lists, rates) and its ranks computed: what preparing a kitchen cost before;
- **shared base**: one kitchen-independent base, each kitchen prepared on it
  (`Prepared::with_base`) and its ranks computed;
- **lanes**: the 64-kitchen pass (`multi::derivable_many`, and `multi::ranks_many` with ranks),
  one thread.

Matching the kitchens' items to the FOON's objects is the same work in all three ways
(O(items) hash lookups, not O(FOON)); it is timed on its own ("match"), and the three ways
run on the kitchens matched once (`foon._foon.match_kitchens`), so that their columns are
the preparations alone. The last column puts the matching back into both sides: a call that
starts from items. Every way gives the same answers (checked). Prints a Markdown table and
the command. The clock is the wall clock, or with `--clock cpu` the CPU time of the process
(all its threads: with one thread, the call's own work), which other programs on a shared
machine disturb less.
"""

from __future__ import annotations

import argparse
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import foon
from foon import _foon
from scale import fmt_n, fmt_s, parse_size

SEED = 1


def best(repeat: int, run: object, clock: str = "wall") -> tuple[float, object]:
    now = time.process_time if clock == "cpu" else time.perf_counter
    times, out = [], None
    for _ in range(repeat):
        t = now()
        out = run()  # type: ignore[operator]
        times.append(now() - t)
    return min(times), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="100k,1M")
    ap.add_argument("--kitchens", type=int, default=64)
    ap.add_argument("--goals", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--work")
    ap.add_argument("--clock", choices=("wall", "cpu"), default="wall")
    args = ap.parse_args()
    work = Path(args.work or tempfile.mkdtemp(prefix="foon-kitchens-"))
    work.mkdir(parents=True, exist_ok=True)
    rows = []
    for n in [parse_size(s) for s in args.sizes.split(",")]:
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
        kitchens = []
        for k in range(args.kitchens):
            rnd = random.Random(k)
            kitchens.append(foon.Kitchen(o for o in items if rnd.random() >= 0.1))
        natives = [k._native for k in kitchens]
        gids = [f.goal_id(g) for g in foon.load_goals(goals)]
        r = {"n": n, "objects": f.object_count}
        r["match"], matched = best(
            args.repeat, lambda f=f, natives=natives: _foon.match_kitchens(f._native, natives, 3),
            args.clock,
        )  # fmt: skip
        print(f"[{name} match: {fmt_s(r['match'])}]", file=sys.stderr, flush=True)

        def way(
            mode: str,
            ranks: bool,
            f: foon.Foon = f,
            matched: object = matched,
            gids: list[int] = gids,
        ) -> object:
            return lambda: _foon.derivable_many(f._native, matched, gids, [], 3, ranks, 1, mode)  # type: ignore[arg-type]

        want = None
        for key, mode, ranks in (
            ("separate", "separate", True),
            ("shared", "shared", True),
            ("lanes_ranks", "lanes", True),
            ("lanes", "lanes", False),
        ):
            r[key], out = best(args.repeat, way(mode, ranks), args.clock)
            if ranks:
                assert want is None or out == want, key
                want = out
            else:
                assert out == [[x is not None for x in row] for row in want], key  # type: ignore[union-attr]
            print(f"[{name} {key}: {fmt_s(r[key])}]", file=sys.stderr, flush=True)
        r["made"] = sum(x is not None for row in want for x in row)  # type: ignore[union-attr]
        rows.append(r)
    k = args.kitchens
    clock = ", CPU time" if args.clock == "cpu" else ""
    print(f"\n### {k} kitchens at once (ranks of {args.goals} goals in each{clock})\n")
    print(
        f"| units | objects | match {k} | separate | shared base | lanes, ranks | "
        "lanes, derivable | separate / shared | separate / lanes ranks | "
        "separate / lanes derivable | with matching: separate / lanes ranks |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        m = r["match"]
        print(
            f"| {fmt_n(r['n'])} | {r['objects']:,} | {fmt_s(m)} | {fmt_s(r['separate'])} | "
            f"{fmt_s(r['shared'])} | {fmt_s(r['lanes_ranks'])} | {fmt_s(r['lanes'])} | "
            f"{r['separate'] / r['shared']:.1f}x | {r['separate'] / r['lanes_ranks']:.1f}x | "
            f"{r['separate'] / r['lanes']:.1f}x | "
            f"{(r['separate'] + m) / (r['lanes_ranks'] + m):.1f}x |"
        )
    opt = " --clock cpu" if args.clock == "cpu" else ""
    print(
        f"\nCommand: `python benchmarks/kitchens_many.py --sizes {args.sizes} --kitchens {k}{opt}`"
    )


if __name__ == "__main__":
    main()
