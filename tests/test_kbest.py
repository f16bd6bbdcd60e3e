"""The k best trees (``plan_k``) and the bounded enumeration (``paths``) against the brute-force
reference in ``kbest_reference.py``, on generated FOONs (cycles, duplicates, self-loops,
container rule) and on the course FOON; and the CLI (text and ``--json``)."""

from __future__ import annotations

import json
import math
import random
import subprocess
import sys
from collections.abc import Sequence

import foon
import foon_reference as ref
import kbest_reference as kref
import pytest
from conftest import DATA, Course
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_differential import (
    CONTAINERS,
    INGREDIENTS,
    LABELS,
    MOTIONS,
    RATES,
    STATES,
    UTENSILS,
    Case,
    GenFoon,
    GenFU,
    GenObject,
    _render_fu,
    draw_case,
    gen_foons,
)

OPTIMAL = ("optimal-success", "optimal-units", "optimal-inputs")

SETTINGS = settings(max_examples=100, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.filter_too_much])  # fmt: skip


def _check_goal(case: Case, goal: int, methods: Sequence[str], diverse: Sequence[str]) -> bool:
    """Compares every tree of one goal; False when the reference's budget is exceeded."""
    rf, f = case.rf, case.f
    k = ref.kitchen_ids(rf, case.kitchen)
    utensils = case.utensils
    try:
        trees = kref.all_trees(rf, goal, k, utensils, budget=400)
    except kref.TooMany:
        return False
    planner = f.planner(case.rkitchen, motions=case.rates, utensils=sorted(utensils))
    _check_paths(planner, rf, goal, k, utensils, set(kref.iter_sets(trees)))
    for method in methods:
        _check_method(planner, case, goal, k, trees, method, method in diverse)
    return True


def _check_metrics(
    r: foon.RankedTree,
    rf: ref.RefFoon,
    goal: int,
    k: set[int],
    utensils: set[str],
    rates: dict[str, float],
) -> None:
    """A listed tree's height, leaf inputs and success are those of its units, by the
    reference's definitions (the core computes them over the goal's ancestry)."""
    t = r.tree
    assert t.height == ref.height(rf, r.units, goal, k, utensils), r.units
    leaves = {x for f in r.units for x in ref.needed_inputs(rf, f, utensils) if x in k}
    assert t.leaf_inputs == len(leaves), r.units
    if all(rf.fus[f].motion in rates for f in r.units):
        want = 1.0
        for f in r.units:
            want *= rates[rf.fus[f].motion]
        assert t.success == want, r.units


def _check_method(
    planner: foon.Planner,
    case: Case,
    goal: int,
    k: set[int],
    trees: list[kref.Tree],
    method: str,
    diverse: bool,
) -> None:
    rf, utensils = case.rf, case.utensils
    wfu, leaf = kref.weights(method, case.rates)

    def weight(fu: int) -> float:
        return wfu(rf.fus[fu])

    best = kref.best_by_set(rf, trees, goal, k, utensils, weight, leaf)
    got = planner.plan_k(goal, len(best) + 3, method)
    # Exactly the trees, each set once, in cost order, each at its lowest cost.
    sets = [frozenset(r.units) for r in got]
    assert len(set(sets)) == len(sets)
    assert set(sets) == set(best)
    raw = [best[s] for s in sets]
    assert raw == sorted(raw)
    for r, s in zip(got, sets, strict=True):
        want = math.exp(-best[s]) if method == "optimal-success" else best[s]
        assert r.cost == want, (r.units, method)
        assert ref.is_valid(rf, r.units, goal, k, utensils)
        assert r.rank == got.index(r) + 1
        _check_metrics(r, rf, goal, k, utensils, case.rates)
    # k = 1 is the optimal plan; a shorter list is a prefix of a longer one (ties are broken
    # the same way every time).
    plan = planner.plan(goal, method)
    if plan.solved:
        assert got and got[0].units == plan.units and got[0].cost == plan.cost
    else:
        assert got == []
    for kk in (1, 3):
        assert [r.units for r in planner.plan_k(goal, kk, method)] == [r.units for r in got[:kk]]
    if diverse and got:
        _check_diverse(planner, rf, goal, k, utensils, trees, method, weight, leaf, len(best))


