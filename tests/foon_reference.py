"""A small, slow, plain pure-Python reference for `foon`.

This module restates docs/SEMANTICS.md and docs/METHODS.md as directly as possible, so that the
Rust core can be checked against it. It favours readability over speed: every method is written
the way METHODS.md describes it. The only look-up tables are identity -> id and the producer
lists, built once per parsed file; nothing is cached across calls. Standard library only.

Conventions:
- Object ids and FU indices are the positions in `RefFoon.objects` and `RefFoon.fus`.
- "K" is the set of object ids that are in the kitchen.
- The "needed inputs" of an FU are its inputs after the container rule (METHODS.md, Terms).
- A "bare" output (no state, no ingredient, no container) is never counted as produced.
"""

from __future__ import annotations

import heapq
import json
import math
import re
import sys
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

Identity = tuple[str, tuple[str, ...], tuple[str, ...], str | None]
"""(label, sorted states, sorted ingredients, container)."""

WARNING_KINDS: tuple[str, ...] = ("no-motion", "two-motions", "unterminated")
OPTIMAL_METHODS: tuple[str, ...] = ("optimal-success", "optimal-units", "optimal-inputs")
METHODS: tuple[str, ...] = ("bfs", "ids", "greedy-success", "greedy-inputs", *OPTIMAL_METHODS)

_LINE_KIND = re.compile(r"^[OSM][0-9]*\t")


# --------------------------------------------------------------------------------------------
# Data model
# --------------------------------------------------------------------------------------------


class RefParseError(Exception):
    """A fatal parse error at a 1-based line and column."""

    def __init__(self, line: int, column: int, reason: str) -> None:
        super().__init__(f"line {line}, column {column}: {reason}")
        self.line: int = line
        self.column: int = column
        self.reason: str = reason


@dataclass
class RefObject:
    """One occurrence of an object inside an FU, as written (states in line order)."""

    label: str
    states: list[str] = field(default_factory=list)
    ingredients: list[str] = field(default_factory=list)
    container: str | None = None

    def identity(self) -> Identity:
        return (
            self.label,
            tuple(sorted(self.states)),
            tuple(sorted(self.ingredients)),
            self.container,
        )

    def is_bare(self) -> bool:
        """True for an object with no state, no ingredient and no container."""
        return len(self.states) == 0 and len(self.ingredients) == 0 and self.container is None


@dataclass
class RefFU:
    motion: str
    inputs: list[RefObject] = field(default_factory=list)
    outputs: list[RefObject] = field(default_factory=list)


@dataclass
class RefFoon:
    fus: list[RefFU]
    objects: list[Identity]
    warnings: list[tuple[int, str]]
    # Plain look-up tables, built once from fus and objects (see __post_init__).
    _id_of_identity: dict[Identity, int] = field(init=False, repr=False, compare=False)
    _producers: list[list[int]] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self._id_of_identity = {}
        for index, ident in enumerate(self.objects):
            if ident not in self._id_of_identity:  # the first object, in id order
                self._id_of_identity[ident] = index
        self._producers = [[] for _ in self.objects]
        for f in range(len(self.fus)):
            for o in self.fu_produced(f):
                if f not in self._producers[o]:
                    self._producers[o].append(f)

    def object_id(self, ident: Identity) -> int | None:
        """The first object, in id order, with this identity (None if there is none)."""
        return self._id_of_identity.get(ident)

    def _id_of(self, obj: RefObject) -> int:
        return self._id_of_identity[obj.identity()]

    def fu_inputs(self, f: int) -> list[int]:
        """Ids of all inputs of FU f, in input order (duplicates kept, no container rule)."""
        return [self._id_of(obj) for obj in self.fus[f].inputs]

    def fu_outputs(self, f: int) -> list[int]:
        """Ids of all outputs of FU f as written, in order (bare outputs included)."""
        return [self._id_of(obj) for obj in self.fus[f].outputs]

    def fu_produced(self, f: int) -> list[int]:
        """Ids of the outputs of FU f that count as produced (not bare), in order."""
        return [self._id_of(obj) for obj in self.fus[f].outputs if not obj.is_bare()]

    def producers(self, o: int) -> list[int]:
        """FUs that produce object o (bare outputs excluded), in file order, each once."""
        return list(self._producers[o])


# --------------------------------------------------------------------------------------------
# Parser
# --------------------------------------------------------------------------------------------


