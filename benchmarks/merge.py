"""Merging the lab's 111 subgraphs: the Rust core against pure-Python merges, in one run.

    python benchmarks/merge.py [--data ../shared/data/foon] [--repeat 5] [--lab-files N]

Three merges of ``subgraphs_foon_api_FOON-111/`` (111 files, 2,337 units):

- ``foon.merge`` (the core, called from Python, file reading included);
- ``merge_reference.merge`` (tests/merge_reference.py): an idiomatic pure-Python merge of the
  same semantics, one dict from unit key to kept unit;
- ``LabMerge`` below: a pure-Python port of the lab's own merge (``_mergeSubgraphs`` of
  ``FOON_graph_analyser.py`` in davidpaulius/foon_api, with ``FOON_classes.py``), without its
  prompts: every file is read line by line; each object is compared with every node read so
  far (at each of the three hierarchy levels) and each unit with every unit kept so far, by
  counting matching pairs of inputs and of outputs. Its files are read in sorted order (the
  lab walks the folder in directory order). It reads the lab's text dialect with ids, so it
  runs on this set only.

Prints a Markdown table: seconds (best of ``--repeat`` for the first two, one run for the
lab port, which takes minutes), units kept at level 3, and the ratio to the core. Build in
release mode first (``maturin develop --release``)."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

import merge_reference as mref
from foon import _merge

# --- a port of the lab's merge (FOON_classes.py and FOON_graph_analyser.py) -----------------


class Thing:
    def __init__(self, kind: int, label: str) -> None:
        self.kind = kind
        self.label = label
        self.neighbours: list[Thing] = []


class LabObject(Thing):
    def __init__(self, kind: int, label: str) -> None:
        super().__init__(kind, label)
        self.states: list[list[object]] = []
        self.ingredients: list[str] = []
        self.goal = False

    def sort_states(self) -> None:
        self.states.sort(key=lambda x: ((x[2] is not None, x[2]), x[0]))

    def add_state(self, t: list[object]) -> None:
        for s in self.states:
            if s[0] == t[0] and s[1] == t[1] and s[1] and s[2] == t[2]:
                return  # the lab prints a duplicate-state warning here
        self.states.append(list(t))
        self.sort_states()

    def same_states(self, o: LabObject) -> bool:
        self.sort_states()
        o.sort_states()
        count = 0
        for s in self.states:
            for su in o.states:
                if s[0] == su[0] and s[1] == su[1] and s[2] == su[2]:
                    count += 1
        return count == len(o.states) and len(self.states) == len(o.states)

    def same_ingredients(self, o: LabObject) -> bool:
        if len(self.ingredients) != len(o.ingredients):
            return False
        o.ingredients.sort()
        self.ingredients.sort()
        count = 0
        for x in o.ingredients:
            if x in self.ingredients:
                count += 1
        return count == len(self.ingredients)

    def equals(self, o: LabObject, level: int) -> bool:
        if level == 1:
            return self.kind == o.kind
        if level == 2:
            return self.kind == o.kind and self.same_states(o)
        return self.kind == o.kind and self.same_states(o) and self.same_ingredients(o)


class LabMotion(Thing):
    pass


class LabUnit:
    def __init__(self) -> None:
        self.inputs: list[LabObject] = []
        self.outputs: list[LabObject] = []
        self.in_flags: list[int] = []
        self.out_flags: list[int] = []
        self.motion: LabMotion | None = None
        self.times: list[str | None] = [None, None]

    def is_empty(self) -> bool:
        return self.motion is None or not self.inputs or not self.outputs

    def add(self, node: LabObject, is_input: bool, flag: int) -> None:
        if is_input:
            if node not in self.inputs:
                self.inputs.append(node)
                self.in_flags.append(flag)
        elif node not in self.outputs:
            self.outputs.append(node)
            self.out_flags.append(flag)

    def equals(self, u: LabUnit, level: int) -> bool:
        results = 0
        count = 0
        for t in self.inputs:
            for tu in u.inputs:
                if t.equals(tu, level):
                    count += 1
        if count == len(self.inputs) and len(self.inputs) == len(u.inputs):
            results += 1
        assert self.motion is not None and u.motion is not None
        if self.motion.kind == u.motion.kind:
            results += 1
        count = 0
        for t in self.outputs:
            for tu in u.outputs:
                if t.equals(tu, level):
                    count += 1
        if count == len(self.outputs) and len(self.outputs) == len(u.outputs):
            results += 1
        return results == 3


class LabMerge:
    """The lab's universal FOON, merged file by file at the three hierarchy levels."""

    def __init__(self) -> None:
        self.units: dict[int, list[LabUnit]] = {1: [], 2: [], 3: []}
        self.nodes: dict[int, list[Thing]] = {1: [], 2: [], 3: []}
        self.node_count = 0
        self.sources: list[str] = []

    def _unit_exists(self, u: LabUnit, level: int) -> bool:
        return any(f.equals(u, level) for f in self.units[level])

    def _node_exists(self, o: LabObject, level: int) -> int:
        found = -1
        for i, n in enumerate(self.nodes[level]):
            if isinstance(n, LabObject) and n.equals(o, level):
                found = i  # the lab's scan does not stop at the first match
        return found

    def _add_object(self, o: LabObject, is_input: bool, flag: int, fus: list[LabUnit]) -> None:
        existing = self._node_exists(o, 3)
        if existing == -1:
            self.nodes[3].append(o)
            index = self.node_count
            self.node_count += 1
        else:
            index = existing
        node = self.nodes[3][index]
        assert isinstance(node, LabObject)
        fus[3].add(node, is_input, flag)
        if not is_input:
            assert fus[3].motion is not None
            fus[3].motion.neighbours.append(node)
        o2 = LabObject(o.kind, o.label)
        for s in o.states:
            o2.add_state([int(str(s[0])), str(s[1]), s[2]])
        for level, copy in ((2, o2), (1, LabObject(o.kind, o.label))):
            existing = self._node_exists(copy, level)
            if existing == -1:
                index = len(self.nodes[level])
                self.nodes[level].append(copy)
            else:
                index = existing
            node = self.nodes[level][index]
            assert isinstance(node, LabObject)
            fus[level].add(node, is_input, flag)
            if not is_input:
                assert fus[level].motion is not None
                fus[level].motion.neighbours.append(node)

    def load_txt(self, path: Path) -> None:
        is_input = True
        new: LabObject | None = None
        fus = [LabUnit(), LabUnit(), LabUnit(), LabUnit()]  # indexed by level (0 unused)
        object_parts: list[str] = []
        with open(path, encoding="utf-8") as fh:
            items = fh.read().splitlines()
        for line in items:
            if line.startswith("# Source:"):
                self.sources.append(line.split("\t")[1].strip("\n"))
            elif line.startswith("//"):
                if new is not None:
                    self._add_object(new, is_input, int(object_parts[2]), fus)
                if fus[3].is_empty():
                    continue  # as the lab does: the unit being read is kept going
                for level in (3, 2, 1):
                    if not self._unit_exists(fus[level], level):
                        motion = fus[level].motion
                        assert motion is not None
                        self.nodes[level].append(motion)
                        self.units[level].append(fus[level])
                        if level == 3:
                            self.node_count += 1
                fus = [LabUnit(), LabUnit(), LabUnit(), LabUnit()]
                is_input = True
                new = None
            elif line.startswith("O"):
                if new is not None:
                    self._add_object(new, is_input, int(object_parts[2]), fus)
                object_parts = line.split("O")[1].split("\t")
                new = LabObject(int(object_parts[0]), object_parts[1])
                if "!" in line:
                    new.goal = True
            elif line.startswith("S"):
                assert new is not None
                parts = [p for p in line.split("S")[1].split("\t") if p]
                related = None
                ingredients: list[str] = []
                if len(parts) > 2:
                    if "{" in parts[2]:
                        inner = parts[2].split("{")[1].split("}")
                        if inner:
                            ingredients = sorted(inner[0].split(","))
                    elif "[" in parts[2]:
                        related = parts[2].split("[")[1].split("]")[0]
                new.add_state([int(parts[0]), parts[1], related])
                if ingredients:
                    new.ingredients = list(ingredients)
            elif line.startswith("M"):
                if new is not None:
                    self._add_object(new, is_input, int(object_parts[2]), fus)
                new = None
                parts = [p for p in line.split("M")[1].split("\t") if p]
                start = end = None
                if "<" in line or ">" in line:
                    times = parts[2].split("<")[1].split(">")[0].split(",")
                    if len(times) > 1:
                        start, end = times[0], times[1]
                else:
                    start, end = parts[2], parts[3]
                for level in (3, 2, 1):
                    motion = LabMotion(int(parts[0]), parts[1])
                    for t in fus[level].inputs:
                        t.neighbours.append(motion)
                    fus[level].motion = motion
                    if start and end and (start != "Assumed" or end != "Assumed"):
                        fus[level].times = [start, end]
                is_input = False

    def merge(self, folder: Path) -> None:
        for f in sorted(folder.iterdir()):
            if f.is_file():
                self.load_txt(f)