def _check_paths(
    planner: foon.Planner,
    rf: ref.RefFoon,
    goal: int,
    k: set[int],
    utensils: set[str],
    sets: set[frozenset[int]],
) -> None:
    every = [r.units for r in planner.paths(goal)]
    assert len(every) == len(sets)
    assert {frozenset(u) for u in every} == sets
    for m in (0, 2):
        assert [r.units for r in planner.paths(goal, max_trees=m)] == every[:m]
    for h in (1, 2, 3):
        want = [u for u in every if ref.height(rf, u, goal, k, utensils) <= h]
        assert [r.units for r in planner.paths(goal, max_height=h)] == want
    it = planner.paths(goal, max_trees=1)
    assert len(list(it)) == min(1, len(sets)) and list(it) == []


def _check_diverse(
    planner: foon.Planner,
    rf: ref.RefFoon,
    goal: int,
    k: set[int],
    utensils: set[str],
    trees: list[kref.Tree],
    method: str,
    weight: object,
    leaf: float,
    n: int,
) -> None:
    """Each tree is the cheapest under the penalised weights among the sets not yet listed."""
    got = planner.plan_k(goal, min(n, 4), method, diverse=True)
    assert len(got) == min(n, 4)
    penalty = math.log(2) if method == "optimal-success" else 1.0
    uses: dict[int, int] = {}
    earlier: set[frozenset[int]] = set()
    for r in got:
        s = frozenset(r.units)
        assert s not in earlier

        def w(fu: int, uses: dict[int, int] = uses) -> float:
            return weight(fu) + penalty * uses.get(fu, 0)  # type: ignore[operator]

        pen = kref.best_by_set(rf, trees, goal, k, utensils, w, leaf)
        rest = [v for u, v in pen.items() if u not in earlier]
        assert pen[s] == min(rest)
        costs = {kref.cost(rf, t, goal, k, utensils, weight, leaf)  # type: ignore[arg-type]
                 for t in trees if t.units == s}  # fmt: skip
        assert (math.log(1 / r.cost) if method == "optimal-success" else r.cost) in costs or (
            method == "optimal-success" and any(math.exp(-c) == r.cost for c in costs)
        )
        earlier.add(s)
        for fu in s:
            uses[fu] = uses.get(fu, 0) + 1


@SETTINGS
@given(g=gen_foons(), data=st.data())
def test_generated_foons(g: GenFoon, data: st.DataObject) -> None:
    """100 hypothesis FOONs, each checked for every objective (generating a FOON costs more
    than checking it): up to two goals each (diverse lists for optimal-units;
    every objective under -m slow), the produced ones first."""
    case = draw_case(data, g)
    for goal in case.goals[-2:]:
        _check_goal(case, goal, OPTIMAL, ("optimal-units",))


def _seeded_case(seed: int) -> Case:
    """A small FOON from a seed (cheaper to make than a hypothesis one): plain units over a
    shared pool, self-loops, duplicates (dropped on load), two-unit cycles and container-rule
    units, and twin units (two units making the same pair); a kitchen of most raw items and a few made ones, rates with ties, 0 and 1."""
    rnd = random.Random(seed)

    def obj() -> GenObject:
        ings = tuple(rnd.sample(INGREDIENTS, rnd.randint(1, 2))) if rnd.random() < 0.2 else ()
        cont = rnd.choice((None, *CONTAINERS))
        return GenObject(rnd.choice(LABELS), tuple(rnd.sample(STATES, rnd.randint(0, 1))), ings,
                         cont)  # fmt: skip

    pool = [obj() for _ in range(rnd.randint(2, 5))]

    def some(lo: int, hi: int) -> tuple[GenObject, ...]:
        return tuple(rnd.choice(pool) for _ in range(rnd.randint(lo, hi)))

    fus: list[GenFU] = []
    for _ in range(rnd.randint(3, 14)):
        kind = rnd.choice(("plain", "plain", "plain", "self-loop", "duplicate", "cycle",
                           "container", "twins"))  # fmt: skip
        m = rnd.choice(MOTIONS)
        if kind == "plain":
            fus.append(GenFU(m, some(0, 3), some(1, 2)))
        elif kind == "self-loop":
            ins = some(1, 2)
            fus.append(GenFU(m, ins, (rnd.choice(ins), *some(0, 1))))
        elif kind == "duplicate" and fus:
            fus.append(rnd.choice(fus))
        elif kind == "cycle":
            a, b = rnd.choice(pool), rnd.choice(pool)
            fus.append(GenFU(m, (a, *some(0, 1)), (b,)))
            fus.append(GenFU(rnd.choice(MOTIONS), (b,), (a,)))
        elif kind == "container":
            u, x = rnd.choice(UTENSILS), rnd.choice(INGREDIENTS)
            holder, held = GenObject(u, (), (x,)), GenObject(x, (), (), u)
            out = GenObject(u, (rnd.choice(STATES),), (x,))
            pool.extend((holder, held, out))
            fus.append(GenFU(m, (holder, held), (out,)))
        elif kind == "twins":
            # Two units making the same pair, and a unit needing both: two choice
            # assignments (each object from another unit) give one set of units.
            a, b = rnd.choice(pool), obj()
            c = obj()
            pool.extend((b, c))
            fus.append(GenFU(m, some(0, 1), (a, b)))
            fus.append(GenFU(rnd.choice(MOTIONS), some(0, 1), (b, a)))
            fus.append(GenFU(rnd.choice(MOTIONS), (a, b), (c,)))
    lines: list[str] = []
    for fu in fus:
        lines += _render_fu(rnd, fu)
    text = "\n".join(lines) + "\n"
    rf = ref.parse(text)
    f = foon.Foon.from_text(text)
    n = len(rf.objects)
    kitchen = [ident for o, ident in enumerate(rf.objects)
               if (rnd.random() < 0.9 if not rf.producers(o) else rnd.random() < 0.15)]  # fmt: skip
    items = [foon.Object(*ident) for ident in kitchen]
    utensils = set(rnd.choice((UTENSILS, ())))
    rates = {m: rnd.choice(RATES) for m in MOTIONS}
    # Goals: made objects, those with several producers first.
    produced = sorted((o for o in range(n) if rf.producers(o)),
                      key=lambda o: (-len(rf.producers(o)), rnd.random()))  # fmt: skip
    goals = sorted(produced[:2])
    return Case(rf, f, kitchen, foon.Kitchen(items), utensils, rates, goals)


