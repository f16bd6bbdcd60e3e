"""Batches of queries in the core (``foon._arrow.plan_table``, ``foon.KitchenSet``) against
``batch_reference``, which answers each row alone with ``Foon.plan``: on the course FOON and
on generated FOONs (cycles, duplicates, self-loops), every method, bad rows, 1 and 2
threads; the kitchen-set forms, errors, bytes and pickling; the query table's checks."""

from __future__ import annotations

import json
import pickle
import subprocess
import sys
from pathlib import Path
from typing import Any

import batch_reference as bref
import foon
import foon_reference as ref
import pytest
from conftest import DATA, need_shared
from hypothesis import given, settings
from hypothesis import strategies as st
from test_differential import GEN_SETTINGS, GenFoon, draw_case, gen_foons

pa = pytest.importorskip("pyarrow")
from foon._arrow import QUERY_COLUMNS, RESULT_SCHEMA, plan_table

MESSAGE_CODES = {"bad-goal", "bad-option", "error", "missing-rate"}


def table(rows: list[bref.Row], options: bool = True) -> Any:
    cols = QUERY_COLUMNS if options else QUERY_COLUMNS[:4]
    rows = [(str(r[0]), *r[1:]) for r in rows]
    return pa.table({c: pa.array([r[i] for r in rows], pa.string()) for i, c in enumerate(cols)})


def check(
    f: foon.Foon,
    ks: foon.KitchenSet,
    rows: list[bref.Row],
    *,
    motions: foon.MotionRates | None = None,
    utensils: list[str] | None = None,
    default_rate: float | None = None,
) -> list[dict[str, Any]]:
    """plan_table with 1 and 2 threads, delta kitchens prepared incrementally and from
    scratch, equals the reference row by row (the message aside, which is there exactly for
    the codes that keep one)."""
    kitchens = {i: ks[i] for i in ks.ids}
    want = bref.answer(
        f, kitchens, rows, motions=motions, utensils=utensils or [], default_rate=default_rate
    )
    q = table(rows)
    one = None
    for threads, deltas in ((1, "incremental"), (2, "incremental"), (2, "from-scratch"),
                            (1, "from-scratch")):  # fmt: skip
        got = plan_table(
            f, ks, q, threads=threads, motions=motions, utensils=utensils,
            default_rate=default_rate, deltas=deltas,
        )  # fmt: skip
        assert got.schema == RESULT_SCHEMA
        assert got.num_rows == len(rows)
        got_rows = got.to_pylist()
        for i, (g, w) in enumerate(zip(got_rows, want, strict=True)):
            assert (g["message"] is not None) == (g["failure"] in MESSAGE_CODES), (i, rows[i], g)
            g = {**g, "message": None}
            w = {**w, "message": None}
            assert bref.same(g, w), (i, rows[i], g, w)
        if one is None:
            one = got
        else:
            assert got.equals(one)
    return want


# --- the course FOON ------------------------------------------------------------------------