def _field_column(raw_fields: list[str], index: int) -> int:
    """1-based column where field `index` starts (fields separated by one TAB each)."""
    column = 1
    for previous in raw_fields[:index]:
        column += len(previous) + 1
    return column


class _Block:
    """The FU being read: everything since the last `//` line."""

    def __init__(self) -> None:
        self.inputs: list[RefObject] = []
        self.outputs: list[RefObject] = []
        self.motion: str | None = None
        self.has_lines: bool = False
        self.second_motion: bool = False
        self.last_object: RefObject | None = None
        self.last_line: int = 0


def _warn(warnings: list[tuple[int, str]], line: int, kind: str, strict: bool) -> None:
    if strict:
        raise RefParseError(line, 1, kind)
    warnings.append((line, kind))


def _close_block(
    block: _Block,
    closing_line: int | None,
    fus: list[RefFU],
    warnings: list[tuple[int, str]],
    strict: bool,
) -> None:
    """Finish a block. closing_line is the line of its `//`, or None at end of file."""
    if not block.has_lines:
        return  # an empty block is ignored silently
    if block.second_motion:
        return  # dropped; the two-motions warning was given at the second M line
    if block.motion is None:
        # The block has object lines (an S line needs an O line before it). An unterminated
        # block without a motion gets the no-motion warning at its last line.
        line = closing_line if closing_line is not None else block.last_line
        _warn(warnings, line, "no-motion", strict)
        return
    if closing_line is None:
        _warn(warnings, block.last_line, "unterminated", strict)
    fus.append(RefFU(motion=block.motion, inputs=block.inputs, outputs=block.outputs))


_Multiset = frozenset[tuple[Identity, int]]  # (identity, number of copies) pairs
_FUKey = tuple[str, _Multiset, _Multiset]


def _fu_key(fu: RefFU) -> _FUKey:
    """Motion, multiset of input identities, multiset of output identities."""
    inputs = frozenset(Counter(obj.identity() for obj in fu.inputs).items())
    outputs = frozenset(Counter(obj.identity() for obj in fu.outputs).items())
    return (fu.motion, inputs, outputs)


def parse(text: str, strict: bool = False) -> RefFoon:
    """Parse FOON text (any of the four dialects of SEMANTICS.md section 1).

    Lines are split on "\n" and lose one trailing "\r". A NUL byte anywhere is an error at its
    column. Blank (whitespace-only) lines and `#` lines are skipped; a `//` line ends the FU.
    Any other line must start with O, S or M, optional digits and a TAB. Trailing empty fields
    are dropped; the second field is lower-cased and right-stripped and must not be empty.
    Objects before the M line are inputs, after it outputs; an S line belongs to the latest O
    line of the FU. Warnings (an error at column 1 when strict): "no-motion" at the closing
    `//` (FU dropped), "two-motions" at the second M line (FU dropped), "unterminated" at the
    last line of a final FU without `//` (kept). Duplicate FUs are then dropped.
    """
    fus_read: list[RefFU] = []
    warnings: list[tuple[int, str]] = []
    block = _Block()

    lines = text.split("\n")
    for line_index, raw_line in enumerate(lines):
        line_number = line_index + 1
        line = raw_line
        line = line.removesuffix("\r")
        if "\x00" in line:
            raise RefParseError(line_number, line.index("\x00") + 1, "NUL byte")
        if line.strip() == "":
            continue
        if line.startswith("#"):
            continue
        if line.startswith("//"):
            _close_block(block, line_number, fus_read, warnings, strict)
            block = _Block()
            continue
        if _LINE_KIND.match(line) is None:
            raise RefParseError(line_number, 1, "unknown line kind")

        kind = line[0]
        raw_fields = line.split("\t")
        fields = list(raw_fields)
        while len(fields) > 0 and fields[-1] == "":
            fields.pop()

        if len(fields) >= 2:
            second = fields[1].lower().rstrip()
        else:
            second = ""
        if second == "":
            what = {"O": "object label", "S": "state", "M": "motion"}[kind]
            raise RefParseError(line_number, _field_column(raw_fields, 1), f"missing {what}")

        block.has_lines = True
        block.last_line = line_number

        if kind == "O":
            obj = RefObject(label=second)
            if block.motion is None:
                block.inputs.append(obj)
            else:
                block.outputs.append(obj)
            block.last_object = obj
        elif kind == "S":
            if block.last_object is None:
                raise RefParseError(line_number, 1, "state before any object")
            target = block.last_object
            if len(fields) >= 3:
                value = fields[2].rstrip()
                column = _field_column(raw_fields, 2)
                if (
                    len(value) >= 2
                    and value.startswith("{")
                    and value.endswith("}")
                    and "{" not in value[1:-1]
                    and "}" not in value[1:-1]
                ):
                    target.ingredients = value[1:-1].split(",")
                elif (
                    len(value) >= 2
                    and value.startswith("[")
                    and value.endswith("]")
                    and "[" not in value[1:-1]
                    and "]" not in value[1:-1]
                ):
                    target.container = value[1:-1]
                else:
                    raise RefParseError(
                        line_number, column, "expected {ingredients} or [container]"
                    )
            else:
                target.states.append(second)
        else:  # kind == "M"
            if block.motion is None:
                block.motion = second
            elif not block.second_motion:
                block.second_motion = True
                _warn(warnings, line_number, "two-motions", strict)

    _close_block(block, None, fus_read, warnings, strict)

    # Drop duplicate FUs (the first copy is kept).
    fus: list[RefFU] = []
    seen_keys: set[_FUKey] = set()
    for fu in fus_read:
        key = _fu_key(fu)
        if key in seen_keys:
            continue
        seen_keys.add(key)
        fus.append(fu)

    # Object ids: first seen, FUs in order, inputs then outputs.
    objects: list[Identity] = []
    known: set[Identity] = set()
    for fu in fus:
        for obj in fu.inputs + fu.outputs:
            ident = obj.identity()
            if ident not in known:
                known.add(ident)
                objects.append(ident)

    return RefFoon(fus=fus, objects=objects, warnings=warnings)