def test_seeded_foons() -> None:
    """500 seeded FOONs, every objective (diverse lists for optimal-units and -success); most
    goals must be within the reference's budget."""
    checked = 0
    for seed in range(500):
        case = _seeded_case(seed)
        for goal in case.goals:
            checked += _check_goal(case, goal, OPTIMAL, ("optimal-units", "optimal-success"))
    assert checked >= 500


@pytest.mark.slow
@settings(SETTINGS, max_examples=3000)
@given(g=gen_foons(), data=st.data())
def test_generated_foons_many(g: GenFoon, data: st.DataObject) -> None:
    """As above, on 3,000 FOONs and every goal."""
    case = draw_case(data, g)
    for goal in case.goals:
        _check_goal(case, goal, OPTIMAL, OPTIMAL)


def test_bad_arguments() -> None:
    ex = foon.example()
    p = ex.foon.planner(ex.kitchen, utensils=ex.utensils)
    g = ex.goals[0]
    with pytest.raises(ValueError, match="k must be at least 1"):
        p.plan_k(g, 0)
    with pytest.raises(TypeError):
        p.plan_k(g, "3")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="optimal method"):
        p.plan_k(g, 3, "ids")
    with pytest.raises(ValueError, match="max_trees"):
        p.paths(g, max_trees=-1)


def test_counts_and_limits_name_their_argument() -> None:
    """Every count or limit argument: a negative one or a bool is refused with its name; one
    too large for the core is no limit (the same result as none)."""
    ex = foon.example()
    p = ex.foon.planner(ex.kitchen, utensils=ex.utensils)
    g = ex.goals[0]
    huge = 2**70
    calls = {
        "k": lambda v: p.plan_k(g, v),
        "node_limit": lambda v: [p.plan(g, "optimal-shared", node_limit=v)],
        "max_trees": lambda v: list(p.paths(g, max_trees=v, max_height=4)),
        "max_height": lambda v: list(p.paths(g, max_trees=5, max_height=v)),
    }
    unbounded = {
        "k": 10**6,
        "node_limit": None,
        "max_trees": None,
        "max_height": None,
    }
    for name, call in calls.items():
        for bad in (-1, -huge):
            with pytest.raises(ValueError, match=f"^{name} must (not be negative|be at least 1), "):
                call(bad)
        with pytest.raises(TypeError, match=f"^{name} must be an int.*, not bool$"):
            call(True)
        with pytest.raises(TypeError, match=f"^{name} must be an int.*, not str$"):
            call("3")
        big = [(t.units, t.cost) for t in call(huge)]
        assert big == [(t.units, t.cost) for t in call(unbounded[name])], name
        assert big, name
    with pytest.raises(ValueError, match=r"^k must not be negative, not -1$"):
        ex.foon.find_similar("onion", -1)
    with pytest.raises(TypeError, match=r"^k must be an int, not bool$"):
        ex.foon.find_similar("onion", True)  # type: ignore[arg-type]
    assert ex.foon.find_similar("onion", huge) == ex.foon.find_similar("onion", 10**6)


