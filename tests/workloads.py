"""Generated inputs and measurements shared by the tests and ``benchmarks/run.py``.

- :func:`chain_text`: a chain of units, each needing the previous one's output, so the last
  object needs all of them (the deepest possible tree, and every object distinct).
- :func:`load_memory`: the index size and the peak memory of loading a file, measured in a
  fresh interpreter.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def chain_text(n: int) -> str:
    """``item (s0) -> item (s1) -> ... -> item (sn)``, one unit (motion ``step``) a link."""
    return "".join(f"O\titem\nS\ts{i}\nM\tstep\nO\titem\nS\ts{i + 1}\n//\n" for i in range(n))


#: Run in a fresh interpreter: loads argv[2] with foon ("foon") or the pure-Python reference
#: ("reference") and prints the index bytes (foon only, else 0) and the peak resident memory
#: the load added, in bytes. A tiny FOON is loaded first by the same code, so that code pages
#: and allocator arenas that any first load brings in are not counted. The peak is VmHWM, the
#: peak of this process alone (ru_maxrss can be the parent's, inherited over fork and exec).
_MEASURE = """
import sys
sys.path.insert(0, sys.argv[3])
import foon, foon_reference as ref
def status(key):
    with open("/proc/self/status") as fh:
        return 1024 * next(int(l.split()[1]) for l in fh if l.startswith(key + ":"))
tiny = "O\\ta\\nM\\tm\\nO\\tb\\nS\\tx\\n//\\n"
if sys.argv[1] == "foon":
    foon.Foon.from_text(tiny)
    base = status("VmRSS")
    index = foon.load(sys.argv[2]).stats()["index_bytes"]
else:
    ref.parse(tiny)
    base = status("VmRSS")
    with open(sys.argv[2], encoding="utf-8") as fh:
        ref.parse(fh.read())
    index = 0
print(index, status("VmHWM") - base)
"""


def can_measure_memory() -> bool:
    """Whether :func:`load_memory` works here (it reads /proc, so Linux only)."""
    return Path("/proc/self/status").exists()


def load_memory(which: str, path: Path) -> tuple[int, int]:
    """(index bytes, peak bytes added) of loading ``path`` with ``which`` ("foon" or
    "reference") in a fresh interpreter."""
    out = subprocess.run([sys.executable, "-c", _MEASURE, which, str(path), str(HERE)],
                         capture_output=True, text=True, timeout=600, check=True).stdout.split()  # fmt: skip
    return int(out[0]), int(out[1])
