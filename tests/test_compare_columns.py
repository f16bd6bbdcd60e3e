"""``foon compare``'s columns beyond the plan figures: the identity ``level``,
``optimal-shared``'s ``objective``, ``bound``, ``proven`` and ``gap``, and with ``--split M``
the split columns (the exact robot/human split and the lab's fixed-tree method) of every row,
in the text, JSON and CSV outputs; and on the course goals, ``optimal-shared``'s unit count
against every other sound method's, goal by goal, read from ``foon compare``'s output."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path
from typing import Any

import foon
import pytest
from conftest import DATA, need_shared
from foon.cli import main

Capture = pytest.CaptureFixture[str]
SCHEMA = Path(__file__).resolve().parent.parent / "schema" / "foon.schema.json"
SOUND = ("ids", "greedy-success", "greedy-inputs", "optimal-success", "optimal-units",
         "optimal-inputs", "optimal-shared")  # fmt: skip


def course_args() -> list[str]:
    return ["--foon", str(DATA / "FOON.txt"), "--kitchen", str(DATA / "kitchen.json"),
            "--utensils", str(DATA / "utensils.txt"), "--motions", str(DATA / "motion.txt"),
            "--goals", str(DATA / "goal_nodes_25.json")]  # fmt: skip


def _compare(args: list[str], capsys: Capture) -> str:
    assert main(["compare", *args]) == 0
    return capsys.readouterr().out


def _validate(doc: dict[str, Any]) -> None:
    import jsonschema

    schema = json.loads(SCHEMA.read_text())
    jsonschema.validate(doc, {**schema["$defs"]["comparison"], "$defs": schema["$defs"]})


def test_course_goals_shared_is_fewest_units_and_proven(capsys: Capture) -> None:
    """On the 25 course goals, through ``foon compare --json``: optimal-shared solves every
    goal the sound methods solve, proves it (bound = unit count, gap 0), and its unit count is
    at most every other sound method's, goal by goal; the rows agree with the Python API."""
    need_shared()
    doc = json.loads(_compare([*course_args(), "--methods", ",".join(SOUND), "--json"], capsys))
    _validate(doc)
    rows = doc["rows"]
    assert len(rows) == 25 * len(SOUND)
    by: dict[str, dict[str, dict[str, Any]]] = {}
    for r in rows:
        by.setdefault(r["goal"], {})[r["method"]] = r
        assert r["level"] == 3
        assert r["max_human"] is None and r["split_success"] is None
        if r["method"] != "optimal-shared":
            assert (r["objective"], r["bound"], r["proven"], r["gap"]) == (None,) * 4
    assert len(by) == 25
    solved = 0
    for goal, ms in by.items():
        shared = ms["optimal-shared"]
        assert shared["objective"] == "units"
        others = [ms[m] for m in SOUND if m != "optimal-shared"]
        assert shared["solved"] == any(r["solved"] for r in others), goal
        if not shared["solved"]:
            assert (shared["bound"], shared["proven"], shared["gap"]) == (None, None, None)
            continue
        solved += 1
        assert shared["proven"] is True and shared["gap"] == 0
        assert shared["bound"] == shared["fu_count"]
        for r in others:
            if r["solved"]:
                assert shared["fu_count"] <= r["fu_count"], (goal, r["method"])
    assert solved == 23  # whipped cream and fried rice cannot be made
    s = {x["method"]: x for x in doc["summary"]}
    assert s["optimal-shared"]["proven_count"] == 23 and s["optimal-shared"]["gap"] == 0
    assert all(s[m]["proven_count"] is None for m in SOUND if m != "optimal-shared")
    # The same figures as the Python API.
    f = foon.load(DATA / "FOON.txt")
    p = f.planner(foon.Kitchen.load(DATA / "kitchen.json"),
                  motions=foon.MotionRates.load(DATA / "motion.txt"),
                  utensils=foon.load_utensils(DATA / "utensils.txt"))  # fmt: skip
    for g in foon.load_goals(DATA / "goal_nodes_25.json")[:6]:
        t = p.plan(g, "optimal-shared")
        r = by[str(f.object(p.goal_id(g)))]
        assert r["optimal-shared"]["fu_count"] == (len(t.units) if t.solved else None)


