"""PDDL output: parsed with the ``pddl`` package and solved by real planners (pyperplan for
problems without costs, Fast Downward from ``up-fast-downward`` with an optimal
configuration for problems with action costs).

What is checked (the rules are in rust/foon-core/src/write/pddl.rs):
- the text is a domain, the line ``;; ---- problem ----``, a problem; both parse;
- a FOON problem has one action per unit of the goal's ancestry (recomputed here with the
  reference implementation: producers of every needed object not in the kitchen, backwards
  from the goal, leaving out units that can never run), a tree problem one per unit of the
  tree; preconditions are the needed inputs, effects the made outputs, nothing deleted, the
  initial state the kitchen items the problem mentions, the goal the goal, action costs
  ``round(-ln(rate) * cost_scale)``; names are valid, unique PDDL names;
- on the course data, the planner's plan mapped back to unit indices is an executable task
  tree (Planner.check_tree, and ``foon verify`` on the written tree text), in the planner's
  order; a FOON problem is solvable exactly when optimal-success solves the goal, a tree
  problem exactly when the tree is valid;
- with costs, the cheapest plan never costs more than the optimal-success tree (the tree's
  units are one plan), and costs the same when that tree shares no sub-goal. They can differ
  otherwise: a tree counts a shared sub-goal once for each unit that uses it (the tree cost
  of SEMANTICS.md), a plan makes it once, so the cheapest plan can share a sub-goal that the
  cheapest tree avoids (on the course data several goals show this);
- generated FOONs (hypothesis): every problem parses, the planner solves it exactly when the
  goal is derivable (without costs) or when optimal-success solves it (with costs), and its
  plan is an executable tree.

The planner packages are test extras: a test that needs one skips when it is missing, and
fails when the CI environment variable is set.
"""

from __future__ import annotations

import importlib
import importlib.util
import json
import math
import os
import re
import subprocess
import sys
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import foon
import foon._foon as native
import foon_reference as ref
import pytest
from conftest import DATA
from foon.cli import main
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_differential import Course, GenFoon, draw_case, gen_foons, load_course

PROBLEM_LINE = ";; ---- problem ----"
NAME = re.compile(r"^[a-z][a-z0-9-]*$")
PDDL_WORDS = {"and", "or", "not", "imply", "exists", "forall", "when", "either", "increase",
              "decrease", "assign", "object", "number", "total-cost", "at", "start", "end",
              "define", "domain", "problem", "minimize", "maximize"}  # fmt: skip
SCALE = 1000  # Options::cost_scale's default


def need(what: str) -> None:
    """Skips (fails under CI) for a missing test extra."""
    msg = f"{what} is not installed (pip install {what}); it is a test extra"
    if os.environ.get("CI"):
        pytest.fail(f"CI is set but {msg}")
    pytest.skip(msg)


_PARSERS: list[Any] = []


def pddl_parsers() -> tuple[Any, Any]:
    """The pddl package's domain and problem parsers (made once: making one takes longer
    than parsing a problem)."""
    if not _PARSERS:
        try:
            domain = importlib.import_module("pddl.parser.domain")
            problem = importlib.import_module("pddl.parser.problem")
        except ImportError:
            need("pddl")
        _PARSERS.extend((domain.DomainParser(), problem.ProblemParser()))
    return _PARSERS[0], _PARSERS[1]


def fast_downward() -> Path:
    """The Fast Downward driver that up-fast-downward ships (run directly: the package's own
    module needs unified-planning, which these tests do not)."""
    spec = importlib.util.find_spec("up_fast_downward")
    if spec is None or not spec.submodule_search_locations:
        need("up-fast-downward")
    for loc in spec.submodule_search_locations:
        driver = Path(loc) / "downward" / "fast-downward.py"
        if driver.is_file():
            return driver
    need("up-fast-downward")
    raise AssertionError  # unreachable: need() skips or fails


def pyperplan() -> Any:
    try:
        return importlib.import_module("pyperplan.planner")
    except ImportError:
        need("pyperplan")


# --- reading what was written ---------------------------------------------------------------


def split(text: str) -> tuple[str, str]:
    lines = text.splitlines(keepends=True)
    at = [i for i, line in enumerate(lines) if line.rstrip("\n") == PROBLEM_LINE]
    assert len(at) == 1, "exactly one problem line"
    return "".join(lines[: at[0]]), "".join(lines[at[0] + 1 :])


@dataclass
class Action:
    fu: int
    pre: set[str]
    eff: set[str]
    cost: int | None