# --------------------------------------------------------------------------------------------
# Writer
# --------------------------------------------------------------------------------------------


def _object_text(obj: RefObject) -> list[str]:
    lines = ["O\t" + obj.label]
    for state in obj.states:
        lines.append("S\t" + state)
    if len(obj.ingredients) > 0:
        lines.append("S\tcontains\t{" + ",".join(obj.ingredients) + "}")
    if obj.container is not None:
        lines.append("S\tin\t[" + obj.container + "]")
    return lines


def fu_text(fu: RefFU) -> str:
    """The course writer: inputs, M line, outputs, `//` (no trailing newline)."""
    lines: list[str] = []
    for obj in fu.inputs:
        lines.extend(_object_text(obj))
    lines.append("M\t" + fu.motion)
    for obj in fu.outputs:
        lines.extend(_object_text(obj))
    lines.append("//")
    return "\n".join(lines)


def course_file(foon: RefFoon, units: list[int]) -> str:
    """A course task-tree file: `//` then each FU, every line ending in a newline."""
    text = "//\n"
    for f in units:
        text += fu_text(foon.fus[f]) + "\n"
    return text


# --------------------------------------------------------------------------------------------
# Kitchen, goals, rates, utensils
# --------------------------------------------------------------------------------------------


def _identity_from_json(item: dict[str, Any]) -> Identity:
    label = item["label"]
    states = item.get("states", [])
    ingredients = item.get("ingredients", [])
    container = item.get("container", None)
    return (label, tuple(sorted(states)), tuple(sorted(ingredients)), container)


def read_kitchen_json(text: str) -> list[Identity]:
    data = json.loads(text)
    return [_identity_from_json(item) for item in data]


def read_goals_json(text: str) -> list[Identity]:
    data = json.loads(text)
    if isinstance(data, dict):
        return [_identity_from_json(data)]
    return [_identity_from_json(item) for item in data]


def read_rates(text: str) -> dict[str, float]:
    rates: dict[str, float] = {}
    for raw_line in text.split("\n"):
        line = raw_line.rstrip("\r")
        if line.strip() == "":
            continue
        parts = line.split("\t")
        rates[parts[0]] = float(parts[1])
    return rates


def read_utensils(text: str) -> set[str]:
    utensils: set[str] = set()
    for raw_line in text.split("\n"):
        name = raw_line.rstrip()
        if name == "":
            continue
        utensils.add(name)
    return utensils


def kitchen_ids(foon: RefFoon, kitchen: list[Identity]) -> set[int]:
    """K: the objects whose identity equals a kitchen item's identity exactly."""
    wanted = set(kitchen)
    return {o for o, ident in enumerate(foon.objects) if ident in wanted}


