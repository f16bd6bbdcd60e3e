"""Generated inputs and measurements shared by the tests and ``benchmarks/run.py``.

- :func:`chain_text`: a chain of units, each needing the previous one's output, so the last
  object needs all of them (the deepest possible tree, and every object distinct).
- :func:`ladder_text` and friends: FOONs on which a search that forgets its failures retries
  every combination (ladders, alternations, cycles back to the path, many producers), and
  :func:`expo_units`, on which a memory of failures keyed by the path never applies.
- :func:`load_memory`: the index size and the peak memory of loading a file, measured in a
  fresh interpreter.
"""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path

HERE = Path(__file__).resolve().parent


def chain_text(n: int) -> str:
    """``item (s0) -> item (s1) -> ... -> item (sn)``, one unit (motion ``step``) a link."""
    return "".join(f"O\titem\nS\ts{i}\nM\tstep\nO\titem\nS\ts{i + 1}\n//\n" for i in range(n))


#: An object as (label, state), and a unit as (inputs, motion, outputs).
Item = tuple[str, str]
Unit = tuple[tuple[Item, ...], str, tuple[Item, ...]]

#: The goal of every generated adversarial FOON.
LADDER_GOAL: Item = ("dish", "done")


def units_text(units: Sequence[Unit]) -> str:
    """The FOON text of ``units``, in order (each object with its one state)."""

    def objs(items: Sequence[Item]) -> str:
        return "".join(f"O\t{label}\nS\t{state}\n" for label, state in items)

    return "".join(f"{objs(ins)}M\t{motion}\n{objs(outs)}//\n" for ins, motion, outs in units)


def ladder_kitchen(width: int) -> list[Item]:
    """The kitchen of a ladder of this width: ``spice k0`` .. ``spice k{width}``."""
    return [("spice", f"k{j}") for j in range(width + 1)]


def ladder_units(
    levels: int, width: int = 2, back_to: int = 0, producers: int = 0, objects: int = 1
) -> list[Unit]:
    """A "ladder": each of the ``objects`` rungs of level 1 has ``width`` producers, each needing
    every rung of level 2 and its own kitchen item, and so on down to level ``levels``, whose
    producers need ``back_to``: the goal itself when 0 (on the path, so they are skipped), else
    the first rung of level ``back_to`` (a cycle back to the middle of the path; that rung can
    also be made from kitchen items, tried after its ladder producers, so the search succeeds
    there after failing below it). The goal ``dish done`` is made first from level 1 (the
    ladder), then by ``producers`` units that need an object nobody makes, and last from
    kitchen items alone, so everything is derivable.

    A search that forgets its failures explores the bottom level once per combination of the
    choices above it: ``width ** levels`` times.
    """
    assert levels >= 1 and width >= 1 and 0 <= back_to <= levels and producers >= 0
    assert objects >= 1
    k = ladder_kitchen(width)
    # As many inputs as a ladder unit, so that no heuristic prefers it.
    plain = tuple(k[j % len(k)] for j in range(objects + 1))

    def level(i: int) -> tuple[Item, ...]:
        if objects == 1:
            return (("rung", f"r{i}"),)
        return tuple(("rung", f"r{i}.{a}") for a in range(objects))

    units: list[Unit] = [((*level(1), k[0]), "mix", (LADDER_GOAL,))]
    for i in range(1, levels + 1):
        if i < levels:
            below = level(i + 1)
        else:
            below = (LADDER_GOAL,) if back_to == 0 else level(back_to)[:1]
        for r in level(i):
            units += [((*below, k[j]), "mix", (r,)) for j in range(width)]
    units += [((("ghost", f"g{j}"), k[0]), "mix", (LADDER_GOAL,)) for j in range(producers)]
    if back_to:
        units.append((plain, "mix", level(back_to)[:1]))
    units.append((plain, "mix", (LADDER_GOAL,)))
    return units


def ladder_text(
    levels: int, width: int = 2, back_to: int = 0, producers: int = 0, objects: int = 1
) -> str:
    """The text of :func:`ladder_units`."""
    return units_text(ladder_units(levels, width, back_to, producers, objects))


