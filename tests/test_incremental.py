"""Incremental kitchens (docs/METHODS.md, "Incremental kitchens"): a planner for a kitchen given
as a planner plus a delta (``Planner.with_changes``) gives exactly the results of a planner
prepared from scratch for the new kitchen: the ranks, and every method's plan (units, cost,
explanation, counts) for every object, whether the base planner had computed its ranks,
choices and costs before the change or not; on generated FOONs (cycles, duplicates,
self-loops, bare outputs, the container rule, rates of 0 and 1) with random kitchens and deltas,
and on the course FOON."""

from __future__ import annotations

import gc
import random
import weakref

import foon
import pytest
from conftest import Course
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_differential import RESULT_FIELDS, Case, GenFoon, draw_case, gen_foons

#: Every sound method (the ones whose preparation is per kitchen) and the course loop.
METHODS = ("ids", "optimal-success", "optimal-units", "optimal-inputs", "greedy-success",
           "greedy-inputs")  # fmt: skip

SETTINGS = settings(max_examples=200, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow,
                                           HealthCheck.data_too_large])  # fmt: skip


def results(p: foon.Planner) -> dict[str, list[tuple[object, ...]]]:
    """Every method's plan for every object, as tuples of every result field."""
    goals = list(range(p.foon.object_count))
    return {
        m: [tuple(getattr(t, a) for a in RESULT_FIELDS) for t in p.plan_many(goals, m, threads=1)]
        for m in METHODS
    }


def check(base: foon.Planner, add: list[foon.Object], remove: list[foon.Object],
          warm: bool) -> None:  # fmt: skip
    """`base.with_changes(add, remove)` against a planner prepared from scratch; with `warm`,
    the base has computed everything (ranks, choices, costs) before the change."""
    if warm:
        base.ranks()
        results(base)
    inc = base.with_changes(add=add, remove=remove)
    kitchen = base.kitchen.without(remove).with_items(add)
    fresh = foon.Planner(base.foon, kitchen, motions=base.motions, utensils=base.utensils,
                         level=base.level)  # fmt: skip
    assert inc.kitchen == kitchen
    assert inc == fresh
    assert inc.ranks() == fresh.ranks()
    want = results(fresh)
    assert results(inc) == want
    # Goals planned one by one in a random order, the methods interleaved: each plan runs
    # the pending updates of another planner from the same change only as far as its goal.
    one = base.with_changes(add=add, remove=remove)
    order = [(g, m) for g in range(base.foon.object_count) for m in METHODS]
    random.Random(len(order)).shuffle(order)
    for g, m in order:
        t = one.plan(g, m)
        assert tuple(getattr(t, a) for a in RESULT_FIELDS) == want[m][g], (g, m)
    # Run to the end, the updates give the same plans again.
    one.finish_updates()
    assert results(one) == want


def objects_of(f: foon.Foon, ids: list[int]) -> list[foon.Object]:
    return [f.object(i) for i in ids]


@SETTINGS
@given(g=gen_foons(), data=st.data())
def test_generated_foons(g: GenFoon, data: st.DataObject) -> None:
    """Random FOONs and kitchens (matched at identity level 3, 2 or 1), random deltas of up to
    four additions and four removals (objects of the FOON, kitchen items or not, and an item
    the FOON does not have)."""
    case: Case = draw_case(data, g)
    f = case.f
    n = f.object_count
    level = data.draw(st.sampled_from((3, 3, 2, 1)), label="level")
    base = foon.Planner(f, case.rkitchen, motions=case.rates, utensils=sorted(case.utensils),
                        level=level)  # fmt: skip
    ids = st.lists(st.integers(0, n - 1), max_size=4)
    add = objects_of(f, data.draw(ids, label="add"))
    remove = objects_of(f, data.draw(ids, label="remove"))
    if data.draw(st.booleans(), label="unknown item"):
        add.append(foon.Object("truffle", ("sliced",)))
    check(base, add, remove, warm=data.draw(st.booleans(), label="warm"))