# --------------------------------------------------------------------------------------------
# Container rule, derivability, ranks, validity, height
# --------------------------------------------------------------------------------------------


def needed_inputs(foon: RefFoon, f: int, utensils: set[str]) -> list[int]:
    """Inputs of FU f minus those skipped by the container rule, in order, duplicates kept."""
    inputs = foon.fus[f].inputs
    result: list[int] = []
    for i, obj in enumerate(inputs):
        skipped = False
        if obj.label in utensils and len(obj.ingredients) == 1:
            held = obj.ingredients[0]
            for j, other in enumerate(inputs):
                if j != i and other.label == held and other.container == obj.label:
                    skipped = True
                    break
        if not skipped:
            result.append(foon._id_of(obj))
    return result


def _ranks_with(
    foon: RefFoon, fu_subset: list[int], kitchen_ids: set[int], utensils: set[str]
) -> tuple[dict[int, int], set[int]]:
    """Layered forward chaining over the FUs of fu_subset.

    Returns (rank of every derivable object, the FUs that can fire). Layer n contains the objects
    that first become available after n parallel steps, which is exactly
    rank(o) = min over producers f of 1 + max(rank of needed inputs of f).
    """
    needed: dict[int, list[int]] = {f: needed_inputs(foon, f, utensils) for f in fu_subset}
    rank: dict[int, int] = {o: 0 for o in kitchen_ids}
    fired: set[int] = set()
    step = 0
    while True:
        step += 1
        newly_fired: list[int] = []
        for f in fu_subset:
            if f in fired:
                continue
            if all(x in rank for x in needed[f]):
                newly_fired.append(f)
        if len(newly_fired) == 0:
            break
        for f in newly_fired:
            fired.add(f)
            for o in foon.fu_produced(f):
                if o not in rank:
                    rank[o] = step
    return rank, fired


def derivable(foon: RefFoon, kitchen_ids: set[int], utensils: set[str]) -> set[int]:
    """The least fixpoint of: o in K, or o has a producer whose needed inputs are derivable."""
    rank, _ = _ranks_with(foon, list(range(len(foon.fus))), kitchen_ids, utensils)
    return set(rank)


def ranks(foon: RefFoon, kitchen_ids: set[int], utensils: set[str]) -> dict[int, int]:
    """rank(o) for every derivable object o."""
    rank, _ = _ranks_with(foon, list(range(len(foon.fus))), kitchen_ids, utensils)
    return rank


def is_valid(
    foon: RefFoon, units: list[int], goal_id: int, kitchen_ids: set[int], utensils: set[str]
) -> bool:
    """Set semantics: some order of the FUs executes all of them and makes the goal."""
    subset = sorted(set(units))
    rank, fired = _ranks_with(foon, subset, kitchen_ids, utensils)
    return len(fired) == len(subset) and goal_id in rank


def height(
    foon: RefFoon, units: list[int], goal_id: int, kitchen_ids: set[int], utensils: set[str]
) -> int | None:
    """Rank of the goal from K using only the tree's FUs (None if they cannot make it)."""
    subset = sorted(set(units))
    rank, _ = _ranks_with(foon, subset, kitchen_ids, utensils)
    return rank.get(goal_id)


# --------------------------------------------------------------------------------------------
# Failure explanation
# --------------------------------------------------------------------------------------------


