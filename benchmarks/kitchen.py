"""Kitchens at scale: loading a large kitchen, preparing a planner with it, and what the
objects it leaves behind cost the garbage collector.

    python benchmarks/kitchen.py [--data ../shared/data/foon] [--copies 421] [--repeat 3]

The FOON is the course FOON and copies-1 renamed copies of it (every object label suffixed
with its copy number: 2,376 x copies units, 1M at 421 copies); the kitchen is the course
kitchen renamed the same way for every copy (1,174 x copies items, 494,254 at 421), so every
item is an object of the FOON. Prints one Markdown row: kitchen items, objects matched, the
best of ``--repeat`` times for ``Kitchen.load``, for ``Foon.planner`` (matching the kitchen
and preparing it) and for a full ``gc.collect()`` with the kitchen and the planner alive,
the objects the collector tracks, and the peak RSS. Build in release mode first
(``maturin develop --release``)."""

from __future__ import annotations

import argparse
import gc
import json
import re
import resource
import tempfile
import time
from pathlib import Path

import foon

HERE = Path(__file__).resolve().parent


def make_inputs(data: Path, copies: int, out: Path) -> tuple[Path, Path]:
    """Writes the FOON and the kitchen of ``copies`` copies (the course's own is copy 0)."""
    text = (data / "FOON.txt").read_text(encoding="utf-8")
    foon_path = out / f"foon_{copies}.txt"
    with foon_path.open("w", encoding="utf-8") as w:
        w.write(text)
        for k in range(1, copies):
            w.write(re.sub(r"^O\t(.*)$", rf"O\t\1 copy{k}", text, flags=re.MULTILINE))
    items = json.loads((data / "kitchen.json").read_text(encoding="utf-8"))
    renamed = [
        {**item, "label": item["label"] + (f" copy{k}" if k else "")}
        for k in range(copies)
        for item in items
    ]
    kitchen_path = out / f"kitchen_{copies}.json"
    kitchen_path.write_text(json.dumps(renamed), encoding="utf-8")
    return foon_path, kitchen_path


def best(times: list[float]) -> str:
    return f"{min(times):.3f} s"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", type=Path, default=HERE.parent.parent / "shared/data/foon")
    ap.add_argument("--copies", type=int, default=421)
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        foon_path, kitchen_path = make_inputs(a.data, a.copies, Path(tmp))
        f = foon.load(foon_path)
        motions = foon.MotionRates.load(a.data / "motion.txt")
        utensils = foon.load_utensils(a.data / "utensils.txt")
        loads, preps, gcs = [], [], []
        tracked = matched = items = 0
        for _ in range(a.repeat):
            gc.collect()
            t = time.perf_counter()
            kitchen = foon.Kitchen.load(kitchen_path)
            loads.append(time.perf_counter() - t)
            t = time.perf_counter()
            planner = f.planner(kitchen, motions=motions, utensils=utensils)
            preps.append(time.perf_counter() - t)
            t = time.perf_counter()
            gc.collect()
            gcs.append(time.perf_counter() - t)
            tracked = len(gc.get_objects())
            items, matched = len(kitchen), len(planner._native.kitchen_objects())
            del kitchen, planner
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"| {f.fu_count:,} units | {items:,} items | {matched:,} matched | {best(loads)} "
          f"| {best(preps)} | {best(gcs)} | {tracked:,} | {rss:,.0f} MB |")  # fmt: skip


if __name__ == "__main__":
    main()
