"""Properties of the Rust planner that follow directly from docs/METHODS.md and
docs/SEMANTICS.md, checked on the course data and on generated FOONs (the strategy of
test_differential.py).

For every sound method (ids, greedy-success, greedy-inputs with both counts, optimal-success,
optimal-units, optimal-inputs):
- a derivable goal is solved, a goal in the kitchen gives the empty tree of height 0;
- the tree is valid (TaskTree.is_valid) and its units are listed in a valid execution order:
  each unit's needed inputs (foon_reference.needed_inputs) are in the kitchen or made by an
  earlier unit, and the goal's unit is last; no unit is listed twice;
- its height (also recomputed by the reference) is at least rank(goal) (Foon.ranks), and the
  ids tree's height equals the rank;
- a goal that is not derivable fails with no units and a non-empty explanation (missing items
  or a cycle, closed: first = last);
- optimal-*: the reported cost equals the cost of the returned tree counted with multiplicity
  (a shared sub-goal counts each time it is used) and is at most that of every other sound
  method's tree for the same goal (for optimal-success, the cost is reported as a success
  probability, exp(-optimum), so it is at least that of every other tree).
Whipped cream and fried rice fail soundly with the course kitchen and succeed (with an invalid,
circular tree) under compat="course".
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import foon
import foon_reference as ref
import pytest
from hypothesis import given
from hypothesis import strategies as st
from test_differential import (
    GEN_SETTINGS,
    Course,
    GenFoon,
    draw_case,
    dropped_kitchen,
    gen_foons,
    load_course,
    rust_kitchen,
)


@dataclass(frozen=True)
class Sound:
    method: str
    count: str = "nodes"

    def __str__(self) -> str:
        return f"{self.method}/{self.count}"


SOUND = (
    Sound("ids"),
    Sound("greedy-success"),
    Sound("greedy-inputs"),
    Sound("greedy-inputs", "ingredients"),
    Sound("optimal-success"),
    Sound("optimal-units"),
    Sound("optimal-inputs"),
)
COURSE = (
    Sound("bfs"),
    Sound("ids"),
    Sound("greedy-success"),
    Sound("greedy-inputs"),
    Sound("greedy-inputs", "ingredients"),
)
OPTIMAL = ("optimal-success", "optimal-units", "optimal-inputs")
UNSOLVABLE = ("whipped cream", "fried rice")


@pytest.fixture(scope="module")
def course() -> Course:
    return load_course()


class Checker:
    """Checks sound trees of one FOON, kitchen, utensil list and rate table."""

    def __init__(
        self,
        rf: ref.RefFoon,
        f: foon.Foon,
        kitchen: list[ref.Identity],
        rkitchen: foon.Kitchen,
        utensils: set[str],
        rates: dict[str, float],
        threads: int | None = None,
    ) -> None:
        self.rf, self.f = rf, f
        self.threads = threads
        self.kitchen, self.rkitchen = kitchen, rkitchen
        self.utensils = utensils
        self.rutensils = sorted(utensils)
        self.rates = rates
        self.k = ref.kitchen_ids(rf, kitchen)
        self.needed = [ref.needed_inputs(rf, i, utensils) for i in range(len(rf.fus))]
        self.produced = [rf.fu_produced(i) for i in range(len(rf.fus))]
        self.rank = f.ranks(rkitchen, self.rutensils)

    def plan(
        self, goals: Sequence[int], cfg: Sound, compat: str | None = None
    ) -> list[foon.TaskTree]:
        return self.f.plan_many(goals, self.rkitchen, cfg.method, compat=compat,  # type: ignore[arg-type]
                                count=cfg.count,  # type: ignore[arg-type]
                                motions=self.rates, utensils=self.rutensils,
                                threads=self.threads)  # fmt: skip

    def executable_in_order(self, units: list[int], goal: int) -> bool:
        have = set(self.k)
        for u in units:
            if not all(x in have for x in self.needed[u]):
                return False
            have.update(self.produced[u])
        return goal in have

    def relevant_kitchen(self, units: list[int], goal: int) -> set[int]:
        """K restricted to the tree's needed inputs and the goal: the reference's validity and
        height only look K up for those, so the result is the same, and much faster than
        copying the 1,174-object course kitchen for each of 30,000 trees."""
        used = {goal}
        for u in units:
            used.update(self.needed[u])
        return used & self.k

    def check_metrics(self, tree: foon.TaskTree) -> None:
        """METHODS.md, Validity and metrics: success = product of the motion rates of the
        tree's units; leaf_inputs = number of distinct needed inputs of its units in K."""
        where = f"{tree.method}/{tree.compat}/{tree.count} goal {tree.goal_id}"
        success = math.prod(self.rates[self.rf.fus[u].motion] for u in tree.units)
        assert tree.success is not None and math.isclose(tree.success, success, rel_tol=1e-9), (
            where,
            tree.success,
            success,
        )
        leaves = {x for u in tree.units for x in self.needed[u] if x in self.k}
        assert tree.leaf_inputs == len(leaves), where

    def check_sound(self, tree: foon.TaskTree, cfg: Sound) -> None:
        """The properties of one sound tree."""
        goal = tree.goal_id
        where = f"{cfg} goal {goal} {self.rf.objects[goal]}"
        self.check_metrics(tree)
        rank = self.rank[goal]
        if rank is None:
            assert not tree.solved, where
            assert tree.units == [] and tree.height is None, where
            assert tree.missing or tree.cycle, where
            if tree.cycle:
                assert len(tree.cycle) >= 2 and tree.cycle[0] == tree.cycle[-1], where
            assert tree.explanation() != "", where
            return
        if cfg.method == "optimal-success" and not tree.solved:
            # Derivable, but every way to make it uses a motion of rate 0 (check_costs checks
            # that the other methods' trees do): nothing is missing and no cycle blocks it.
            assert tree.units == [] and tree.cost is None, where
            assert tree.missing == [] and tree.cycle == [] and tree.unresolved == [], where
            assert (
                tree.explanation() == "every way to make it uses a motion whose success rate is 0"
            )
            return
        assert tree.solved, where
        assert tree.missing == [] and tree.cycle == [] and tree.unresolved == [], where
        assert len(set(tree.units)) == len(tree.units), where
        if goal in self.k:
            assert tree.units == [] and tree.height == 0, where
        else:
            assert tree.units, where
            assert goal in self.produced[tree.units[-1]], where  # the goal's unit is last
        assert self.executable_in_order(tree.units, goal), where
        assert tree.is_valid(), where
        k = self.relevant_kitchen(tree.units, goal)
        assert ref.is_valid(self.rf, tree.units, goal, k, self.utensils), where
        assert tree.height == ref.height(self.rf, tree.units, goal, k, self.utensils), where
        assert tree.height is not None and tree.height >= rank, where
        if cfg.method == "ids":
            assert tree.height == rank, where

    def multiplicity_cost(self, units: list[int], goal: int, method: str) -> float:
        """Tree cost counted with multiplicity, for a tree listed in a valid execution order:
        each object costs the least over the tree's units made so far of w(unit) + the cost of
        its needed inputs; kitchen objects cost 0 (1 for optimal-inputs). Every value is the
        cost of an actual derivation, so the optimum is at most this; for the optimal tree
        (each object's chosen unit comes before its users) it is exactly the optimum."""
        leaf = 1.0 if method == "optimal-inputs" else 0.0
        k = self.k
        cost: dict[int, float] = {}  # objects outside K
        for u in units:
            if method == "optimal-success":
                rate = self.rates[self.rf.fus[u].motion]
                w = math.inf if rate == 0 else -math.log(rate)
            elif method == "optimal-units":
                w = 1.0
            else:
                w = 0.0
            # An object made only through a motion of rate 0 costs inf (absent from `cost`).
            total = w + sum(leaf if x in k else cost.get(x, math.inf) for x in self.needed[u])
            for o in self.produced[u]:
                if o not in k and total < cost.get(o, math.inf):
                    cost[o] = total
        return leaf if goal in k else cost.get(goal, math.inf)

    def check_costs(self, trees: dict[Sound, foon.TaskTree]) -> None:
        """The optimal-* properties over the sound trees of one derivable goal."""
        any_tree = next(iter(trees.values()))
        goal = any_tree.goal_id
        for method in OPTIMAL:
            best = trees[Sound(method)]
            where = f"{method} goal {goal} {self.rf.objects[goal]}"
            if method == "optimal-success" and not best.solved:
                # No tree without a motion of rate 0: every other method's tree has one.
                for cfg, other in trees.items():
                    if other.solved:
                        assert self.multiplicity_cost(other.units, goal, method) == math.inf, (
                            where,
                            str(cfg),
                        )
                continue
            assert best.cost is not None, where
            own = self.multiplicity_cost(best.units, goal, method)
            if method == "optimal-success":
                assert math.isclose(best.cost, math.exp(-own), rel_tol=1e-9), where
            else:
                assert best.cost == own, where
            if method == "optimal-units":
                assert len(best.units) <= best.cost, where
            for cfg, other in trees.items():
                c = self.multiplicity_cost(other.units, goal, method)
                assert own <= c + 1e-9 * max(1.0, abs(c)), (where, str(cfg), own, c)