def knuth(
    foon: RefFoon,
    base: set[int],
    utensils: set[str],
    leaf: float,
    weight: Callable[[int], float],
) -> tuple[dict[int, float], dict[int, int]]:
    """Knuth's generalisation of Dijkstra: cost(o) = leaf on `base`, else min over producers f
    of weight(f) + the costs of f's needed inputs (added in input order). Returns the final
    cost of every object reached with a finite cost, and the choice (an FU index) of every such
    object outside base.

    Ties: every object also has a depth (0 on `base`); a unit offers its cost and, as its
    depth, one more than the largest depth of a needed input that costs exactly as much as
    the unit (a step that leaves the cost unchanged), 0 when every input costs less. Objects
    are finalised in (cost, depth, id) order. An FU is evaluated once, when all its needed
    inputs are final; it sets the (cost, depth) of an output that is not final and not in base
    when it is lower, or equal with a lower FU index. A unit's (cost, depth) is above each of
    its inputs', so the choice of an object is the lowest-index producer whose (cost, depth)
    is the object's, whatever the order of equal-cost objects. An FU of infinite cost (a
    motion of rate 0) never sets anything.
    """
    needed: list[list[int]] = [needed_inputs(foon, f, utensils) for f in range(len(foon.fus))]
    users: dict[int, list[int]] = {}  # object -> FUs that need it
    for f in range(len(foon.fus)):
        for x in needed[f]:
            users.setdefault(x, [])
            if f not in users[x]:
                users[x].append(f)

    cost: dict[int, float] = {o: leaf for o in base}
    depth: dict[int, int] = {o: 0 for o in base}
    choice: dict[int, int] = {}
    final: set[int] = set()
    evaluated: set[int] = set()
    heap: list[tuple[float, int, int]] = [(leaf, 0, o) for o in base]
    heapq.heapify(heap)

    def evaluate(f: int) -> None:
        evaluated.add(f)
        total = weight(f)
        for x in needed[f]:
            total += cost[x]
        if total == math.inf:
            return
        d = max((depth[x] + 1 for x in needed[f] if cost[x] == total), default=0)
        for o in foon.fu_produced(f):
            if o in base or o in final:
                continue
            if (
                o not in cost
                or (total, d) < (cost[o], depth[o])
                or ((total, d) == (cost[o], depth[o]) and f < choice[o])
            ):
                cost[o] = total
                depth[o] = d
                choice[o] = f
                heapq.heappush(heap, (total, d, o))

    for f in range(len(foon.fus)):
        if len(needed[f]) == 0:
            evaluate(f)

    while len(heap) > 0:
        c, d, o = heapq.heappop(heap)
        if o in final or (c, d) != (cost[o], depth[o]):
            continue
        final.add(o)
        for f in users.get(o, []):
            if f not in evaluated and all(x in final for x in needed[f]):
                evaluate(f)
    return cost, choice


def _optimal_inputs_choices(foon: RefFoon, base: set[int], utensils: set[str]) -> dict[int, int]:
    """The choices of Knuth's algorithm with cost 1 on `base` and FUs of weight 0."""
    return knuth(foon, base, utensils, 1.0, lambda f: 0.0)[1]


def optimal_costs(
    foon: RefFoon,
    k: set[int],
    utensils: set[str],
    rates: dict[str, float] | None,
    method: str,
) -> tuple[dict[int, float], dict[int, int]]:
    """Knuth's algorithm from K for an optimal method (METHODS.md): FU weight -ln(rate), 1 or
    0, leaf cost 0, 0 or 1 for optimal-success, -units and -inputs."""
    if method == "optimal-success":

        def success_weight(f: int) -> float:
            rate = _rate(rates, foon.fus[f].motion)
            return math.inf if rate == 0 else -math.log(rate)

        return knuth(foon, k, utensils, 0.0, success_weight)
    if method == "optimal-units":
        return knuth(foon, k, utensils, 0.0, lambda f: 1.0)
    if method == "optimal-inputs":
        return knuth(foon, k, utensils, 1.0, lambda f: 0.0)
    raise ValueError(f"not an optimal method: {method}")


def explain(
    foon: RefFoon, goal_id: int, kitchen_ids: set[int], utensils: set[str]
) -> tuple[list[int], list[int]]:
    """(missing raw items in id order, cycle objects) for a goal that is not derivable from K.

    K' = K plus every object without a producer. If the goal is derivable from K', the missing
    items are the leaves outside K of the optimal-inputs tree from K' and the cycle is empty.
    Otherwise there are no missing items and the cycle is found by walking from the goal: take
    the first producer and its first needed input not derivable from K', until an object repeats;
    the cycle is the walk from the first visit of that object to just before it repeats.
    A goal derivable from K gives ([], []).
    """
    if goal_id in derivable(foon, kitchen_ids, utensils):
        return ([], [])
    extended: set[int] = set(kitchen_ids)
    for o in range(len(foon.objects)):
        if len(foon.producers(o)) == 0:
            extended.add(o)
    from_extended = derivable(foon, extended, utensils)

    if goal_id in from_extended:
        choice = _optimal_inputs_choices(foon, extended, utensils)
        missing: set[int] = set()
        seen: set[int] = set()
        stack: list[int] = [goal_id]
        while len(stack) > 0:
            o = stack.pop()
            if o in seen:
                continue
            seen.add(o)
            if o in extended:
                if o not in kitchen_ids:
                    missing.add(o)
                continue
            stack.extend(needed_inputs(foon, choice[o], utensils))
        return (sorted(missing), [])

    walk: list[int] = []
    o = goal_id
    while o not in walk:
        walk.append(o)
        first_producer = foon.producers(o)[0]
        next_object: int | None = None
        for x in needed_inputs(foon, first_producer, utensils):
            if x not in from_extended:
                next_object = x
                break
        assert next_object is not None, "a non-derivable object has a blocked input"
        o = next_object
    start = walk.index(o)
    return ([], walk[start:])