@dataclass
class Written:
    """A written problem, parsed by the pddl package and read back."""

    domain_file: Path
    problem_file: Path
    predicates: list[str]  # in the order written
    actions: dict[int, Action]
    init: set[str]
    goal: set[str]
    costs: bool


def _atoms(formula: Any) -> Iterator[Any]:
    name = type(formula).__name__
    if name == "Predicate":
        yield formula
    elif name == "And":
        for op in formula.operands:
            yield from _atoms(op)


def read(text: str, where: Path) -> Written:
    """Writes the two files into ``where`` and parses them with the pddl package."""
    parse_domain, parse_problem = pddl_parsers()
    dom, prob = split(text)
    where.mkdir(parents=True, exist_ok=True)
    df, pf = where / "domain.pddl", where / "problem.pddl"
    df.write_text(dom, encoding="utf-8")
    pf.write_text(prob, encoding="utf-8")
    d = parse_domain(dom)
    p = parse_problem(prob)
    assert p.domain_name == d.name == "foon"
    predicates = re.findall(r"^    \(([^)\s]*)\) ; ", dom, flags=re.MULTILINE)
    assert sorted(predicates) == sorted(x.name for x in d.predicates)
    assert len(set(predicates)) == len(predicates), "names are unique"
    for n in predicates:
        assert NAME.match(n) and n not in PDDL_WORDS, n
    actions = {}
    for a in d.actions:
        m = re.fullmatch(r"fu(\d+)(-[a-z0-9-]+)?", a.name)
        assert m, a.name
        assert not a.parameters
        effects = list(a.effect.operands) if type(a.effect).__name__ == "And" else [a.effect]
        assert all(type(e).__name__ in ("Predicate", "Increase") for e in effects), "add only"
        costs = [int(e.operands[1].value) for e in effects if type(e).__name__ == "Increase"]
        actions[int(m.group(1))] = Action(
            int(m.group(1)),
            {x.name for x in _atoms(a.precondition)},
            {x.name for x in _atoms(a.effect)},
            costs[0] if costs else None,
        )
    costs = any("action-costs" in str(r) for r in d.requirements)
    assert all((a.cost is not None) == costs for a in actions.values())
    assert (p.metric is not None) == costs
    init = {x.name for x in p.init if type(x).__name__ == "Predicate"}
    return Written(df, pf, predicates, actions, init, {x.name for x in _atoms(p.goal)}, costs)


# --- planners ---------------------------------------------------------------------------------


@dataclass
class Solution:
    units: list[int]
    cost: int | None


def solve_fd(w: Written, where: Path) -> Solution | None:
    """Fast Downward, optimal (A* with LM-cut); None when it proves the problem unsolvable."""
    driver = fast_downward()
    plan = where / "plan.txt"
    plan.unlink(missing_ok=True)
    r = subprocess.run(
        [sys.executable, str(driver), "--plan-file", str(plan), "--alias", "seq-opt-lmcut",
         str(w.domain_file), str(w.problem_file)],
        cwd=where, capture_output=True, text=True, check=False,
    )  # fmt: skip
    if r.returncode in (11, 12):  # unsolvable (proved by the translator or the search)
        return None
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    text = plan.read_text()
    units = [int(u) for u in re.findall(r"^\(fu(\d+)\b", text, flags=re.MULTILINE)]
    m = re.search(r"; cost = (\d+)", text)
    return Solution(units, int(m.group(1)) if m and w.costs else None)


def solve_pyperplan(w: Written) -> Solution | None:
    """pyperplan (greedy best-first with h_FF; no costs)."""
    pp = pyperplan()
    plan = pp.search_plan(str(w.domain_file), str(w.problem_file), pp.SEARCHES["gbf"],
                          pp.HEURISTICS["hff"])  # fmt: skip
    if plan is None:
        return None
    units = [int(re.fullmatch(r"\(fu(\d+)[^)]*\)", op.name).group(1)) for op in plan]  # type: ignore[union-attr]
    return Solution(units, None)


# --- what the problem must be -------------------------------------------------------------------