def test_changes_chain() -> None:
    """A planner changed again and again (each from the previous one) stays equal to one
    prepared from scratch."""
    text = (
        "O\ta\nS\tx\nM\tmix\nO\tb\nS\tx\n//\n"
        "O\tb\nS\tx\nM\tmix\nO\tc\nS\tx\n//\n"
        "M\tchop\nO\tc\nS\tx\n//\n"
        "O\tc\nS\tx\nO\ta\nS\tx\nM\tmix\nO\td\nS\tx\n//\n"
        "O\td\nS\tx\nM\tmix\nO\ta\nS\tx\n//\n"
    )
    f = foon.Foon.from_text(text)
    p = foon.Planner(f, [f.object(0)], motions={"mix": 0.5, "chop": 1.0})
    rnd = random.Random(3)
    for _ in range(30):
        add = objects_of(f, rnd.sample(range(f.object_count), rnd.randint(0, 2)))
        remove = objects_of(f, rnd.sample(range(f.object_count), rnd.randint(0, 2)))
        check(p, add, remove, warm=True)
        p = p.with_changes(add=add, remove=remove)


def test_changes_chain_builds_its_kitchen_on_first_use() -> None:
    """A chain of changes whose kitchens are never read keeps no planner of the chain alive,
    and its kitchen, read at the end, is the changes applied in order."""
    text = "".join(f"O\ti{i}\nS\tx\nM\tmix\nO\ti{i + 1}\nS\tx\n//\n" for i in range(8))
    f = foon.Foon.from_text(text)
    p = foon.Planner(f, [f.object(0), f.object(3)])
    want = p.kitchen
    first = weakref.ref(p)
    rnd = random.Random(5)
    for _ in range(20):
        add = objects_of(f, rnd.sample(range(f.object_count), rnd.randint(0, 2)))
        remove = objects_of(f, rnd.sample(range(f.object_count), rnd.randint(0, 2)))
        p = p.with_changes(add=add, remove=remove)
        want = want.without(remove).with_items(add)
    gc.collect()
    assert first() is None
    assert p.kitchen == want
    assert [o._fields() for o in p.kitchen] == [o._fields() for o in want]  # order and forms
    fresh = foon.Planner(f, want)
    assert p == fresh and p.ranks() == fresh.ranks()
    for g in range(f.object_count):
        assert p.plan(g, "ids").units == fresh.plan(g, "ids").units


def test_no_change_and_bad_items() -> None:
    f = foon.Foon.from_text("O\ta\nS\tx\nM\tmix\nO\tb\nS\tx\n//\n")
    p = foon.Planner(f, [f.object(0)])
    p.ranks()
    same = p.with_changes()
    assert same == p and same.ranks() == p.ranks() == [0, 1]
    gone = p.with_changes(remove=[f.object(0)])
    assert gone.ranks() == [None, None]
    with pytest.raises(TypeError):
        p.with_changes(add=[42])  # type: ignore[list-item]
    # Items, never a file; the error names the argument.
    for kw, name in [({"add": "a"}, "add"), ({"remove": "kitchen.json"}, "remove"),
                     ({"add": 42}, "add"), ({"remove": f.object(0)}, "remove"),
                     ({"add": f}, "add")]:  # fmt: skip
        with pytest.raises(TypeError, match=f"^{name} must be an iterable of objects"):
            p.with_changes(**kw)  # type: ignore[arg-type]


def test_a_derived_planner_has_its_own_utensils() -> None:
    f = foon.Foon.from_text("O\ta\nS\tx\nM\tmix\nO\tb\nS\tx\n//\n")
    p = foon.Planner(f, [f.object(0)], utensils=["knife"])
    q = p.with_changes(add=[f.object(1)])
    p.utensils.clear()
    assert q.utensils == ["knife"]