def check_all(ch: Checker, goals: Sequence[int]) -> int:
    """Every sound property for these goals; returns the number of trees checked."""
    by_cfg = {cfg: ch.plan(goals, cfg) for cfg in SOUND}
    checked = 0
    for i, goal in enumerate(goals):
        trees = {cfg: by_cfg[cfg][i] for cfg in SOUND}
        for cfg, tree in trees.items():
            assert tree.goal_id == goal
            ch.check_sound(tree, cfg)
            checked += 1
        if ch.rank[goal] is not None:
            ch.check_costs(trees)
    return checked


# --------------------------------------------------------------------------------------------
# Real data
# --------------------------------------------------------------------------------------------


def course_checker(c: Course, kitchen: list[ref.Identity] | None = None) -> Checker:
    if kitchen is None:
        return Checker(c.ref, c.foon, c.kitchen, c.rkitchen, c.utensils, c.rates)
    return Checker(c.ref, c.foon, kitchen, rust_kitchen(kitchen), c.utensils, c.rates)


def test_course_25_goals(course: Course) -> None:
    ch = course_checker(course)
    goals = [course.foon.goal_id(g) for g in course.rgoals]
    assert check_all(ch, goals) == 25 * len(SOUND)
    solvable = [g for g in goals if ch.rank[g] is not None]
    assert len(solvable) == 23