# --- the run ---------------------------------------------------------------------------------


def best(f: object, repeat: int) -> float:
    assert callable(f)
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", type=Path, default=HERE.parent.parent / "shared/data/foon")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument(
        "--lab-files", type=int, default=0, help="run the lab port on the first N files only"
    )
    args = ap.parse_args()
    folder = args.data / "subgraphs_foon_api_FOON-111"
    files = sorted(p for p in folder.iterdir() if p.suffix == ".txt")

    core_kept = _merge.merge(folder).fu_count
    core = best(lambda: _merge.merge(folder), args.repeat)

    def reference() -> int:
        sources = [(str(p), p.read_text(encoding="utf-8")) for p in files]
        return len(mref.merge(sources, 3))

    ref_kept = reference()
    ref_t = best(reference, args.repeat)

    lab = LabMerge()
    t = time.perf_counter()
    if args.lab_files:
        for f in files[: args.lab_files]:
            lab.load_txt(f)
    else:
        lab.merge(folder)
    lab_t = time.perf_counter() - t
    lab_kept = len(lab.units[3])
    lab_what = f"first {args.lab_files} files" if args.lab_files else "all files"

    print(f"Merge of {len(files)} subgraphs ({folder.name}), level 3, one run:\n")
    print("| merge | seconds | units kept | time / core |")
    print("|---|---:|---:|---:|")
    print(f"| foon.merge (Rust core) | {core:.4f} | {core_kept} | 1 |")
    print(f"| pure-Python merge, same semantics | {ref_t:.4f} | {ref_kept} | {ref_t / core:,.0f} |")
    print(
        f"| port of the lab's merge ({lab_what}) | {lab_t:.2f} | {lab_kept} | {lab_t / core:,.0f} |"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
