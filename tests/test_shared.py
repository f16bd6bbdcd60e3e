"""``optimal-shared`` (docs/METHODS.md, "Fewest distinct units"): exact against a brute-force
enumeration of every valid FU set on generated FOONs (cycles, duplicates, self-loops), valid
trees, the proven bound, node-limit determinism, the course goals, the command line."""

from __future__ import annotations

import json
import math

import foon
import foon_reference as ref
import pytest
import shared_reference as sref
from foon.cli import main
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_differential import draw_case, gen_foons, rust_kitchen
from workloads import graph_units, units_text

NODE_KITCHEN: list[ref.Identity] = [("node", ("n0",), (), None)]
MOTIONS = ("mix", "stir", "chop")
RATE_CHOICES = (0.25, 0.5, 0.9, 1.0)


@st.composite
def small_graphs(draw: st.DrawFn) -> tuple[list[list[list[int]]], list[str]]:
    """(graph, motions): 3 to 7 nodes (node 0 is the kitchen), each other node made in 1 or 2
    ways from 1 to 3 nodes, which may include itself (a self-loop) and nodes that need it (a
    cycle); some ways are written twice (a duplicate, dropped on load). At most 12 units, so
    every subset can be enumerated."""
    n = draw(st.integers(3, 7))
    node = st.integers(0, n - 1)
    ways = st.lists(st.lists(node, min_size=1, max_size=3, unique=True), min_size=1, max_size=2)
    graph: list[list[list[int]]] = [[]]
    for _ in range(n - 1):
        w = draw(ways)
        if draw(st.integers(0, 5)) == 0:
            w = [*w, w[0]]
        graph.append(w)
    total = sum(len(w) for w in graph)
    motions = [draw(st.sampled_from(MOTIONS)) for _ in range(total)]
    return graph, motions


def graph_text(graph: list[list[list[int]]], motions: list[str]) -> str:
    units = [(ins, m, outs) for (ins, _, outs), m in zip(graph_units(graph), motions, strict=True)]
    return units_text(units)


def check_goal(
    f: foon.Foon,
    rf: ref.RefFoon,
    planner: foon.Planner,
    goal: int,
    kitchen_ids: set[int],
    utensils: set[str],
    rates: dict[str, float] | None,
) -> None:
    t = planner.plan(goal, "optimal-shared")
    want = sref.fewest_units(rf, goal, kitchen_ids, utensils)
    if want is None:
        assert not t.solved
        return
    assert t.solved and t.proven is True
    assert len(t.units) == len(set(t.units)) == want[0] == t.cost == t.bound
    assert t.gap == 0
    assert t.is_valid()
    assert ref.is_valid(rf, list(t.units), goal, kitchen_ids, utensils)
    # Never worse than the optimal tree it starts from.
    assert len(t.units) <= len(planner.plan(goal, "optimal-units").units)
    if rates is None:
        return
    best = sref.best_success(rf, goal, kitchen_ids, utensils, rates)
    s = planner.plan(goal, "optimal-shared", objective="success")
    if best is None or best == 0.0:
        assert not s.solved or s.cost == 0.0
        return
    assert s.solved and s.proven is True and s.cost is not None
    assert ref.is_valid(rf, list(s.units), goal, kitchen_ids, utensils)
    assert math.isclose(s.cost, best, rel_tol=1e-9)
    assert math.isclose(sref.distinct_success(rf, list(s.units), rates), best, rel_tol=1e-9)


@settings(max_examples=250, deadline=None, derandomize=True)
@given(case=small_graphs(), rates=st.lists(st.sampled_from(RATE_CHOICES), min_size=3, max_size=3))
def test_generated_graphs_match_the_brute_force(
    case: tuple[list[list[list[int]]], list[str]], rates: list[float]
) -> None:
    graph, motions = case
    text = graph_text(graph, motions)
    rf = ref.parse(text)
    f = foon.Foon.from_text(text)
    rate_table = dict(zip(MOTIONS, rates, strict=True))
    planner = f.planner(rust_kitchen(NODE_KITCHEN), motions=rate_table)
    kitchen_ids = ref.kitchen_ids(rf, NODE_KITCHEN)
    for goal in range(len(rf.objects)):
        check_goal(f, rf, planner, goal, kitchen_ids, set(), rate_table)