class Ref:
    """The reference's view of one FOON with a kitchen and utensils."""

    def __init__(self, rf: ref.RefFoon, kitchen: Sequence[ref.Identity], utensils: set[str]):
        self.rf = rf
        self.k = ref.kitchen_ids(rf, list(kitchen))
        self.needed = [ref.needed_inputs(rf, i, utensils) for i in range(len(rf.fus))]
        self.der = ref.derivable(rf, self.k, utensils)

    def ancestry(self, goal: int, allowed: set[int] | None = None) -> set[int]:
        out: set[int] = set()
        seen, todo = {goal}, [goal]
        while todo:
            o = todo.pop()
            if o in self.k:
                continue
            for f in self.rf.producers(o):
                if f in out or (allowed is not None and f not in allowed):
                    continue
                if not all(x in self.der for x in self.needed[f]):
                    continue
                out.add(f)
                for x in self.needed[f]:
                    if x not in seen:
                        seen.add(x)
                        todo.append(x)
        return out

    def check(self, w: Written, goal: int, units: set[int], rates: dict[str, float] | None) -> None:
        """The written problem is the one of making ``goal`` with ``units``."""
        rf = self.rf
        if rates is not None:
            assert w.costs
            units = {u for u in units if rates[rf.fus[u].motion] > 0}
        assert set(w.actions) == units
        mentioned = {goal}
        for u in units:
            mentioned.update(self.needed[u], rf.fu_produced(u))
        assert len(w.predicates) == len(mentioned)
        name = dict(zip(sorted(mentioned), w.predicates, strict=True))  # id order
        for u in units:
            a = w.actions[u]
            assert a.pre == {name[x] for x in self.needed[u]}, u
            assert a.eff == {name[x] for x in rf.fu_produced(u)}, u
            if rates is not None:
                assert a.cost == round(-math.log(rates[rf.fus[u].motion]) * SCALE), u
        assert w.init == {name[o] for o in mentioned if o in self.k}
        assert w.goal == {name[goal]}


def foon_problem(f: foon.Foon, planner: foon.Planner, goal: int, **kw: Any) -> str:
    return native.write_foon(f._native, "pddl", focus=goal, planner=planner._native,
                             **kw).decode()  # fmt: skip


def executable(planner: foon.Planner, units: list[int], goal: int) -> bool:
    """Valid, and runnable in the order given."""
    valid, _, first_blocked = planner._native.check_tree(units, goal)
    return bool(valid) and first_blocked is None


def tree_cost(w: Written, units: Sequence[int]) -> int:
    return sum(w.actions[u].cost or 0 for u in units)


def shares_no_subgoal(t: foon.TaskTree) -> bool:
    """The tree cost (with multiplicity, reported as the probability exp(-cost)) equals the
    cost of its distinct units (their product of rates): nothing is used twice."""
    assert t.cost is not None and t.success is not None
    return t.cost > 0 and math.isclose(t.cost, t.success, rel_tol=1e-9)


# --- the course data --------------------------------------------------------------------------


@pytest.fixture(scope="module")
def course() -> Course:
    return load_course()


@pytest.fixture(scope="module")
def cref(course: Course) -> Ref:
    return Ref(course.ref, course.kitchen, course.utensils)


#: Planner runs are on the goals whose problem has at most this many actions (15 of the 25).
SMALL = 60


def small_goals(c: Course, r: Ref) -> list[foon.Object]:
    return [g for g in c.rgoals if len(r.ancestry(c.foon.goal_id(g))) <= SMALL]


def rated(c: Course) -> foon.Planner:
    return c.foon.planner(c.rkitchen, motions=c.rmotions, utensils=c.rutensils)


def unrated(c: Course) -> foon.Planner:
    return c.foon.planner(c.rkitchen, utensils=c.rutensils)


def test_course_problems_are_the_goals_ancestry(course: Course, cref: Ref, tmp_path: Path) -> None:
    f, p = course.foon, rated(course)
    sizes = []
    for i, g in enumerate(course.rgoals):
        gid = f.goal_id(g)
        text = foon_problem(f, p, gid)
        assert text == foon_problem(f, p, gid), "deterministic"
        w = read(text, tmp_path / str(i))
        units = cref.ancestry(gid)
        cref.check(w, gid, units, course.rates)
        sizes.append(len(units))
        if len(units) <= SMALL:  # without rates: the same actions, no costs
            w0 = read(foon_problem(f, unrated(course), gid), tmp_path / f"{i}-plain")
            cref.check(w0, gid, units, None)
            assert not w0.costs
    assert max(sizes) > 100 and min(sizes) == 0  # whipped cream and fried rice: nothing runs


