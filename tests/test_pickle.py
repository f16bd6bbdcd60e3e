"""Foon, Planner and TaskTree pickle and deep-copy: a round trip gives equal objects that
plan the same trees, in this process and in worker processes."""

from __future__ import annotations

import copy
import multiprocessing
import pickle
import warnings
from concurrent.futures import ProcessPoolExecutor

import foon
import pytest
from conftest import Course

#: Dropped duplicates (the second and fourth units), a bare output (knife), an FU without a
#: motion (dropped with a warning), an unterminated last unit (kept with a warning), lab
#: metadata, and objects whose states are written in different orders.
AWKWARD = (
    "O\tonion\nS\twhole\nM\tpeel\nO\tonion\nS\tpeeled\n//\n"
    "O\tonion\nS\twhole\nM\tpeel\nO\tonion\nS\tpeeled\n//\n"
    "O\tonion\nS\tpeeled\nO\tknife\nM\tchop\nO\tonion\nS\tchopped\nS\tsmall\nO\tknife\n//\n"
    "O\tonion\nS\twhole\nM\tpeel\nO\tonion\nS\tpeeled\n//\n"
    "O\tbowl\nO\tonion\nS\tsmall\nS\tchopped\n//\n"
    "O\tonion\nS\tsmall\nS\tchopped\nO\tbowl\nS\tempty\nM\tpour\nO\tbowl\nS\tcontains\t{onion}\n"
    "O\tonion\nS\tchopped\nS\tsmall\nS\tin\t[bowl]\n"
)


def awkward(text: str = AWKWARD) -> foon.Foon:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", foon.FoonWarning)
        return foon.Foon.from_text(text, path="awkward.foon")


def same_content(a: foon.Foon, b: foon.Foon) -> None:
    """Every observable part of two FOONs is equal."""
    assert a == b and hash(a) == hash(b)
    assert a.stats() == b.stats()
    assert a.warnings == b.warnings
    assert a._native.duplicates() == b._native.duplicates()
    assert a._native.source == b._native.source
    assert [a.object(i) for i in range(a.object_count)] == [
        b.object(i) for i in range(b.object_count)
    ]
    # First written forms (state order) survive too, not only identities.
    assert [a.object(i).states for i in range(a.object_count)] == [
        b.object(i).states for i in range(b.object_count)
    ]
    assert [a.fu(i) for i in range(a.fu_count)] == [b.fu(i) for i in range(b.fu_count)]
    assert [a.fu_text(i) for i in range(a.fu_count)] == [b.fu_text(i) for i in range(b.fu_count)]
    assert [a.producers(o) for o in range(a.object_count)] == [
        b.producers(o) for o in range(b.object_count)
    ]
    assert a.to_text() == b.to_text()


def test_the_awkward_foon_is_awkward() -> None:
    f = awkward()
    assert [k for _, _, _, k, _ in f.warnings] == ["no-motion", "unterminated"]
    assert f._native.duplicates() == [(7, 0), (22, 0)]
    knife = f.find(foon.Object("knife"))
    assert knife is not None and f.producers(knife) == []  # a bare output is not produced


@pytest.mark.parametrize("make", [lambda: awkward(), lambda: foon.example().foon])
def test_foon_round_trips(make: object) -> None:
    f = make()  # type: ignore[operator]
    for protocol in range(2, pickle.HIGHEST_PROTOCOL + 1):
        same_content(pickle.loads(pickle.dumps(f, protocol)), f)
    same_content(copy.deepcopy(f), f)
    assert copy.copy(f) is f and copy.deepcopy(f) is f  # immutable: copies are the object
    g = awkward(AWKWARD.replace("chop", "dice"))
    assert g != f


def test_course_foon_round_trips(course: Course) -> None:
    f = course.foon
    g = pickle.loads(pickle.dumps(f))
    same_content(g, f)
    assert g.stats()["duplicates_dropped"] == f.stats()["duplicates_dropped"]


def test_a_corrupt_serialised_form_is_a_value_error() -> None:
    data = foon.example().foon._native.to_bytes()
    for bad in (data[:-1], data[:20], b"nonsense", data + b"x"):
        with pytest.raises(ValueError, match="not a serialised FOON"):
            foon._foon.Foon.from_bytes(bad)