def alternation_units(levels: int, width: int = 2) -> list[Unit]:
    """A deep alternation of two kinds of objects: ``a{i}`` is made from ``b{i}`` and ``b{i}``
    from ``a{i+1}`` (motions ``stir`` and ``mix``), each in ``width`` ways; the last ``b``
    needs the goal, so every way down fails, and the goal is made, after the ladder, from
    kitchen items."""
    k = ladder_kitchen(width)
    units: list[Unit] = [((("a", "1"), k[0]), "mix", (LADDER_GOAL,))]
    for i in range(1, levels + 1):
        units += [((("b", str(i)), k[j]), "stir", (("a", str(i)),)) for j in range(width)]
        below = ("a", str(i + 1)) if i < levels else LADDER_GOAL
        units += [((below, k[j]), "mix", (("b", str(i)),)) for j in range(width)]
    units.append(((k[0], k[1 % len(k)]), "mix", (LADDER_GOAL,)))
    return units


def expo_units(levels: int, chain: int = 0, through_path: bool = False) -> list[Unit]:
    """A ladder on which every path fails with another set of dependencies: the dish is made
    first from rung ``r1``; rung ``r{i}`` from ``a{i}`` or ``b{i}``, each made from rung
    ``r{i+1}``; the bottom rung from any ``a{j}`` (on the path when rung ``j`` was made from it)
    or from the dish (always on the path). A memory of failures keyed by the path never applies
    again (the plain search expands ``2 ** (levels + 2) - 2`` objects), but no object below the
    dish can lead to a choice. With ``chain``, the dish can also be made, before the kitchen
    way, from ``c1``, made from ``c2``, ..., ``c{chain}`` from kitchen items (a live region next
    to the dead one). With ``through_path``, each ``a{i}`` can also be made from rung ``r1``
    and ``r1`` from kitchen items, both tried after the other ways: every object then reaches a
    unit ready to run, but only through ``r1``, which is on the path below the dish whenever
    the ladder is explored."""
    k0, k1 = ladder_kitchen(1)

    def r(i: int) -> Item:
        return ("rung", f"r{i}")

    units: list[Unit] = [((r(1), k0), "mix", (LADDER_GOAL,))]
    for i in range(1, levels + 1):
        a, b = ("a", f"a{i}"), ("b", f"b{i}")
        units += [((a, k0), "mix", (r(i),)), ((b, k1), "mix", (r(i),)),
                  ((r(i + 1), k0), "mix", (a,)), ((r(i + 1), k1), "mix", (b,))]  # fmt: skip
    units += [((("a", f"a{i}"), k0), "mix", (r(levels + 1),)) for i in range(1, levels + 1)]
    units.append(((LADDER_GOAL, k0), "mix", (r(levels + 1),)))
    if chain:
        c = [("c", f"c{i}") for i in range(chain + 1)]
        units.append(((c[1], k1), "mix", (LADDER_GOAL,)))
        units += [((c[i + 1], k0), "mix", (c[i],)) for i in range(1, chain)]
        units.append(((k1, k0), "mix", (c[chain],)))
    if through_path:
        units += [((r(1), k1), "mix", (("a", f"a{i}"),)) for i in range(1, levels + 1)]
        units.append(((k0, k1), "mix", (r(1),)))
    units.append(((k0, k1), "mix", (LADDER_GOAL,)))
    return units


def graph_units(producers: Sequence[Sequence[Sequence[int]]]) -> list[Unit]:
    """A dense little FOON from a graph: object ``i`` is ``node n{i}``; ``producers[i]`` lists
    the ways to make it, each a list of input objects, in file order (``node n0`` is meant as
    the kitchen). Random graphs of this kind give the cases where a failure depends on the
    path it happened on."""
    node = [("node", f"n{i}") for i in range(len(producers))]
    return [
        (tuple(node[x] for x in ins), "mix", (node[o],))
        for o, ways in enumerate(producers)
        for ins in ways
    ]


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