@settings(
    max_examples=100,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(g=gen_foons(), data=st.data())
def test_generated_foons_match_the_brute_force(g: object, data: st.DataObject) -> None:
    """The differential generator's FOONs (dialects, container rule, bare outputs, cycles,
    self-loops, duplicates), for goals with at most 12 runnable units around them."""
    case = draw_case(data, g)  # type: ignore[arg-type]
    kitchen_ids = ref.kitchen_ids(case.rf, case.kitchen)
    if len(sref.runnable_fus(case.rf, kitchen_ids, case.utensils)) > 12:
        return
    planner = case.f.planner(case.rkitchen, motions=case.rates, utensils=sorted(case.utensils))
    for goal in case.goals:
        check_goal(case.f, case.rf, planner, goal, kitchen_ids, case.utensils, None)


def wide_text(width: int) -> str:
    """A goal made from `width` parts, each part made alone (one unit each) or all at once by
    one shared unit that needs a part made two steps from the kitchen: the tree cost prefers
    the singles, the fewest distinct units the shared unit."""
    units = []
    parts = [("part", f"p{i}") for i in range(width)]
    for p in parts:
        units.append(((("node", "n0"),), "mix", (p,)))
    units.append(((("node", "n0"),), "mix", (("base", "b1"),)))
    units.append(((("base", "b1"),), "mix", (("base", "b2"),)))
    units.append(((("base", "b2"),), "mix", tuple(parts)))
    units.append((tuple(parts), "mix", (("dish", "done"),)))
    return units_text(units)


def test_a_shared_unit_beats_the_optimal_tree() -> None:
    f = foon.Foon.from_text(wide_text(5))
    p = f.planner(rust_kitchen(NODE_KITCHEN))
    units = p.plan({"label": "dish", "states": ["done"]}, "optimal-units")
    shared = p.plan({"label": "dish", "states": ["done"]}, "optimal-shared")
    assert len(units.units) == 6 and units.cost == 6
    assert len(shared.units) == 4 and shared.cost == 4 and shared.proven
    assert shared.is_valid()


def test_node_limit_is_deterministic_and_the_bound_holds() -> None:
    f = foon.Foon.from_text(wide_text(8))
    p = f.planner(rust_kitchen(NODE_KITCHEN))
    goal = {"label": "dish", "states": ["done"]}
    exact = p.plan(goal, "optimal-shared")
    assert exact.proven and exact.cost == 4
    for limit in (0, 1, 2, 3, 5, 100):
        a = p.plan(goal, "optimal-shared", node_limit=limit)
        b = p.plan(goal, "optimal-shared", node_limit=limit)
        assert a == b
        assert a.bound is not None and a.cost is not None and a.gap is not None
        assert a.bound <= exact.cost <= a.cost
        assert a.gap == a.cost - a.bound
        assert a.is_valid()
        if not a.proven:
            assert a.expanded == limit
    stopped = p.plan(goal, "optimal-shared", node_limit=0)
    assert stopped.proven is False and stopped.cost == 9 and stopped.bound == 2
    timed = p.plan(goal, "optimal-shared", time_limit=60.0)
    assert timed.proven and timed.units == exact.units


def test_bad_options_are_errors() -> None:
    f = foon.Foon.from_text(wide_text(2))
    p = f.planner(rust_kitchen(NODE_KITCHEN))
    goal = {"label": "dish", "states": ["done"]}
    with pytest.raises(ValueError, match="unknown objective 'fewest'"):
        p.plan(goal, "optimal-shared", objective="fewest")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="time limit is -1"):
        p.plan(goal, "optimal-shared", time_limit=-1.0)
    with pytest.raises(foon.MissingRateError):
        p.plan(goal, "optimal-shared", objective="success")


def test_other_methods_have_no_bound() -> None:
    f = foon.Foon.from_text(wide_text(2))
    t = f.plan({"label": "dish", "states": ["done"]}, rust_kitchen(NODE_KITCHEN), "optimal-units")
    assert t.bound is None and t.proven is None and t.gap is None


def test_a_goal_in_the_kitchen_is_proven_empty() -> None:
    f = foon.Foon.from_text(wide_text(2))
    t = f.plan({"label": "node", "states": ["n0"]}, rust_kitchen(NODE_KITCHEN), "optimal-shared")
    assert t.solved and t.units == [] and t.cost == 0 and t.bound == 0 and t.proven


SOUND = ("ids", "greedy-success", "greedy-inputs", "optimal-success", "optimal-units",
         "optimal-inputs")  # fmt: skip


def test_course_goals_fewest_units(course) -> None:  # type: ignore[no-untyped-def]
    """On the 25 course goals, optimal-shared's tree is valid, proven, and has no more units
    than the tree of any other sound method, goal by goal."""
    p = course.foon.planner(course.kitchen, motions=course.motions, utensils=course.utensils)
    solved = 0
    for g in course.goals25:
        shared = p.plan(g, "optimal-shared")
        others = {m: p.plan(g, m) for m in SOUND}
        if not shared.solved:
            assert not any(t.solved for t in others.values())
            continue
        solved += 1
        assert shared.proven and shared.is_valid()
        for m, t in others.items():
            if t.solved:
                assert len(shared.units) <= len(set(t.units)), (g.label, m)
        s = p.plan(g, "optimal-shared", objective="success")
        assert s.proven and s.is_valid()
        assert s.cost is not None and others["optimal-success"].success is not None
        assert s.cost >= others["optimal-success"].success - 1e-12
    assert solved >= 20


def run(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_plan_text_and_json(capsys: pytest.CaptureFixture[str]) -> None:
    ex = foon.example()
    code, out, err = run(["plan", "--method", "optimal-shared"], capsys)
    assert code == 0 and "Traceback" not in err
    want = ex.foon.plan(
        ex.goals[0], ex.kitchen, "optimal-shared", motions=ex.motions, utensils=ex.utensils
    )
    assert out == want.to_text()
    code, out, err = run(["plan", "--method", "optimal-shared", "--format", "json"], capsys)
    assert code == 0
    [d] = json.loads(out)
    assert d["method"] == "optimal-shared" and d["solved"] is True
    assert len(d["units"]) == len(want.units)


def test_cli_compare_has_the_method(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(["compare", "--json"], capsys)
    assert code == 0
    doc = json.loads(out)
    assert "optimal-shared" in json.dumps(doc)
