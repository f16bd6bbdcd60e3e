"""``foon explain`` / ``Foon.explain``: the course goals blocked by cycles, shopping lists that
unblock kitchens with items removed, and what blocks each producer checked against a
pure-Python reference on generated FOONs."""

from __future__ import annotations

import argparse
import io
import json
import random
from contextlib import redirect_stdout

import foon
import foon_reference as ref
import pytest
from conftest import DATA, Course
from foon._cli_explain import add_explain_options, cmd_explain
from hypothesis import given, settings
from hypothesis import strategies as st
from test_differential import GEN_SETTINGS, GenFoon, draw_case, gen_foons


def _explain(course: Course, goal: foon.Object, kitchen: foon.Kitchen) -> foon.GoalExplanation:
    return course.foon.explain(goal, kitchen, motions=course.motions, utensils=course.utensils)


def _derivable(course: Course, goal: foon.Object, kitchen: foon.Kitchen) -> bool:
    return _explain(course, goal, kitchen).status != "blocked"


@pytest.mark.parametrize("label", ["whipped cream", "fried rice"])
def test_course_goals_blocked_by_a_cycle(course: Course, label: str) -> None:
    """Both goals are blocked by cycles only: no shopping list, no producer's blocking input
    can be bought, the cycle is shown as a chain, and adding an object named to unblock it
    makes the goal derivable."""
    goal = next(g for g in course.goals25 if g.label == label)
    e = _explain(course, goal, course.kitchen)
    assert e.status == "blocked" and not e.derivable and not e.buyable
    assert e.shopping == () and e.tree is None and e.rank is None
    assert e.producers and all(p.blockers for p in e.producers)
    blockers = [b for p in e.producers for b in p.blockers]
    assert all(not b.buyable and b.kind != "missing" for b in blockers)
    if label == "whipped cream":
        # Its producer needs an object that needs the goal; fried rice's cycle is elsewhere.
        assert any(b.kind == "cycle" for b in blockers)
    assert len(e.cycle) >= 2 and len(e.cycle_units) == len(e.cycle) - 1
    assert e.cycle[-1] in e.cycle[:-1]
    for i, u in enumerate(e.cycle_units):
        assert e.cycle_ids[i] in course.foon.fu(u).output_ids
        assert e.cycle_ids[i + 1] in course.foon.fu(u).input_ids
    assert "blocking cycle: " in e.text and "--[unit " in e.text
    assert str(e.cycle_units[0]) in e.text
    assert e.unblock, "something must unblock the goal"
    for u in e.unblock:
        added = course.kitchen.with_items([u.object])
        if u.alone:
            assert _derivable(course, goal, added)
        else:
            again = _explain(course, goal, added)
            assert again.buyable
            assert _derivable(course, goal, added.with_items(again.shopping))
        assert f"adding {u.object}" in e.text
    d = e.to_dict()
    json.dumps(d)
    assert d["status"] == "blocked" and d["cycle_units"] == list(e.cycle_units)


def test_course_derivable_goal(course: Course) -> None:
    goal = next(g for g in course.goals25 if _derivable(course, g, course.kitchen))
    e = _explain(course, goal, course.kitchen)
    assert e.status == "derivable" and e.rank is not None and e.tree is not None
    assert e.objective == "optimal-success"
    t = course.foon.plan(goal, course.kitchen, "optimal-success", motions=course.motions,
                         utensils=course.utensils)  # fmt: skip
    assert e.tree.units == t.units and e.tree.success == t.success
    assert e.to_dict()["tree"]["unit_count"] == len(t.units)
    inside = _explain(course, course.kitchen[0], course.kitchen)
    assert inside.status == "in-kitchen"


def _dropped(kitchen: foon.Kitchen, fraction: float, seed: int) -> foon.Kitchen:
    items = list(kitchen)
    rnd = random.Random(seed)
    drop = set(rnd.sample(range(len(items)), int(len(items) * fraction)))
    return foon.Kitchen(o for i, o in enumerate(items) if i not in drop)


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_shopping_list_unblocks_reduced_kitchens(course: Course, seed: int) -> None:
    """With 30% of the kitchen removed, every blocked goal that raw items can make becomes
    derivable once its shopping list is added."""
    kitchen = _dropped(course.kitchen, 0.3, seed)
    planner = course.foon.planner(kitchen, motions=course.motions, utensils=course.utensils)
    bought = 0
    for goal in course.goals25:
        e = planner.explain(goal)
        if e.status != "blocked" or not e.buyable:
            continue
        assert e.shopping
        assert all(not course.foon.producers(course.foon.goal_id(o)) for o in e.shopping)
        assert all(o not in kitchen for o in e.shopping)
        assert _derivable(course, goal, kitchen.with_items(e.shopping)), goal
        bought += 1
    assert bought > 0