def test_course_every_object(course: Course) -> None:
    """Every object of the course FOON as a goal with the course kitchen: 4,191 derivable
    (kitchen objects included) and 114 not derivable."""
    ch = course_checker(course)
    goals = list(range(course.foon.object_count))
    assert sum(r is None for r in ch.rank) == 114
    assert check_all(ch, goals) == len(goals) * len(SOUND)


@pytest.mark.parametrize("fraction", [0.05, 0.30])
def test_course_random_kitchen(course: Course, fraction: float) -> None:
    """The 25 goals with a seeded random 5% / 30% of the course kitchen dropped."""
    ch = course_checker(course, dropped_kitchen(course.kitchen, fraction, 7))
    goals = [course.foon.goal_id(g) for g in course.rgoals]
    check_all(ch, goals)
    assert any(ch.rank[g] is None for g in goals)


@pytest.mark.parametrize("name", UNSOLVABLE)
def test_unsolvable_course_goals(course: Course, name: str) -> None:
    ch = course_checker(course)
    (goal,) = [course.foon.goal_id(g) for g in course.rgoals if g.label == name]
    assert ch.rank[goal] is None
    for cfg in SOUND:
        (tree,) = ch.plan([goal], cfg)
        ch.check_sound(tree, cfg)
        assert not tree.solved and (tree.missing or tree.cycle), cfg
    for cfg in COURSE:
        (tree,) = ch.plan([goal], cfg, compat="course")
        assert tree.solved and tree.units, cfg
        assert tree.unresolved == [], cfg
        # The course tree relies on a circular step: it is not valid and has no height.
        assert not tree.is_valid(), cfg
        assert tree.height is None, cfg


def course_validity(ch: Checker, goals: Sequence[int]) -> list[tuple[foon.TaskTree, bool]]:
    """Course-compatible trees for these goals, each with the reference's validity verdict."""
    out = []
    for cfg in COURSE:
        for tree in ch.plan(goals, cfg, compat="course"):
            k = ch.relevant_kitchen(tree.units, tree.goal_id)
            out.append((tree, ref.is_valid(ch.rf, tree.units, tree.goal_id, k, ch.utensils)))
    return out


def check_course_validity(ch: Checker, goals: Sequence[int]) -> None:
    """TaskTree.is_valid on course trees (often invalid) equals the reference's verdict."""
    for tree, valid in course_validity(ch, goals):
        ch.check_metrics(tree)
        assert tree.is_valid() == valid, (tree.method, tree.goal_id)
        if tree.height is None:
            assert not valid, (tree.method, tree.goal_id)


def test_course_trees_validity(course: Course) -> None:
    ch = course_checker(course)
    goals = [course.foon.goal_id(g) for g in course.rgoals]
    check_course_validity(ch, goals)
    verdicts = [valid for _, valid in course_validity(ch, goals)]
    assert any(verdicts) and not all(verdicts)


def test_course_trees_validity_equals_reference(course: Course) -> None:
    """TaskTree.is_valid on the course trees of the 25 goals equals the reference's verdict
    (greedy-success/course for coleslaw reaches the goal but holds a unit that cannot run)."""
    ch = course_checker(course)
    goals = [course.foon.goal_id(g) for g in course.rgoals]
    for tree, valid in course_validity(ch, goals):
        assert tree.is_valid() == valid, (tree.method, tree.goal_id)