def planned() -> tuple[foon.Planner, list[foon.TaskTree]]:
    ex = foon.example()
    p = ex.foon.planner(ex.kitchen, motions=ex.motions, utensils=ex.utensils)
    trees = [p.plan(g, m) for g in ex.goals for m in ("ids", "greedy-success", "bfs")]
    return p, trees


def test_planner_and_trees_round_trip() -> None:
    p, trees = planned()
    for q in (pickle.loads(pickle.dumps(p)), copy.deepcopy(p)):
        assert q == p and hash(q) == hash(p) and q is not p
        assert q.kitchen == p.kitchen and q.utensils == p.utensils and q.motions == p.motions
        ex = foon.example()
        assert [q.plan(g).units for g in ex.goals] == [p.plan(g).units for g in ex.goals]
    for t in trees:
        for u in (pickle.loads(pickle.dumps(t)), copy.deepcopy(t)):
            assert u == t and u.to_dict() == t.to_dict()
            assert [fu.index for fu in u] == t.units and list(u) == list(t)
            assert u.is_valid() == t.is_valid()
            for fu in t:
                assert pickle.loads(pickle.dumps(fu)) == fu
    # One pickle of many trees stores their FOON once.
    many = pickle.dumps(trees)
    assert len(many) < 2 * len(pickle.dumps(trees[0]))
    back = pickle.loads(many)
    assert all(b.foon is back[0].foon for b in back) and back == trees


def plan_in_worker(planner: foon.Planner, goal: foon.Object) -> foon.TaskTree:
    return planner.plan(goal, "greedy-success")


@pytest.mark.parametrize("context", ["spawn", "fork"])
def test_process_pools_plan_the_same_trees(context: str) -> None:
    if context not in multiprocessing.get_all_start_methods():
        pytest.skip(f"no {context} start method here")
    p, _ = planned()
    ex = foon.example()
    want = [p.plan(g, "greedy-success") for g in ex.goals]
    # A batch on worker threads first, so that a forked child inherits a built pool (which it
    # must not use: its threads do not exist in the child).
    p.plan_many(ex.goals * 10, threads=2)
    with warnings.catch_warnings():
        # Python 3.12+ warns about fork in a process with threads.
        warnings.simplefilter("ignore", DeprecationWarning)
        ctx = multiprocessing.get_context(context)
        with ProcessPoolExecutor(2, mp_context=ctx) as pool:
            got = list(pool.map(plan_in_worker, [p] * len(ex.goals), ex.goals, timeout=120))
            batch = pool.submit(batch_in_worker, p, ex.goals).result(timeout=120)
    assert got == want
    assert batch == [t.units for t in p.plan_many(ex.goals * 10)]


def batch_in_worker(planner: foon.Planner, goals: list[foon.Object]) -> list[list[int]]:
    return [t.units for t in planner.plan_many(goals * 10, threads=2)]


SYNTH_UNITS = 3_000  # about 1 MB of text: several parse chunks, read on the worker pool


def load_and_plan_in_child(text: str, goals: list[foon.Object]) -> list[list[int]]:
    """Everything that runs in parallel inside the core, in a forked child: a parse of several
    chunks, the index build, what a prepared kitchen computes once per method."""
    f = foon.Foon.from_text(text)
    p = f.planner(foon.synth_kitchen(SYNTH_UNITS, 1), motions=foon.synth_motions())
    return [
        t.units
        for m in ("greedy-success", "greedy-inputs", "optimal-units")
        for t in p.plan_many(goals, m)
    ]


def test_a_forked_child_runs_every_parallel_step_after_its_parent_did() -> None:
    if "fork" not in multiprocessing.get_all_start_methods():
        pytest.skip("no fork start method here")
    text = foon.synth(SYNTH_UNITS, 1)
    goals = foon.synth_goals(SYNTH_UNITS, 1, 10)
    # The parent runs every parallel step first, so that a forked child inherits their pool.
    want = load_and_plan_in_child(text, goals)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("fork")) as pool:
            got = pool.submit(load_and_plan_in_child, text, goals).result(timeout=120)
    assert got == want