@pytest.mark.parametrize("seed", [1, 2])
def test_course_deltas(course: Course, seed: int) -> None:
    """The course FOON with its kitchen, utensils and rates: deltas of one to ten items
    (additions from the FOON's objects, removals from the kitchen, both)."""
    f = course.foon
    base = foon.Planner(f, course.kitchen, motions=course.motions, utensils=course.utensils)
    base.ranks()
    results(base)
    rnd = random.Random(seed)
    items = list(course.kitchen)
    for size in (1, 3, 10):
        add = objects_of(f, rnd.sample(range(f.object_count), size))
        remove = rnd.sample(items, min(size, len(items)))
        for a, r in ((add, []), ([], remove), (add[: size // 2 + 1], remove[: size // 2])):
            inc = base.with_changes(add=a, remove=r)
            fresh = foon.Planner(f, course.kitchen.without(r).with_items(a),
                                 motions=course.motions, utensils=course.utensils)  # fmt: skip
            assert inc.ranks() == fresh.ranks()
            want = results(fresh)
            assert results(inc) == want
            # The goals one by one, in a random order, through the pending updates.
            one = base.with_changes(add=a, remove=r)
            goals = list(range(f.object_count))
            rnd.shuffle(goals)
            for m in ("optimal-units", "optimal-success"):
                for g in goals[:400]:
                    t = one.plan(g, m)
                    assert tuple(getattr(t, x) for x in RESULT_FIELDS) == want[m][g], (g, m)


def test_finish_updates_from_several_threads() -> None:
    """Plans from several Python threads at once on a planner whose updates are pending, and
    `finish_updates` called meanwhile, give the plans of a planner prepared from scratch."""
    from concurrent.futures import ThreadPoolExecutor

    text = "".join(
        f"O\ti{i}\nS\tx\nO\tj{i % 7}\nS\tx\nM\tmix\nO\ti{i + 1}\nS\tx\n//\n"
        f"O\tj{i % 7}\nS\tx\nM\tchop\nO\ti{i + 2}\nS\tx\n//\n"
        for i in range(60)
    )
    f = foon.Foon.from_text(text)
    kitchen = [f.object(0)] + [o for o in (f.object(i) for i in range(f.object_count))
                               if o.label.startswith("j")]  # fmt: skip
    base = foon.Planner(f, kitchen, motions={"mix": 0.5, "chop": 0.9})
    results(base)
    add = [f.object(5), f.object(11)]
    inc = base.with_changes(add=add)
    fresh = foon.Planner(f, base.kitchen.with_items(add), motions={"mix": 0.5, "chop": 0.9})
    want = results(fresh)
    jobs = [(g, m) for g in range(f.object_count) for m in METHODS]
    random.Random(9).shuffle(jobs)

    def plan(job: tuple[int, str]) -> tuple[object, ...]:
        g, m = job
        if g == 3 and m == "ids":
            inc.finish_updates()
        t = inc.plan(g, m)
        return tuple(getattr(t, a) for a in RESULT_FIELDS)

    with ThreadPoolExecutor(4) as ex:
        got = list(ex.map(plan, jobs))
    assert got == [want[m][g] for g, m in jobs]


@pytest.mark.parametrize("seed", [1, 2])
def test_synthetic_deltas_at_size(seed: int) -> None:
    """A synthetic FOON large enough that the update passes take their large-FOON path (the
    changes kept in arrays once they are thousands, levels of hundreds of objects): additions
    of made objects (each lowers the cost of much of what is made from it), removals and both,
    against a planner prepared from scratch, goal by goal through the pending updates and run
    to the end."""
    units = 60_000
    f = foon.Foon.from_text(foon.synth(units, seed))
    kitchen = foon.synth_kitchen(units, seed)
    motions = foon.synth_motions()
    base = foon.Planner(f, kitchen, motions=motions)
    rnd = random.Random(seed)
    goals = sorted({f.find(g) for g in foon.synth_goals(units, seed, 40)} - {None})
    goals += rnd.sample(range(f.object_count), 40)
    methods = ("ids", "optimal-units", "optimal-success", "optimal-inputs")
    for m in methods:
        base.plan_many(goals, m)
    inside = {f.find(o) for o in kitchen}
    made = [o for o in range(f.object_count) if o not in inside and f.producers(o)]
    add = objects_of(f, rnd.sample(made, 10))
    remove = rnd.sample(list(kitchen), 10)
    for a, r in ((add, []), ([], remove), (add[:5], remove[:5])):
        fresh = foon.Planner(f, kitchen.without(r).with_items(a), motions=motions)
        want = {m: fresh.plan_many(goals, m) for m in methods}
        inc = base.with_changes(add=a, remove=r)
        assert inc.ranks() == fresh.ranks()
        for m in methods:
            got = [inc.plan(g, m) for g in goals]
            assert [tuple(getattr(t, x) for x in RESULT_FIELDS) for t in got] == [
                tuple(getattr(t, x) for x in RESULT_FIELDS) for t in want[m]
            ], m
        inc.finish_updates()
        for m in methods:
            assert inc.plan_many(goals, m) == want[m], m