def test_cli_text_and_json(course: Course) -> None:
    goal = next(g for g in course.goals25 if g.label == "whipped cream")
    p = argparse.ArgumentParser()
    add_explain_options(p)
    base = ["--foon", str(DATA / "FOON.txt"), "--kitchen", str(DATA / "kitchen.json"),
            "--motions", str(DATA / "motion.txt"), "--utensils", str(DATA / "utensils.txt"),
            "--goal", json.dumps(goal.to_dict())]  # fmt: skip
    out = io.StringIO()
    with redirect_stdout(out):
        rc = cmd_explain(p.parse_args(base))
    assert rc == 1 and "blocking cycle: " in out.getvalue()
    out = io.StringIO()
    with redirect_stdout(out):
        rc = cmd_explain(p.parse_args([*base, "--json"]))
    d = json.loads(out.getvalue())
    assert rc == 1 and d["status"] == "blocked" and d["cycle"]
    assert set(d) >= {"goal", "goal_id", "objective", "rank", "tree", "buyable", "shopping",
                      "shopping_objective", "producers", "cycle_units", "unblock"}  # fmt: skip


def _reach(rf: ref.RefFoon, goal: int, d2: set[int], utensils: set[str]) -> set[int]:
    """The objects not derivable from K' that need the goal (through such objects)."""
    reach = {goal} if goal not in d2 else set()
    changed = True
    while changed:
        changed = False
        for f in range(len(rf.fus)):
            if any(x in reach for x in ref.needed_inputs(rf, f, utensils)):
                for z in rf.fu_produced(f):
                    if z not in d2 and z not in reach:
                        reach.add(z)
                        changed = True
    return reach


@settings(GEN_SETTINGS, max_examples=80)
@given(g=gen_foons(), data=st.data())
def test_what_blocks_each_producer_matches_the_reference(g: GenFoon, data: st.DataObject) -> None:
    case = draw_case(data, g)
    rf, f, ut = case.rf, case.f, case.utensils
    k = ref.kitchen_ids(rf, case.kitchen)
    raw = {o for o in range(len(rf.objects)) if not rf.producers(o)}
    d = ref.derivable(rf, k, ut)
    d2 = ref.derivable(rf, k | raw, ut)
    planner = f.planner(case.rkitchen, utensils=sorted(ut))
    for goal in case.goals:
        e = planner.explain(goal)
        want = "in-kitchen" if goal in k else "derivable" if goal in d else "blocked"
        assert e.status == want
        if want != "blocked":
            assert e.tree is not None and e.tree.solved
            continue
        assert e.buyable == (goal in d2)
        reach = _reach(rf, goal, d2, ut)
        expect = []
        for p in rf.producers(goal):
            blockers: list[tuple[int, str, bool]] = []
            for x in ref.needed_inputs(rf, p, ut):
                if x in d or any(b[0] == x for b in blockers):
                    continue
                kind = ("missing" if x in raw else "cycle" if x not in d2 and x in reach
                        else "not-derivable")  # fmt: skip
                blockers.append((x, kind, x in d2))
            expect.append((p, blockers))
        got = [(p.unit, [(b.object_id, b.kind, b.buyable) for b in p.blockers])
               for p in e.producers]  # fmt: skip
        assert got == expect
        if e.buyable:
            assert goal in ref.derivable(rf, k | {f.find(o) for o in e.shopping}, ut)
        else:
            assert e.cycle_ids and e.cycle_ids[-1] in e.cycle_ids[:-1]
            for u in e.unblock:
                alone = goal in ref.derivable(rf, k | {u.object_id}, ut)
                assert u.alone == alone
                assert alone or goal in ref.derivable(rf, k | raw | {u.object_id}, ut)