def test_split_columns_in_every_format(capsys: Capture) -> None:
    """``--split 2`` on the example: every row of a goal carries the goal's split and
    fixed-tree successes (those of ``Foon.split``), the split never below the fixed tree; the
    CSV has the same values as the JSON, and the text table the columns."""
    ex = foon.example()
    args = ["--methods", "ids,optimal-shared", "--split", "2"]
    doc = json.loads(_compare([*args, "--json"], capsys))
    _validate(doc)
    f = ex.foon
    p = f.planner(ex.kitchen, utensils=ex.utensils)
    want: dict[str, tuple[float | None, float | None]] = {}
    for g in ex.goals:
        gid = p.goal_id(g)
        r = p.split(gid, {"robot": ex.motions}, 2, fixed_tree=True)
        split = r.best[2] if r.solved else None
        fixed = r.fixed[-1].success if r.fixed else None
        want[str(f.object(gid))] = (split, fixed)
    seen = set()
    for r in doc["rows"]:
        assert r["max_human"] == 2
        got = (r["split_success"], r["fixed_tree_success"])
        assert got == want[r["goal"]], r
        if got[0] is not None and got[1] is not None:
            assert got[0] >= got[1] * (1 - 1e-12)
        seen.add(r["goal"])
    assert seen == set(want) and any(v[0] is not None for v in want.values())
    # CSV: the same columns and values (floats in Python's repr).
    table = list(csv.DictReader(io.StringIO(_compare([*args, "--csv"], capsys))))
    rows = [t for t in table if t["goal"] != "(all)"]
    assert len(rows) == len(doc["rows"])
    for t, r in zip(rows, doc["rows"], strict=True):
        assert (t["goal"], t["method"]) == (r["goal"], r["method"])
        assert t["level"] == "3" and t["max_human"] == "2"
        for k in ("split_success", "fixed_tree_success", "bound", "gap"):
            assert t[k] == ("" if r[k] is None else repr(r[k])), (k, t, r)
        assert t["objective"] == (r["objective"] or "")
        assert t["proven"] == ("" if r["proven"] is None else str(r["proven"]))
    summary = {t["method"]: t for t in table if t["goal"] == "(all)"}
    assert summary["optimal-shared"]["proven_count"] != "" and summary["ids"]["proven_count"] == ""
    # Text: the optional columns, only when they apply.
    head = _compare(args, capsys).splitlines()[0].split()
    assert head[-7:] == ["bound", "gap", "proven", "split", "M=2", "fixed-tree", "M=2"]
    plain = _compare(["--methods", "ids"], capsys).splitlines()[0].split()
    assert plain == ["goal", "method", "units", "height", "success", "leaves", "expanded",
                     "peak", "ms"]  # fmt: skip


def test_shared_columns_without_split(capsys: Capture) -> None:
    """Without ``--split`` the split columns are null, and a text table of optimal-shared
    shows its bound, gap and proven; for a goal in the kitchen the bound is 0 and proven."""
    ex = foon.example()
    doc = json.loads(_compare(["--methods", "optimal-shared", "--json"], capsys))
    _validate(doc)
    for r in doc["rows"]:
        assert r["max_human"] is None and r["split_success"] is None
        assert r["fixed_tree_success"] is None and r["objective"] == "units"
        if r["solved"]:
            assert r["proven"] is True and r["bound"] == r["fu_count"] and r["gap"] == 0
    assert len(doc["rows"]) == len(ex.goals)
    head = _compare(["--methods", "optimal-shared"], capsys).splitlines()[0].split()
    assert head[-3:] == ["bound", "gap", "proven"]
