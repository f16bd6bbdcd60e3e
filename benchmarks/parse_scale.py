"""Parse and index at scale: FOONs of renamed copies of the course FOON, loaded from text.

    python benchmarks/parse_scale.py [--data ../shared/data/foon] [--units 10000 100000 1000000]
        [--threads 1 2] [--dir DIR] [--python NAME=INTERPRETER ...] [--repeat 1]

Each FOON is the course FOON followed by renamed copies of it: in copy k every label that is
neither a kitchen item nor a utensil gets the suffix `` copyK`` (ingredients and containers
are renamed the same way), so the copies share their raw items and utensils, as a merged FOON
does. A FOON of N units is ceil(N / 2,376) copies (421 copies for 1M units, 245 MB).

Every figure is one fresh interpreter running ``foon.load(FILE)`` (and ``foon stats FILE``):
wall time of the load and peak RSS of the process, with ``RAYON_NUM_THREADS`` set to each
``--threads`` value. ``--python`` compares builds in one run (for example the main branch
installed into another virtual environment): each NAME=INTERPRETER is measured on the same
files, in turn. Build in release mode first (``maturin develop --release``)."""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
COURSE_UNITS = 2376

_LOAD = """
import sys, time
import foon
t = time.perf_counter()
f = foon.load(sys.argv[1])
print(time.perf_counter() - t, f.fu_count)
"""


def shared_labels(data: Path) -> set[str]:
    """Labels kept across copies: the kitchen's items and the utensils."""
    kitchen = json.loads((data / "kitchen.json").read_text(encoding="utf-8"))
    keep = {str(item["label"]).lower() for item in kitchen}
    utensils = (data / "utensils.txt").read_text(encoding="utf-8").splitlines()
    keep.update(u.strip().lower() for u in utensils if u.strip())
    return keep


def renamed_copy(text: str, k: int, keep: set[str]) -> str:
    """Copy ``k`` of FOON text: labels, ingredients and containers not in ``keep`` renamed."""
    if k == 0:
        return text

    def name(s: str) -> str:
        return s if s.strip().lower() in keep else f"{s} copy{k}"

    def line(m: re.Match[str]) -> str:
        kind, rest = m.group(1), m.group(2)
        if kind.startswith("O"):
            fields = rest.split("\t")
            fields[0] = name(fields[0])
            return kind + "\t" + "\t".join(fields)
        fields = rest.split("\t")
        if len(fields) > 1:
            third = fields[1]
            if third.startswith("{") and third.rstrip().endswith("}"):
                inner = third.rstrip()[1:-1]
                fields[1] = "{" + ",".join(name(i) for i in inner.split(",")) + "}"
            elif third.startswith("[") and third.rstrip().endswith("]"):
                fields[1] = "[" + name(third.rstrip()[1:-1]) + "]"
        return kind + "\t" + "\t".join(fields)

    return re.sub(r"^(O\d*|S\d*)\t(.*)$", line, text, flags=re.MULTILINE)


def make_foon(data: Path, units: int, out: Path) -> int:
    """Writes the FOON of ``units`` units (rounded up to whole copies); returns the copies."""
    copies = max(1, math.ceil(units / COURSE_UNITS))
    if out.exists():
        return copies
    text = (data / "FOON.txt").read_text(encoding="utf-8")
    keep = shared_labels(data)
    tmp = out.with_suffix(".tmp")
    with tmp.open("w", encoding="utf-8", newline="") as w:
        for k in range(copies):
            w.write(renamed_copy(text, k, keep))
    tmp.replace(out)
    return copies


def measure(argv: list[str], threads: int) -> tuple[float, int, str]:
    """(wall seconds, peak RSS bytes, stdout) of one child process."""
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
    t = time.perf_counter()
    p = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, text=True)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t
    out = p.stdout.read() if p.stdout else ""
    err = p.stderr.read() if p.stderr else ""
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(argv)} failed: {err.strip()}")
    return wall, usage.ru_maxrss * 1024, out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", type=Path, default=HERE.parent.parent / "shared" / "data" / "foon")
    ap.add_argument("--units", type=int, nargs="+", default=[10_000, 100_000, 1_000_000])
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--dir", type=Path, help="where the FOONs are written (kept; default: temp)")
    ap.add_argument(
        "--python",
        action="append",
        default=[],
        metavar="NAME=INTERPRETER",
        help="a build to measure (repeatable); default: this interpreter",
    )
    ap.add_argument("--repeat", type=int, default=1, help="runs per figure (the best is shown)")
    ap.add_argument("--stats", action="store_true", help="also time `foon stats FILE`")
    a = ap.parse_args()
    builds = [tuple(p.split("=", 1)) for p in a.python] or [("this", sys.executable)]
    tmp = None
    if a.dir is None:
        tmp = tempfile.TemporaryDirectory(prefix="foon-scale-")
        a.dir = Path(tmp.name)
    a.dir.mkdir(parents=True, exist_ok=True)
    print("| units | copies | MB | build | threads | foon.load s | load peak RSS MB |"
          + (" foon stats s | stats peak RSS MB |" if a.stats else ""))  # fmt: skip
    print("|---:|---:|---:|---|---:|---:|---:|" + ("---:|---:|" if a.stats else ""))
    for units in a.units:
        path = a.dir / f"copies-{units}.txt"
        copies = make_foon(a.data, units, path)
        mb = path.stat().st_size / 1e6
        for name, python in builds:
            for threads in a.threads:
                runs = [measure([python, "-c", _LOAD, str(path)], threads) for _ in range(a.repeat)]
                wall = min(float(r[2].split()[0]) for r in runs)
                rss = min(r[1] for r in runs)
                row = f"| {units:,} | {copies} | {mb:,.0f} | {name} | {threads} | {wall:.2f} | {rss / 1e6:,.0f} |"
                if a.stats:
                    cmd = [python, "-m", "foon", "stats", str(path)]
                    st = [measure(cmd, threads) for _ in range(a.repeat)]
                    row += f" {min(s[0] for s in st):.2f} | {min(s[1] for s in st) / 1e6:,.0f} |"
                print(row, flush=True)
    if tmp is not None:
        tmp.cleanup()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
