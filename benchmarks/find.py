"""`foon find` on a 1M-unit synthetic FOON: the index build (once per FOON) and queries.

python benchmarks/find.py DIR     # uses DIR/s1m.txt, made with
                                  # foon synth --units 1000000 --seed 1 -o DIR/s1m.txt
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path

import foon

QUERIES = [
    "chopped onion in bowl",
    "sliced tomato",
    "boiled egg in pot",
    "whipped cream in mixing bowl",
    "fried rice in frying pan",
    "diced carrot",
    "melted butter in pan",
    "grated cheese in bowl",
    "xyzzy",
    "onoin chpoped",
]


def main() -> int:
    folder = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    path = folder / "s1m.txt"
    if not path.exists():
        subprocess.run(
            [sys.executable, "-m", "foon", "synth", "--units", "1000000", "--seed", "1",
             "-o", str(path)],
            check=True,
        )  # fmt: skip
    t = time.perf_counter()
    f = foon.load(path)
    print(f"load: {time.perf_counter() - t:.1f} s ({f.fu_count} units, {f.object_count} objects)")
    t = time.perf_counter()
    f.find_similar("", 1)
    print(f"index build (first query): {time.perf_counter() - t:.3f} s")
    times = []
    for q in QUERIES * 3:
        t = time.perf_counter()
        found = f.find_similar(q, 10)
        times.append(time.perf_counter() - t)
        if len(times) <= len(QUERIES):
            best = found[0] if found else None
            print(f"  {q!r}: {1000 * times[-1]:.1f} ms; best {best.object if best else None}")
    print(
        f"query: median {1000 * statistics.median(times):.1f} ms, "
        f"max {1000 * max(times):.1f} ms over {len(times)} queries (k = 10)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
