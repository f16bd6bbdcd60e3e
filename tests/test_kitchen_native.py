"""The native kitchen: ``foon.Kitchen`` is a handle on the core's set of identities, and it
behaves as the list of objects it replaces (membership, repeats, equality in any order, the
objects matched in a FOON), on the real kitchen files and on generated ones; it pickles, and
bad kitchen files give the errors the list parser gives (file, line, column)."""

from __future__ import annotations

import gc
import json
import pickle
import random
from pathlib import Path

import foon
import foon_reference as ref
import pytest
from conftest import DATA, Course, need_shared
from foon import _foon
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_differential import GenFoon, gen_foons

Fields = tuple[str, tuple[str, ...], tuple[str, ...], str | None]


def written(objs: object) -> list[Fields]:
    """Each object's fields as written (``Object.__eq__`` compares identities only)."""
    return [o._fields() for o in objs]  # type: ignore[attr-defined]


def list_semantics(raw: list[tuple[str, list[str], list[str], str | None]]) -> list[foon.Object]:
    """The old kitchen: the list parser's objects, a repeated identity kept at its first place."""
    seen: set[foon.Object] = set()
    out = []
    for t in raw:
        o = foon.Object(*t)
        if o not in seen:
            seen.add(o)
            out.append(o)
    return out


def kitchen_files() -> list[Path]:
    need_shared()
    files = [DATA / "kitchen.json", *sorted((DATA / "lab_history").glob("kitchen*"))]
    assert len(files) > 5
    return files


def test_real_kitchens_behave_as_their_lists(course: Course) -> None:
    for path in kitchen_files():
        raw = _foon.load_objects(path, "kitchen")
        want = list_semantics(raw)
        k = foon.Kitchen.load(path)
        assert written(k) == written(want), path
        assert len(k) == len(want) and k.items == tuple(want)
        assert all(foon.Object(*t) in k for t in raw)
        assert all(o.to_dict() in k for o in want[:50])
        # Shuffled and repeated, it is the same kitchen.
        shuffled = list(want) + want[:7]
        random.Random(len(want)).shuffle(shuffled)
        other = foon.Kitchen(shuffled)
        assert other == k and hash(other) == hash(k) and other.fingerprint == k.fingerprint
        assert foon.Kitchen.from_text(path.read_bytes()) == k
        # The objects matched in the FOON are those whose identity is an item's.
        rf = course_ref()
        expect = sorted(ref.kitchen_ids(rf, [o.identity() for o in want]))
        assert course.foon.planner(k)._native.kitchen_objects() == expect, path
        if path.suffix == ".json":
            idents = ref.read_kitchen_json(path.read_text())
            assert {o.identity() for o in k} == set(idents)
    assert len(course.kitchen) == 1174


_REF: list[ref.RefFoon] = []


def course_ref() -> ref.RefFoon:
    if not _REF:
        _REF.append(ref.parse((DATA / "FOON.txt").read_text()))
    return _REF[0]


def test_planning_accepts_every_kitchen_form(course: Course, tmp_path: Path) -> None:
    goal = course.goals5[1]
    items = [o.to_dict() for o in course.kitchen]
    path = tmp_path / "k.json"
    path.write_text(json.dumps(items))
    kw = {"motions": course.motions, "utensils": course.utensils}
    trees = [
        course.foon.plan(goal, k, "greedy-success", **kw)  # type: ignore[arg-type]
        for k in (course.kitchen, items, list(course.kitchen), path, str(path))
    ]
    assert all(t.units == trees[0].units and t.solved for t in trees)
    assert not course.foon.plan(goal, None, "ids").solved
    checks = [
        [vars(x) for x in foon.check([DATA / "FOON.txt"], kitchen=k, utensils=course.utensils)]
        for k in (course.kitchen, items, path)
    ]
    assert checks[0] == checks[1] == checks[2] and checks[0]
    planner = course.foon.planner(course.kitchen, **kw)  # type: ignore[arg-type]
    back = pickle.loads(pickle.dumps(planner))
    assert back == planner and back.plan(goal).units == planner.plan(goal).units


def test_pickle_round_trip(course: Course) -> None:
    for k in (
        course.kitchen,
        foon.Kitchen(),
        foon.Kitchen([foon.Object("a", ("x", "y"), ("é",), "")]),
    ):
        back = pickle.loads(pickle.dumps(k))
        assert back == k and written(back) == written(k) and back.fingerprint == k.fingerprint
        assert repr(back) == repr(k) == f"Kitchen({len(k)} items)"
    data = course.kitchen._native.to_bytes()
    for bad in (data[:-1], data + b"x", b"FOONKIT2" + data[8:], b""):
        with pytest.raises(ValueError, match="not a valid serialised kitchen"):
            _foon.Kitchen.from_bytes(bad)