#: FU 0 (e -> c) and the cycle FU 3 (f -> e), FU 4 (e -> f) can never run; FU 1 (a -> b, c)
#: and FU 2 (b, c -> g) make the goal g from a. bfs/course takes each object's first producer.
CIRCULAR_UNIT = (
    "O\te\nS\tx\nM\tm\nO\tc\nS\ty\n//\n"
    "O\ta\nS\tx\nM\tm\nO\tb\nS\ty\nO\tc\nS\ty\n//\n"
    "O\tb\nS\ty\nO\tc\nS\ty\nM\tm\nO\tg\nS\tz\n//\n"
    "O\tf\nS\tx\nM\tm\nO\te\nS\tx\n//\n"
    "O\te\nS\tx\nM\tm\nO\tf\nS\tx\n//\n"
)


def test_is_valid_rejects_a_tree_with_a_unit_that_cannot_run() -> None:
    f = foon.Foon.from_text(CIRCULAR_UNIT)
    rf = ref.parse(CIRCULAR_UNIT)
    goal = f.goal_id(foon.Object("g", ("z",)))
    tree = f.plan(goal, [foon.Object("a", ("x",))], "bfs", compat="course")
    assert tree.solved and tree.units == [4, 3, 0, 1, 2] and tree.height == 2
    k = ref.kitchen_ids(rf, [("a", ("x",), (), None)])
    assert not ref.is_valid(rf, tree.units, goal, k, set())
    assert not tree.is_valid()


def test_optimal_success_cost_of_a_goal_in_the_kitchen() -> None:
    f = foon.Foon.from_text("O\tonion\nS\twhole\nM\tchop\nO\tonion\nS\tchopped\n//\n")
    kitchen = [foon.Object("onion", ("whole",))]
    made = f.plan(1, kitchen, "optimal-success", motions={"chop": 0.5})
    assert made.units == [0] and made.cost == 0.5  # exp(-(-log 0.5))
    tree = f.plan(0, kitchen, "optimal-success", motions={"chop": 0.5})
    assert tree.solved and tree.units == [] and tree.success == 1.0
    assert tree.cost == 1.0


#: FU 0 makes a from nothing, FU 1 makes b from a; the kitchen has a.
INPUT_FREE = "M\tmix\nO\ta\nS\tx\n//\nO\ta\nS\tx\nM\tchop\nO\tb\nS\ty\n//\n"

#: The same, one step further (found by test_generated_foons): FU 1 makes p {s} from nothing,
#: FU 2 makes s in [p] from it; the kitchen has onion and s in [p]; goal r.
MADE_FROM_NOTHING = (
    "O\ts\nS\tin\t[p]\nO\tonion\nM\tchop\nO\tr\nS\thot\n//\n"
    "M\tpour\nO\tp\nS\tcontains\t{s}\n//\n"
    "O\tp\nS\tcontains\t{s}\nM\tpour\nO\ts\nS\tin\t[p]\n//\n"
)


def test_optimal_inputs_cost_of_a_kitchen_object_made_from_nothing() -> None:
    f = foon.Foon.from_text(INPUT_FREE)
    tree = f.plan(foon.Object("b", ("y",)), [foon.Object("a", ("x",))], "optimal-inputs")
    assert tree.solved and tree.units == [1]
    assert tree.cost == 1.0  # cost(b) = cost(a) = 1: a is in the kitchen


def test_optimal_inputs_cost_of_a_kitchen_object_made_from_nothing_in_two_steps() -> None:
    f = foon.Foon.from_text(MADE_FROM_NOTHING)
    kitchen = [foon.Object("onion"), foon.Object("s", container="p")]
    tree = f.plan(foon.Object("r", ("hot",)), kitchen, "optimal-inputs")
    assert tree.solved and tree.units == [0]
    assert tree.cost == 2.0  # two kitchen inputs, 1 each


# --------------------------------------------------------------------------------------------
# Generated FOONs
# --------------------------------------------------------------------------------------------


@GEN_SETTINGS
@given(g=gen_foons(), data=st.data())
def test_generated_foons(g: GenFoon, data: st.DataObject) -> None:
    """Every object of a generated FOON as a goal, every sound method, every property; and
    TaskTree.is_valid on course-compatible trees."""
    case = draw_case(data, g)
    # threads=1: many small calls, each cheaper on one thread than spread over several.
    ch = Checker(case.rf, case.f, case.kitchen, case.rkitchen, case.utensils, case.rates, threads=1)
    goals = list(range(len(case.rf.objects)))
    check_all(ch, goals)
    check_course_validity(ch, case.goals)