# --------------------------------------------------------------------------------------------
# Planning
# --------------------------------------------------------------------------------------------


@dataclass
class RefResult:
    solved: bool
    units: list[int]  # in output order
    unresolved: list[int]
    height: int | None
    cost: float | None = None  # optimal methods: the optimum (a success probability for -success)


def _rate(rates: dict[str, float] | None, motion: str) -> float:
    if rates is None or motion not in rates:
        raise KeyError(motion)
    return rates[motion]


def _ingredient_count(fu: RefFU) -> int:
    labels: set[str] = set()
    for obj in fu.inputs:
        if len(obj.ingredients) > 0:
            for ingredient in obj.ingredients:
                labels.add(ingredient)
        else:
            labels.add(obj.label)
    return len(labels)


def _heuristic_order(
    foon: RefFoon,
    candidates: list[int],
    method: str,
    rates: dict[str, float] | None,
    count: str,
) -> list[int]:
    """Candidate FUs best first; ties go to the lowest FU index."""
    if method == "greedy-success":
        keyed_success: list[tuple[float, int]] = []
        for f in candidates:
            keyed_success.append((-_rate(rates, foon.fus[f].motion), f))
        return [f for _, f in sorted(keyed_success)]
    if method == "greedy-inputs":
        keyed_inputs: list[tuple[int, int]] = []
        for f in candidates:
            if count == "nodes":
                size = len(foon.fus[f].inputs)
            elif count == "ingredients":
                size = _ingredient_count(foon.fus[f])
            else:
                raise ValueError(f"unknown count: {count}")
            keyed_inputs.append((size, f))
        return [f for _, f in sorted(keyed_inputs)]
    raise ValueError(f"no heuristic for method {method}")


def _course_plan(
    foon: RefFoon,
    goal_id: int,
    k: set[int],
    utensils: set[str],
    rates: dict[str, float] | None,
    method: str,
    count: str,
) -> RefResult:
    """The course loop of METHODS.md."""
    queue: list[int] = [goal_id]
    visited: set[int] = set()
    tree: list[int] = []
    unresolved: list[int] = []
    while len(queue) > 0:
        o = queue.pop(0)
        if o in visited:
            continue
        visited.add(o)
        if o in k:
            continue
        candidates = foon.producers(o)
        if len(candidates) == 0:
            unresolved.append(o)
            continue
        if method in ("bfs", "ids"):
            f = candidates[0]
        else:
            f = _heuristic_order(foon, candidates, method, rates, count)[0]
        if f in tree:
            continue
        tree.append(f)
        for x in needed_inputs(foon, f, utensils):
            if x not in queue:
                queue.append(x)
    units = list(reversed(tree))
    return RefResult(
        solved=len(unresolved) == 0,
        units=units,
        unresolved=unresolved,
        height=height(foon, units, goal_id, k, utensils),
    )


def _emit_tree(
    foon: RefFoon, goal_id: int, k: set[int], choice: dict[int, int], utensils: set[str]
) -> list[int]:
    """The closure of the choices from the goal, in depth-first post-order."""
    seen: set[int] = set()
    emitted: list[int] = []

    def emit(o: int) -> None:
        if o in k or o in seen:
            return
        seen.add(o)
        f = choice[o]
        if f in emitted:
            return
        for x in needed_inputs(foon, f, utensils):
            emit(x)
        if f not in emitted:
            emitted.append(f)

    emit(goal_id)
    return emitted