@pytest.mark.parametrize("method", OPTIMAL)
def test_course_goals(course: Course, method: str) -> None:
    """On the course FOON: k = 1 is the optimal plan, costs never decrease, the sets are
    distinct and every tree runs."""
    p = course.foon.planner(course.kitchen, motions=course.motions, utensils=course.utensils)
    for g in course.goals5:
        plan = p.plan(g, method)
        got = p.plan_k(g, 20, method)
        if not plan.solved:
            assert got == []
            continue
        assert got[0].units == plan.units and got[0].cost == plan.cost
        costs = [r.cost for r in got]
        assert costs == sorted(costs, reverse=method == "optimal-success")
        assert len({frozenset(r.units) for r in got}) == len(got)
        assert all(r.tree.is_valid() for r in got)


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "foon", *args], capture_output=True, text=True,
                          check=False)  # fmt: skip


def _paths_cli(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    """``foon paths`` through its module (its parser options and command)."""
    import argparse

    from foon._cli_paths import add_paths_options, cmd_paths

    ap = argparse.ArgumentParser()
    add_paths_options(ap)
    code = cmd_paths(ap.parse_args(args))
    return code, capsys.readouterr().out


BASE = ["--foon", str(DATA / "FOON.txt"), "--kitchen", str(DATA / "kitchen.json"),
        "--utensils", str(DATA / "utensils.txt")]  # fmt: skip


def _goal(course: Course) -> tuple[foon.Planner, foon.Object, list[str]]:
    """The first of the 25 course goals with three trees or more, and its --goal option."""
    p = course.foon.planner(course.kitchen, utensils=course.utensils)
    g = next(g for g in course.goals25 if len(p.plan_k(g, 3)) == 3)
    return p, g, ["--goal", json.dumps(g.to_dict())]


def test_cli_plan_k(course: Course) -> None:
    p, goal, arg = _goal(course)
    want = p.plan_k(goal, 3)
    r = _cli("plan", *BASE, *arg, "--method", "optimal-units", "--k", "3")
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith(f"# goal: {goal.label}\n#1 cost {want[0].cost:g}")
    assert f"#{len(want)} cost" in r.stdout
    r = _cli("plan", *BASE, *arg, "--method", "optimal-units", "--k", "3",
             "--format", "json")  # fmt: skip
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert [t["rank"] for t in d[0]["trees"]] == list(range(1, len(want) + 1))
    assert [t["units"] for t in d[0]["trees"]] == [t.units for t in want]
    r = _cli("plan", *BASE, *arg, "--method", "optimal-units", "--k", "3",
             "--diverse", "--format", "json")  # fmt: skip
    assert r.returncode == 0, r.stderr
    want = p.plan_k(goal, 3, diverse=True)
    assert [t["units"] for t in json.loads(r.stdout)[0]["trees"]] == [t.units for t in want]
    r = _cli("plan", *BASE, *arg, "--method", "ids", "--k", "3")
    assert r.returncode != 0 and "Traceback" not in r.stderr and "optimal" in r.stderr


def test_paths_end_when_no_tree_can_be_low_enough(course: Course) -> None:
    """A height limit below every tree of the goal, or trees that fit fewer than asked: the
    enumeration ends (at once when the goal's rank is above the limit)."""
    planner = foon.Planner(course.foon, course.kitchen, motions=course.motions,
                           utensils=course.utensils)  # fmt: skip
    ranks = planner.ranks()
    deep = max((r, g) for g, r in enumerate(ranks) if r is not None and r >= 8)[1]
    r = ranks[deep]
    assert r is not None
    assert list(planner.paths(deep, max_trees=1, max_height=r - 1)) == []
    assert list(planner.paths(deep, max_height=2)) == []
    some = list(planner.paths(deep, max_trees=3, max_height=r))
    assert 1 <= len(some) <= 3
    for t in some:
        height = t.tree.height
        assert height is not None and height <= r
        assert t.tree.is_valid(course.kitchen, course.utensils)


def test_cli_paths(course: Course, capsys: pytest.CaptureFixture[str]) -> None:
    p, goal, arg = _goal(course)
    code, out = _paths_cli([*BASE, *arg, "--max-trees", "4", "--json"], capsys)
    assert code == 0
    d = json.loads(out)
    assert [t["units"] for t in d[0]["trees"]] == [t.units for t in p.paths(goal, max_trees=4)]
    code, out = _paths_cli([*BASE, *arg, "--max-trees", "2"], capsys)
    assert code == 0 and "#2 cost" in out and "#3 cost" not in out
    code, out = _paths_cli([*BASE, *arg, "--max-height", "0"], capsys)
    assert code == 1 and "no tree" in out
