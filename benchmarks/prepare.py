"""Preparing one kitchen with everything a planner computes once for it, in a fresh process.

    python benchmarks/prepare.py [--work DIR] [--size 1M] [--repeat 3]

Reads the FOON (`.foonidx`), kitchen and goals that `benchmarks/scale.py --keep` leaves in its
work directory (`synth-SIZE.foonidx`, `synth-SIZE-kitchen.json`, `synth-SIZE-goals.json`) and
times, in a process that has done nothing else, the steps of `scale.prepare_everything`: the
planner (kitchen matched, container rule, rates), ranks and the `ids` choice, the three optimal
objectives (computed together), and the shopping costs of failure explanations. Each repeat
runs in its own process; the best total is printed as a Markdown row.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def worker(work: Path, size: str) -> dict[str, float]:
    import foon
    from scale import prepare_everything

    f = foon.load(work / f"synth-{size}.foonidx")
    kitchen = foon.Kitchen.load(work / f"synth-{size}-kitchen.json")
    goals = foon.load_goals(work / f"synth-{size}-goals.json")
    return prepare_everything(f, list(kitchen), goals, foon.synth_motions())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--work", default=str(Path.cwd()))
    ap.add_argument("--size", default="1M")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        sys.path.insert(0, str(HERE))
        print(json.dumps(worker(Path(args.work), args.size)))
        return
    runs = []
    for _ in range(args.repeat):
        out = subprocess.run(
            [sys.executable, __file__, "--worker", "--work", args.work, "--size", args.size],
            capture_output=True,
            text=True,
            check=True,
        )
        runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
    best = min(runs, key=lambda r: r["total"])
    keys = list(best)
    print(f"`python benchmarks/prepare.py --size {args.size} --repeat {args.repeat}`\n")
    print("| size | " + " | ".join(keys) + " | without shopping |")
    print("|---|" + "---:|" * (len(keys) + 1))
    cells = [f"{best[k] * 1000:.0f} ms" if best[k] >= 1e-3 else "< 1 ms" for k in keys]
    without = (best["total"] - best["shopping"]) * 1000
    print(f"| {args.size} | " + " | ".join(cells) + f" | {without:.0f} ms |")


if __name__ == "__main__":
    main()