def _ids_choices(
    foon: RefFoon, k: set[int], utensils: set[str], rank: dict[int, int]
) -> dict[int, int]:
    """choice(o) = lowest-index producer f with 1 + max(rank of needed inputs) = rank(o).

    METHODS.md defines `ids` as iterative deepening whose depth-limited search returns rank(o)
    exactly; the tree it returns is made of these choices, so the reference uses ranks directly.
    """
    choice: dict[int, int] = {}
    for o, r in rank.items():
        if o in k:
            continue
        for f in foon.producers(o):
            needed = needed_inputs(foon, f, utensils)
            if not all(x in rank for x in needed):
                continue
            level = 1 + max((rank[x] for x in needed), default=0)
            if level == r:
                choice[o] = f
                break
    return choice


def _greedy_choices(
    foon: RefFoon,
    goal_id: int,
    k: set[int],
    utensils: set[str],
    rates: dict[str, float] | None,
    method: str,
    count: str,
    can_derive: set[int],
) -> tuple[bool, dict[int, int]]:
    """The depth-first resolution of METHODS.md; returns (goal resolved, choices)."""
    choice: dict[int, int] = {}

    def resolve(o: int, path: list[int]) -> bool:
        if o in k or o in choice:
            return True
        if o not in can_derive:
            return False
        for f in _heuristic_order(foon, foon.producers(o), method, rates, count):
            needed = needed_inputs(foon, f, utensils)
            if any(x == o or x in path for x in needed):
                continue
            failed = False
            for x in needed:
                if not resolve(x, [*path, o]):
                    failed = True
                    break
            if not failed:
                choice[o] = f
                return True
        return False

    return resolve(goal_id, []), choice


def plan(
    foon: RefFoon,
    goal: Identity,
    kitchen: list[Identity],
    utensils: set[str],
    rates: dict[str, float] | None,
    method: str,
    compat: str | None = None,
    count: str = "nodes",
) -> RefResult:
    """Plan a task tree for `goal`.

    method: one of METHODS; compat None (sound) or "course". "bfs" is course-only (compat is
    ignored); the optimal methods are sound-only (compat "course" raises ValueError). A missing
    rate raises KeyError(motion).
    A sound failure returns solved=False, no units, and as `unresolved` the missing items of
    explain(), or the cycle objects when the goal is blocked only by a cycle. An optimal-success
    goal that is derivable but only through motions of rate 0 fails with nothing unresolved.
    """
    if method not in METHODS:
        raise ValueError(f"unknown method: {method}")
    if compat not in (None, "course"):
        raise ValueError(f"unknown compat: {compat}")
    if count not in ("nodes", "ingredients"):
        raise ValueError(f"unknown count: {count}")
    if method in OPTIMAL_METHODS and compat is not None:
        raise ValueError(f"method {method} has no course-compatible form")
    goal_id = foon.object_id(goal)
    if goal_id is None:
        raise ValueError("The goal node does not exist")
    k = kitchen_ids(foon, kitchen)

    old_limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(old_limit, 10 * len(foon.objects) + 1000))
    try:
        if method == "bfs" or compat == "course":
            return _course_plan(foon, goal_id, k, utensils, rates, method, count)

        if goal_id in k:
            if method in OPTIMAL_METHODS:
                # Nothing to do: success 1, no unit, the goal itself as the one kitchen input.
                empty_cost = 0.0 if method == "optimal-units" else 1.0
                return RefResult(solved=True, units=[], unresolved=[], height=0, cost=empty_cost)
            return RefResult(solved=True, units=[], unresolved=[], height=0)
        rank = ranks(foon, k, utensils)
        if goal_id not in rank:
            missing, cycle = explain(foon, goal_id, k, utensils)
            return RefResult(
                solved=False,
                units=[],
                unresolved=missing if len(missing) > 0 else cycle,
                height=None,
            )
        optimum: float | None = None
        if method in OPTIMAL_METHODS:
            cost, choice = optimal_costs(foon, k, utensils, rates, method)
            if goal_id not in cost:
                return RefResult(solved=False, units=[], unresolved=[], height=None)
            optimum = math.exp(-cost[goal_id]) if method == "optimal-success" else cost[goal_id]
        elif method == "ids":
            choice = _ids_choices(foon, k, utensils, rank)
        else:
            resolved, choice = _greedy_choices(
                foon, goal_id, k, utensils, rates, method, count, set(rank)
            )
            assert resolved, "a derivable goal always resolves"
        units = _emit_tree(foon, goal_id, k, choice, utensils)
        return RefResult(
            solved=True,
            units=units,
            unresolved=[],
            height=height(foon, units, goal_id, k, utensils),
            cost=optimum,
        )
    finally:
        sys.setrecursionlimit(old_limit)