def test_course_plans_are_executable_trees_costing_what_optimal_success_trees_cost(
    course: Course, cref: Ref, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    f, p = course.foon, rated(course)
    cheaper, unshared, by_cli = 0, 0, False
    goals = small_goals(course, cref)
    assert any(not p.plan(g, "optimal-success").solved for g in goals)
    for i, g in enumerate(goals):
        gid = f.goal_id(g)
        where = tmp_path / str(i)
        w = read(foon_problem(f, p, gid), where)
        sol = solve_fd(w, where)
        t = p.plan(g, "optimal-success")
        assert (sol is not None) == t.solved, g.label
        if sol is None:
            continue
        assert executable(p, sol.units, gid), g.label
        # The plan as a task-tree file passes `foon verify`.
        tree_file = where / "tree.txt"
        tree_file.write_text(f._native.tree_text(sol.units))
        assert f.verify(tree_file, g, course.rkitchen, course.rutensils).valid
        if not by_cli:  # once through the command line, as a user runs it
            by_cli = True
            argv = ["verify", "--foon", str(DATA / "FOON.txt"), "--kitchen",
                    str(DATA / "kitchen.json"), "--utensils", str(DATA / "utensils.txt"),
                    "--goal", json.dumps(g.to_dict()), str(tree_file)]  # fmt: skip
            assert main(argv) == 0, g.label
        assert sol.cost == tree_cost(w, sol.units)
        assert set(t.units) <= set(w.actions)
        tree = tree_cost(w, t.units)
        assert sol.cost is not None and sol.cost <= tree, g.label
        if shares_no_subgoal(t):
            assert sol.cost == tree, g.label
            unshared += 1
        cheaper += sol.cost < tree
    capsys.readouterr()
    # The test reaches both: trees that share nothing, and plans that make a shared
    # sub-goal once where the tree makes it for each use.
    assert unshared > 0 and cheaper > 0


@pytest.mark.parametrize(("method", "compat"), [("ids", None), ("bfs", "course")])
def test_course_tree_problems_without_costs(
    course: Course, cref: Ref, tmp_path: Path, method: str, compat: str | None
) -> None:
    """A tree problem's actions are the tree's units; pyperplan solves it exactly when the
    tree is valid (the course's bfs trees of whipped cream and fried rice are circular)."""
    p = unrated(course)
    invalid = 0
    for i, t in enumerate(p.plan_many(course.rgoals, method, compat=compat)):  # type: ignore[arg-type]
        text = str(t.write("pddl"))
        w = read(text, tmp_path / str(i))
        cref.check(w, t.goal_id, set(t.units), None)
        sol = solve_pyperplan(w)
        valid = t.is_valid()
        assert (sol is not None) == valid, t.goal.label
        invalid += not valid
        if sol is not None:
            assert set(sol.units) <= set(t.units)
            assert executable(p, sol.units, t.goal_id)
        if not t.solved:
            assert "; the tree is not a solution" in text
    assert 0 < invalid < len(course.rgoals)  # both outcomes are reached


def test_course_tree_problems_with_costs(course: Course, cref: Ref, tmp_path: Path) -> None:
    """An optimal-success tree's problem: Fast Downward orders (a subset of) its units at no
    more than the tree's cost."""
    p = rated(course)
    for i, t in enumerate(p.plan_many(small_goals(course, cref), "optimal-success")):
        if not t.solved:
            continue
        where = tmp_path / str(i)
        w = read(str(t.write("pddl")), where)
        cref.check(w, t.goal_id, set(t.units), course.rates)
        sol = solve_fd(w, where)
        assert sol is not None and sol.cost is not None
        assert set(sol.units) <= set(t.units) and executable(p, sol.units, t.goal_id)
        assert sol.cost <= tree_cost(w, t.units)
        if shares_no_subgoal(t):
            assert sol.cost == tree_cost(w, t.units)


def test_course_goal_problems_without_costs_pyperplan(
    course: Course, cref: Ref, tmp_path: Path
) -> None:
    f, p = course.foon, unrated(course)
    ranks = p.ranks()
    for i, g in enumerate(small_goals(course, cref)):
        gid = f.goal_id(g)
        w = read(foon_problem(f, p, gid), tmp_path / str(i))
        sol = solve_pyperplan(w)
        assert (sol is not None) == (ranks[gid] is not None), g.label
        if sol is not None:
            assert executable(p, sol.units, gid), g.label


# --- options and errors ---------------------------------------------------------------------


def example() -> tuple[foon.Foon, foon.Planner, foon.Object]:
    ex = foon.example()
    return (
        ex.foon,
        ex.foon.planner(ex.kitchen, motions=ex.motions, utensils=ex.utensils),
        ex.goals[0],
    )


def test_one_goal_a_document() -> None:
    with pytest.raises(
        ValueError, match=r"^PDDL holds one goal's problem: give one goal or --out DIR$"
    ):
        native.TreeWriter("pddl", True)
    _, p, g = example()
    w = native.TreeWriter("pddl", False)
    assert w.begin() == b""
    with pytest.raises(ValueError, match=r"^no PDDL problem for caviar: not in the FOON$"):
        w.failed(("caviar", [], [], None), True, "ids", "not in the FOON")
    t = p.plan(g)
    w = native.TreeWriter("pddl", False)
    assert w.tree(p._native, t._plan) == str(t.write("pddl")).encode()
    with pytest.raises(ValueError, match="holds one task tree"):
        w.tree(p._native, t._plan)


def test_a_foon_problem_needs_a_goal_and_a_kitchen() -> None:
    f, p, g = example()
    with pytest.raises(ValueError, match=r"needs a goal: give one \(--goal\)"):
        f.write("pddl", kitchen=p.kitchen)
    with pytest.raises(ValueError, match=r"needs a kitchen for its initial state: give one"):
        f.write("pddl", goal=g)
    text = str(f.write("pddl", goal=g, kitchen=p.kitchen, utensils=p.utensils))
    assert text == foon_problem(f, f.planner(p.kitchen, utensils=p.utensils), f.goal_id(g))


def test_missing_rates_and_the_cost_scale(tmp_path: Path) -> None:
    f, p, g = example()
    gid = f.goal_id(g)
    assert p.motions is not None
    r = Ref(ref.parse(f.to_text()), [o.identity() for o in p.kitchen], set(p.utensils))
    units = sorted(r.ancestry(gid))
    gone = f.fu(units[0]).motion
    motions = {m: v for m, v in p.motions.items() if m != gone}
    partial = f.planner(p.kitchen, motions=motions, utensils=p.utensils)
    with pytest.raises(foon.MissingRateError, match=re.escape(gone)):
        foon_problem(f, partial, gid)
    # A default rate fills it.
    filled = f.planner(p.kitchen, motions=motions, utensils=p.utensils, default_rate=0.5)
    w = read(foon_problem(f, filled, gid), tmp_path / "filled")
    assert w.actions[units[0]].cost == round(-math.log(0.5) * SCALE)
    scaled = read(foon_problem(f, p, gid, cost_scale=10), tmp_path / "10")
    full = read(foon_problem(f, p, gid), tmp_path / "1000")
    assert set(scaled.actions) == set(full.actions) == set(units)
    for u, a in full.actions.items():
        rate = p.motions[f.fu(u).motion]
        assert a.cost == round(-math.log(rate) * SCALE)
        assert scaled.actions[u].cost == round(-math.log(rate) * 10)
    none = foon_problem(f, p, gid, cost_scale=0)
    assert "total-cost" not in none and ":action-costs" not in none
    assert set(read(none, tmp_path / "0").actions) == set(units)


def test_a_motion_that_never_succeeds_is_left_out(tmp_path: Path) -> None:
    text = (
        "O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n"
        "O\tegg\nS\twhole\nM\tsmash\nO\tegg\nS\tcracked\n//\n"
        "O\tegg\nS\tcracked\nM\tfry\nO\tegg\nS\tfried\n//\n"
    )
    f = foon.Foon.from_text(text)
    kitchen = [foon.Object("egg", ("whole",))]
    goal = f.goal_id(foon.Object("egg", ("fried",)))
    for rates, units in (({"crack": 0.0, "smash": 0.5, "fry": 0.9}, {1, 2}),
                         ({"crack": 0.0, "smash": 0.0, "fry": 0.9}, {2})):  # fmt: skip
        p = f.planner(kitchen, motions=rates)
        out = foon_problem(f, p, goal)
        w = read(out, tmp_path / str(len(units)))
        assert set(w.actions) == units
        assert "; unit 0 (crack) is left out: its motion's success rate is 0" in out
        sol = solve_fd(w, tmp_path / str(len(units)))
        assert (sol is not None) == p.plan(goal, "optimal-success").solved == (1 in units)


def test_depth_and_units_narrow_the_ancestry(tmp_path: Path) -> None:
    f, p, g = example()
    gid = f.goal_id(g)
    plain = f.planner(p.kitchen, utensils=p.utensils)
    r = Ref(ref.parse(f.to_text()), [o.identity() for o in p.kitchen], set(p.utensils))
    whole = read(foon_problem(f, plain, gid), tmp_path / "whole")
    assert set(whole.actions) == r.ancestry(gid) != set()
    for depth in (0, 1, 2):
        w = read(foon_problem(f, plain, gid, depth=depth), tmp_path / str(depth))
        assert set(w.actions) <= set(whole.actions)
        assert "within the units selected" in w.domain_file.read_text()
    for k in range(len(whole.actions) + 1):
        units = sorted(whole.actions)[:k]
        w = read(foon_problem(f, plain, gid, units=units), tmp_path / f"units{k}")
        r.check(w, gid, r.ancestry(gid, set(units)), None)


# --- generated FOONs --------------------------------------------------------------------------

PDDL_SETTINGS = settings(max_examples=25, deadline=None, derandomize=True,
                         suppress_health_check=[HealthCheck.too_slow,
                                                HealthCheck.data_too_large,
                                                HealthCheck.function_scoped_fixture])  # fmt: skip


@PDDL_SETTINGS
@given(g=gen_foons(), data=st.data())
def test_generated_foons_pyperplan(g: GenFoon, data: st.DataObject, tmp_path: Path) -> None:
    """Without costs: every problem parses and is exactly the goal's ancestry; pyperplan
    solves it exactly when the goal is derivable, with an executable tree."""
    case = draw_case(data, g)
    r = Ref(case.rf, case.kitchen, case.utensils)
    p = case.f.planner(case.rkitchen, utensils=sorted(case.utensils))
    for goal in case.goals[:3]:
        text = foon_problem(case.f, p, goal)
        w = read(text, tmp_path / str(goal))
        r.check(w, goal, r.ancestry(goal), None)
        sol = solve_pyperplan(w)
        assert (sol is not None) == (goal in r.der)
        if sol is not None:
            assert executable(p, sol.units, goal)


@settings(PDDL_SETTINGS, max_examples=10)
@given(g=gen_foons(), data=st.data())
def test_generated_foons_fast_downward(g: GenFoon, data: st.DataObject, tmp_path: Path) -> None:
    """With costs: Fast Downward solves the problem exactly when optimal-success solves the
    goal, with an executable tree that costs no more than optimal-success's."""
    case = draw_case(data, g)
    r = Ref(case.rf, case.kitchen, case.utensils)
    p = case.f.planner(case.rkitchen, motions=case.rates, utensils=sorted(case.utensils))
    for goal in case.goals[:2]:
        where = tmp_path / str(goal)
        w = read(foon_problem(case.f, p, goal), where)
        r.check(w, goal, r.ancestry(goal), case.rates)
        sol = solve_fd(w, where)
        t = p.plan(goal, "optimal-success")
        assert (sol is not None) == t.solved
        if sol is not None:
            assert executable(p, sol.units, goal)
            assert sol.cost is not None and sol.cost <= tree_cost(w, t.units)
            if not t.units:  # the goal is in the kitchen
                assert sol == Solution([], 0)


AWKWARD = ("and", "not", "at", "either", "total-cost", "7up", "jalapeño", "crème brûlée",
           "salt & pepper", "a" * 90, "-", "x", "X", "(x)", "ª")  # fmt: skip


@PDDL_SETTINGS
@given(chain=st.lists(st.tuples(st.sampled_from(AWKWARD), st.sampled_from(AWKWARD),
                          st.sampled_from(("", "chopped", "the end", "1"))),
                min_size=1, max_size=8).map(list))  # fmt: skip
def test_awkward_labels_give_valid_unique_names(
    tmp_path: Path, chain: list[tuple[str, str, str]]
) -> None:
    """Labels that are PDDL words, digits, punctuation, non-ASCII or very long: names stay
    valid and unique, and the problem is solved."""
    units = []
    first = chain[0][0]
    prev = f"O\t{first}\n"
    for i, (_, label, state) in enumerate(chain):
        out = f"O\t{label}\nS\tstep {i}\n" + (f"S\t{state}\n" if state else "")
        units.append(f"{prev}M\tmix it {i}\n{out}//\n")
        prev = out
    f = foon.Foon.from_text("".join(units))
    kitchen = [foon.Object(first.lower().rstrip())]
    goal = f.fu(f.fu_count - 1).output_ids[0]
    p = f.planner(kitchen)
    w = read(foon_problem(f, p, goal), tmp_path / "p")
    sol = solve_pyperplan(w)
    assert sol is not None and executable(p, sol.units, goal)