@pytest.fixture(scope="module")
def course() -> dict[str, Any]:
    need_shared()
    f = foon.load(DATA / "FOON.txt")
    k = foon.Kitchen.load(DATA / "kitchen.json")
    items = list(k)
    ks = foon.KitchenSet({"full": k, "half": items[: len(items) // 2], "none": []})
    goals = json.loads((DATA / "goal_nodes_25.json").read_text(encoding="utf-8"))
    return {
        "foon": f,
        "kitchens": ks,
        "goals": [json.dumps(g) for g in goals],
        "motions": foon.MotionRates.load(DATA / "motion.txt"),
        "utensils": foon.load_utensils(DATA / "utensils.txt"),
    }


def test_course_every_method_and_bad_rows(course: dict[str, Any]) -> None:
    rows: list[bref.Row] = []
    kids = ("full", "half", "none")
    for i, g in enumerate(course["goals"]):
        for j, m in enumerate(foon.METHODS):
            rows.append((f"{i}-{m}", kids[(i + j) % 3], g, m, None))
    g0 = course["goals"][0]
    first = json.loads(g0)["label"]
    rows += [
        ("c1", "full", g0, "greedy-inputs", '{"count": "ingredients"}'),
        ("c2", "full", g0, "ids", '{"compat": "course"}'),
        ("c3", "half", g0, "optimal-shared", '{"objective": "success", "node_limit": 1000}'),
        ("c4", "full", g0, "ids", '{"level": 2}'),
        ("c5", "full", first, "ids", '{"level": 1}'),
        ("c6", "full", first, "ids", None),
        ("b1", "nowhere", g0, "ids", None),
        ("b2", "full", "no such label", "ids", None),
        ("b3", "full", "{not json", "ids", None),
        ("b4", "full", g0, "quickest", None),
        ("b5", "full", g0, "ids", '{"speed": 3}'),
        ("b6", "full", g0, "ids", '{"node_limit": 5}'),
        ("b7", "full", g0, "ids", "[]"),
        ("b8", None, g0, "ids", None),
        ("b9", "full", None, None, None),
        ("b10", "full", g0, "optimal-units", '{"compat": "course"}'),
    ]
    want = check(
        course["foon"], course["kitchens"], rows,
        motions=course["motions"], utensils=course["utensils"],
    )  # fmt: skip
    codes = {w["failure"] for w in want}
    # The course data reaches solved rows and the failures of real and of bad rows alike.
    assert None in codes
    assert {"unknown-kitchen", "goal-not-found", "bad-goal", "unknown-method",
            "bad-option", "not-derivable"} <= codes  # fmt: skip
    # An optimal method asked for in its course form is a bad option, found with the others
    # before any planning.
    assert want[[r[0] for r in rows].index("b10")]["failure"] == "bad-option"


def test_course_delta_kitchens(course: dict[str, Any]) -> None:
    # Deltas of the course kitchen (items removed, some added back, a new one added), every
    # method at every level: the same answers as each kitchen built from its items.
    items = list(course["kitchens"]["full"])
    deltas = {}
    for k in range(5):
        remove = items[k::6]
        add = {0: [], 1: remove[:2], 2: [{"label": "water"}]}[k % 3]
        deltas[f"d{k}"] = (add, remove)
    ks = foon.KitchenSet.with_deltas(items, deltas)
    levels = (None, '{"level": 2}', '{"level": 1}')
    rows: list[bref.Row] = []
    for i, g in enumerate(course["goals"]):
        for j, m in enumerate(foon.METHODS):
            rows.append((f"{i}-{m}", f"d{(i + j) % 5}", g, m, levels[(i + 2 * j) % 3]))
    want = check(course["foon"], ks, rows, motions=course["motions"], utensils=course["utensils"])
    codes = {w["failure"] for w in want}
    assert None in codes and "not-derivable" in codes


def test_course_missing_rates_and_default_rate(course: dict[str, Any]) -> None:
    few = foon.MotionRates(dict(list(course["motions"].items())[:3]))
    rows: list[bref.Row] = []
    for i, g in enumerate(course["goals"][:8]):
        for m in ("greedy-success", "optimal-success", "ids"):
            rows.append((str(i), "full", g, m, None))
            rows.append((str(i), "full", g, m, '{"default_rate": 0.5}'))
    want = check(course["foon"], course["kitchens"], rows, motions=few, utensils=course["utensils"])
    assert "missing-rate" in {w["failure"] for w in want}
    check(
        course["foon"], course["kitchens"], rows, motions=few, utensils=course["utensils"],
        default_rate=0.9,
    )  # fmt: skip


# --- generated FOONs ------------------------------------------------------------------------


OPTIONS = (None, "", '{"compat": "course"}', '{"count": "ingredients"}', '{"level": 2}',
           '{"level": 1}', '{"default_rate": 0.25}', '{"objective": "success"}',
           '{"level": 4}', "{")  # fmt: skip


@settings(GEN_SETTINGS, max_examples=80)
@given(g=gen_foons(), data=st.data())
def test_generated_foons_agree(g: GenFoon, data: st.DataObject) -> None:
    case = draw_case(data, g)
    f = case.f
    others = data.draw(st.lists(st.lists(st.integers(0, len(case.rf.objects) - 1), max_size=4),
                                max_size=3), label="other kitchens")  # fmt: skip
    kitchens: dict[str, Any] = {"k": case.rkitchen}
    for i, objs in enumerate(others):
        kitchens[f"o{i}"] = [f.object(o) for o in objs]
    ks = foon.KitchenSet(kitchens)
    goal_texts = []
    for o in case.goals:
        obj = f.object(o)
        goal_texts.append(json.dumps(obj.to_dict()))
        goal_texts.append(obj.label)
    goal_texts += ["truffle", '{"label": 5}']
    methods = [*foon.METHODS, "fastest"]
    n = data.draw(st.integers(1, 30), label="rows")
    rows: list[bref.Row] = []
    for i in range(n):
        rows.append((
            i,
            data.draw(st.sampled_from([*kitchens, "missing"]), label=f"kitchen {i}"),
            data.draw(st.sampled_from(goal_texts), label=f"goal {i}"),
            data.draw(st.sampled_from(methods), label=f"method {i}"),
            data.draw(st.sampled_from(OPTIONS), label=f"options {i}"),
        ))  # fmt: skip
    motions = foon.MotionRates(case.rates)
    check(f, ks, rows, motions=motions, utensils=sorted(case.utensils))
    # The other kitchens as deltas of the first: items of it removed, others added.
    base = list(ks["k"])
    deltas = {}
    for i, objs in enumerate(others):
        drop = data.draw(st.lists(st.integers(0, max(len(base) - 1, 0)), max_size=3),
                         label=f"removed {i}")  # fmt: skip
        remove = [base[j] for j in drop if j < len(base)]
        deltas[f"o{i}"] = ([f.object(o) for o in objs], remove)
    deltas["k"] = ([], [])
    ds = foon.KitchenSet.with_deltas(base, deltas)
    check(f, ds, rows, motions=motions, utensils=sorted(case.utensils))


# --- the kitchen set ------------------------------------------------------------------------


def test_kitchen_set_forms(tmp_path: Path) -> None:
    egg = {"label": "egg", "states": ["whole"]}
    tea = {"label": "tea"}
    (tmp_path / "set.json").write_text(json.dumps({"a": [egg], "b": [egg, tea]}))
    s = foon.KitchenSet.load(tmp_path / "set.json")
    assert s.ids == ["a", "b"] and len(s) == 2 and "a" in s and "c" not in s
    assert s["b"] == foon.Kitchen([egg, tea])
    assert list(s) == ["a", "b"]
    assert s == foon.KitchenSet({"a": [egg], "b": foon.Kitchen([tea, egg])})

    folder = tmp_path / "kitchens"
    folder.mkdir()
    (folder / "a.json").write_text(json.dumps([egg]))
    (folder / "b.txt").write_text("O\tegg\nS\twhole\nO\ttea\n")
    assert foon.KitchenSet.load(folder) == s

    (tmp_path / "base.json").write_text(json.dumps([egg]))
    (tmp_path / "delta.json").write_text(
        json.dumps({"base": "base.json", "kitchens": {"a": {}, "b": {"add": [tea]}}})
    )
    d = foon.KitchenSet.load(tmp_path / "delta.json")
    assert d.ids == ["a", "b"] and d["a"] == s["a"] and d["b"] == s["b"]
    assert d.is_delta("b") and not s.is_delta("b")
    assert d.fingerprint == s.fingerprint  # the same ids and kitchens
    w = foon.KitchenSet.with_deltas([egg, tea], {"a": ([], [tea]), "b": ([tea], [])})
    assert w == s and w.is_delta("a")
    for x in (s, d, w):
        assert foon.KitchenSet.from_bytes(x.to_bytes()) == x
        back = pickle.loads(pickle.dumps(x))
        assert back == x and back.ids == x.ids
        assert [back.is_delta(i) for i in back.ids] == [x.is_delta(i) for i in x.ids]
    assert len(s.fingerprint) == 32 and s.fingerprint != foon.KitchenSet({"a": [egg]}).fingerprint


def test_kitchen_set_errors(tmp_path: Path) -> None:
    p = tmp_path / "dup.json"
    p.write_text('{"a": [],\n "a": []}')
    with pytest.raises(foon.ParseError, match=r"dup\.json:2:2: .*kitchen id 'a' is given twice"):
        foon.KitchenSet.load(p)
    p.write_text('{"a": [\n  {"label": "egg", "colour": "red"}]}')
    with pytest.raises(foon.ParseError, match=r"dup\.json:2:"):
        foon.KitchenSet.load(p)
    with pytest.raises(foon.ParseError, match="expected a JSON object of kitchens"):
        foon.KitchenSet.from_text("[]")
    with pytest.raises(ValueError, match="not a valid serialised kitchen set"):
        foon.KitchenSet.from_bytes(b"nonsense")
    with pytest.raises(TypeError, match="mapping"):
        foon.KitchenSet([("a", [])])  # type: ignore[arg-type]
    with pytest.raises(KeyError):
        foon.KitchenSet({"a": []})["b"]
    with pytest.raises(TypeError, match=r"pair \(add, remove\)"):
        foon.KitchenSet.with_deltas([], {"a": []})  # type: ignore[dict-item]


# --- the query table ------------------------------------------------------------------------


@pytest.fixture(scope="module")
def small() -> tuple[foon.Foon, foon.KitchenSet]:
    f = foon.Foon.from_text("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    return f, foon.KitchenSet({"k": [{"label": "egg", "states": ["whole"]}]})


def test_query_table_checks(small: tuple[foon.Foon, foon.KitchenSet]) -> None:
    f, ks = small
    goal = '{"label": "egg", "states": ["cracked"]}'
    q = pa.table({"query_id": [7, 8], "kitchen_id": ["k", "k"], "goal": [goal, goal],
                  "method": ["ids", "bfs"]})  # fmt: skip
    t = plan_table(f, ks, q)
    assert t.column("query_id").to_pylist() == ["7", "8"]
    assert t.column("solved").to_pylist() == [True, True]
    assert t.column("units").to_pylist() == [[0], [0]]
    assert plan_table(f, ks, q.to_batches()[0]).equals(t)
    assert plan_table(f, ks, q.slice(0, 0)).num_rows == 0
    with pytest.raises(ValueError, match="no column 'goal'"):
        plan_table(f, ks, q.drop_columns(["goal"]))
    with pytest.raises(ValueError, match="no column 'query_id'"):
        plan_table(f, ks, q.drop_columns(["query_id"]))
    with pytest.raises(ValueError, match="'method' must be strings"):
        plan_table(f, ks, q.set_column(3, "method", pa.array([1, 2])))
    with pytest.raises(ValueError, match="'options' must be strings"):
        plan_table(f, ks, q.append_column("options", pa.array([1, 2])))
    nulls = q.append_column("options", pa.nulls(2))
    assert plan_table(f, ks, nulls).equals(t)
    with pytest.raises(TypeError, match="KitchenSet"):
        plan_table(f, {"k": []}, q)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="threads must be at least 1"):
        plan_table(f, ks, q, threads=0)
    with pytest.raises(ValueError, match="deltas must be 'incremental' or 'from-scratch'"):
        plan_table(f, ks, q, deltas="lazy")


def test_import_foon_without_pyarrow() -> None:
    code = (
        "import sys; sys.modules['pyarrow'] = None\n"
        "import foon\n"
        "s = foon.KitchenSet({'a': []})\n"
        "assert s.ids == ['a']\n"
        "try:\n    import foon._arrow\nexcept ImportError:\n    print('ok')\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "ok"


def test_reference_is_not_vacuous() -> None:
    # The reference parses the FOON the way the course does; a FOON it cannot plan would
    # make every comparison trivially equal.
    rf = ref.parse("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    assert len(rf.fus) == 1
    f = foon.Foon.from_text("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    rows: list[bref.Row] = [("a", "k", "egg", "ids", None)]
    got = bref.answer(f, {"k": foon.Kitchen([{"label": "egg", "states": ["whole"]}])}, rows)
    assert got[0]["failure"] == "goal-ambiguous"
