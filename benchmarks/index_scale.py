"""The index at scale: a FOON of N renamed copies of the course FOON (421 copies: 1M units),
parsed from text, written as a ``.foonidx`` file, opened from it, and planned over from
both.

The copies share the raw items (labels no unit outputs) and the utensils, as merged FOONs
do; every other label is suffixed per copy. Each measure runs in a fresh process, so its
peak RSS is its own::

    python benchmarks/index_scale.py [--copies 421] [--dir /tmp/foon-scale] [--goals 200]

Prints one Markdown table row per measure. Needs a release build (``maturin develop
--release``) for meaningful figures.
"""

from __future__ import annotations

import argparse
import json
import re
import resource
import subprocess
import sys
import time
from pathlib import Path

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "foon"


def make_copies(out: Path, copies: int) -> None:
    text = (DATA / "FOON.txt").read_text()
    utensils = {u.strip() for u in (DATA / "utensils.txt").read_text().splitlines() if u.strip()}
    produced: set[str] = set()
    for unit in text.split("//\n"):
        lines = unit.splitlines()
        motion = next((i for i, line in enumerate(lines) if line.startswith("M")), None)
        if motion is None:
            continue
        for line in lines[motion + 1 :]:
            if line.startswith("O"):
                produced.add(line.split("\t")[1])
    private = produced - utensils

    def rename(k: int) -> str:
        def sub(m: re.Match[str]) -> str:
            label = m.group(1)
            return f"O\t{label} copy{k}" if label in private else m.group(0)

        return re.sub(r"^O\t([^\t\n]*)", sub, text, flags=re.MULTILINE)

    with out.open("w") as f:
        f.write(text)
        for k in range(1, copies):
            f.write(rename(k))


def rss_mb() -> tuple[float, float]:
    """(anonymous, file-backed) resident MB of this process."""
    fields = {}
    for line in Path("/proc/self/status").read_text().splitlines():
        key, _, value = line.partition(":")
        if key in ("RssAnon", "RssFile"):
            fields[key] = int(value.split()[0]) / 1024
    return fields.get("RssAnon", 0.0), fields.get("RssFile", 0.0)


def peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def child(what: str, text: Path, index: Path, goals: int) -> dict[str, object]:
    import foon

    before = rss_mb()
    t = time.perf_counter()
    if what == "parse":
        f = foon.load(text)
        out: dict[str, object] = {"seconds": time.perf_counter() - t, "units": f.fu_count}
        t = time.perf_counter()
        f.write_index(index)
        out["write_seconds"] = time.perf_counter() - t
        out["index_mb"] = index.stat().st_size / 1e6
        out["peak_mb"] = peak_mb()
        return out
    if what == "open":
        f = foon.load(index)
        secs = time.perf_counter() - t
        after = rss_mb()
        t = time.perf_counter()
        f.verify_checksum()
        return {
            "seconds": secs,
            "units": f.fu_count,
            "anon_mb": after[0] - before[0],
            "file_mb": after[1] - before[1],
            "checksum_seconds": time.perf_counter() - t,
        }
    # plans: the same goals from the parsed text and from the mapped index, one run
    kitchen = foon.Kitchen.load(DATA / "kitchen.json")
    utensils = foon.load_utensils(DATA / "utensils.txt")
    res: dict[str, object] = {}
    for name, path in (("text", text), ("index", index)):
        f = foon.load(path)
        produced = [o for o in range(f.object_count) if f.producers(o)]
        ids = produced[:: max(1, len(produced) // goals)][:goals]
        p = f.planner(kitchen, utensils=utensils, default_rate=0.9)
        for method in ("ids", "greedy-success", "optimal-success"):
            # The first batch pays what the method computes once per kitchen and, from the
            # mapped index, the first touch of its pages: the best of later batches is the
            # steady speed.
            trees = p.plan_many(ids, method, threads=1)
            secs = float("inf")
            for _ in range(7):
                t = time.perf_counter()
                p.plan_many(ids, method, threads=1)
                secs = min(secs, time.perf_counter() - t)
            res[f"{name}/{method}"] = {
                "plans_per_s": len(ids) / secs,
                "units": sum(len(tr.units) for tr in trees),
            }
    return res


def run(what: str, text: Path, index: Path, goals: int) -> dict[str, object]:
    cmd = [sys.executable, __file__, "--child", what, "--text", str(text), "--index", str(index)]
    cmd += ["--goals", str(goals)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out)  # type: ignore[no-any-return]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--copies", type=int, default=421)
    ap.add_argument("--dir", type=Path, default=Path("/tmp/foon-scale"))
    ap.add_argument("--goals", type=int, default=200)
    ap.add_argument("--child", help=argparse.SUPPRESS)
    ap.add_argument("--text", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--index", type=Path, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        print(json.dumps(child(a.child, a.text, a.index, a.goals)))
        return 0
    a.dir.mkdir(parents=True, exist_ok=True)
    text = a.dir / f"copies{a.copies}.txt"
    index = a.dir / f"copies{a.copies}.foonidx"
    if not text.exists():
        make_copies(text, a.copies)
    print(f"text: {text} ({text.stat().st_size / 1e6:.0f} MB)")
    parse = run("parse", text, index, a.goals)
    print("| measure | value |\n|---|---|")
    print(f"| units | {parse['units']:,} |")
    print(
        f"| parse + index from text | {parse['seconds']:.2f} s, peak RSS {parse['peak_mb']:.0f} MB |"
    )
    print(f"| write .foonidx | {parse['write_seconds']:.2f} s, {parse['index_mb']:.0f} MB |")
    opened = run("open", text, index, a.goals)
    print(
        f"| open .foonidx (validated) | {float(opened['seconds']) * 1000:.1f} ms, "  # type: ignore[arg-type]
        f"+{opened['anon_mb']:.1f} MB anonymous, +{opened['file_mb']:.0f} MB of the mapped file |"
    )
    print(f"| verify checksum | {float(opened['checksum_seconds']) * 1000:.0f} ms |")  # type: ignore[arg-type]
    plans = run("plans", text, index, a.goals)
    for method in ("ids", "greedy-success", "optimal-success"):
        t = plans[f"text/{method}"]
        m = plans[f"index/{method}"]
        assert t["units"] == m["units"]  # type: ignore[index]
        print(
            f"| {method}: plans/s parsed vs mapped | {t['plans_per_s']:.0f} vs "  # type: ignore[index]
            f"{m['plans_per_s']:.0f} ({a.goals} goals, 1 thread) |"  # type: ignore[index]
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