def test_with_without_and_indexing() -> None:
    a, b, c = (
        foon.Object("a", ("x", "y")),
        foon.Object("b", (), ("i", "j"), "pot"),
        foon.Object("c"),
    )
    k = foon.Kitchen([a, b, foon.Object("a", ("y", "x"))])
    assert len(k) == 2 and written(k) == written([a, b]) and k[1] == b and k[-1] == b
    with pytest.raises(IndexError, match="out of range"):
        k[2]
    assert k.without([{"label": "a", "states": ["y", "x"]}]) == foon.Kitchen([b])
    assert k.with_items([c, a]) == foon.Kitchen([c, b, a])
    assert written(k.with_items([c, a])) == written([a, b, c])
    assert k.without(k) == foon.Kitchen() and len(foon.Kitchen()) == 0
    assert "a" not in k and {"label": "c"} not in k
    assert foon.Kitchen(k) == k
    assert json.loads(k.to_json())[0] == a.to_dict()


def test_errors_are_those_of_the_list_parser(tmp_path: Path) -> None:
    bad = {
        "motion.txt": "O\tonion\nM\tchop\n",
        "state.txt": "S\tred\n",
        "empty.json": '[{"label": "x", "states": ["  "]}]',
        "type.json": '[{"label": "x",\n "container": 3}]',
        "one.json": '{"label": "x"}',
        "tail.json": '[{"label": "x"}] ,',
        "list.json": '[["ice"]]',
        "field.json": '[{"label": "x", "state": []}]',
        "utf8.txt": b"O\tonion\nS\t\xff\n",
    }
    for name, text in bad.items():
        p = tmp_path / name
        (p.write_bytes if isinstance(text, bytes) else p.write_text)(text)  # type: ignore[operator]
        with pytest.raises(foon.ParseError) as old:
            _foon.load_objects(p, "kitchen")
        with pytest.raises(foon.ParseError) as new:
            foon.Kitchen.load(p)
        assert str(new.value) == str(old.value) and str(p) in str(new.value)
        e, o = new.value, old.value
        assert (e.path, e.line, e.column, e.reason) == (o.path, o.line, o.column, o.reason)  # type: ignore[attr-defined]
        assert "\n" not in str(e)
        with pytest.raises(foon.ParseError):
            foon.Kitchen.from_text(p.read_bytes())


def test_load_builds_no_python_object_per_item(tmp_path: Path) -> None:
    items = [{"label": f"item {i}", "states": ["s", f"t{i % 7}"]} for i in range(20000)]
    path = tmp_path / "big.json"
    path.write_text(json.dumps(items))
    gc.collect()
    before = len(gc.get_objects())
    k = foon.Kitchen.load(path)
    after = len(gc.get_objects())
    assert len(k) == 20000 and after - before < 100
    assert sum(1 for _ in k) == 20000


@st.composite
def kitchens(draw: st.DrawFn) -> tuple[GenFoon, list[foon.Object]]:
    g = draw(gen_foons())
    rf = ref.parse(g.text)
    idents = list(rf.objects)
    items = []
    for _ in range(draw(st.integers(0, 2 * len(idents) + 2))):
        if idents and draw(st.booleans()):
            lab, s, i, c = draw(st.sampled_from(idents))
        else:
            lab = draw(st.sampled_from(("truffle", "onion", "x")))
            s = tuple(draw(st.lists(st.sampled_from(("a", "b")), max_size=2)))
            i, c = (), draw(st.sampled_from((None, "", "bowl")))
        items.append(foon.Object(lab, draw(st.permutations(s)), draw(st.permutations(i)), c))
    return g, items


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kitchens(), st.randoms(use_true_random=False))
def test_generated_kitchens_behave_as_lists(case: tuple[GenFoon, list[foon.Object]],
                                            rnd: random.Random) -> None:  # fmt: skip
    g, items = case
    k = foon.Kitchen(items)
    want = list_semantics([o._tuple() for o in items])
    assert written(k) == written(want)
    assert all(o in k for o in items)
    shuffled = items + items[: len(items) // 2]
    rnd.shuffle(shuffled)
    other = foon.Kitchen(shuffled)
    assert other == k and other.fingerprint == k.fingerprint
    fewer = foon.Kitchen(want[1:])
    assert (fewer == k) == (len(want) == 0)
    assert (fewer.fingerprint == k.fingerprint) == (len(want) == 0)
    text = foon.Kitchen.from_text(k.to_json())
    assert text == k and written(text) == written(k)
    rf = ref.parse(g.text)
    f = foon.Foon.from_text(g.text)
    expect = sorted(ref.kitchen_ids(rf, [o.identity() for o in items]))
    assert f.planner(k)._native.kitchen_objects() == expect
