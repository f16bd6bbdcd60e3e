"""foon compare, foon verify, foon check (CLI and Python) and the reusable Planner."""

from __future__ import annotations

import json
from pathlib import Path

import foon
import pytest
from conftest import DATA, GOLDEN, Course, need_shared
from foon.cli import main

Capture = pytest.CaptureFixture[str]


def course_args() -> list[str]:
    return [
        "--foon",
        str(DATA / "FOON.txt"),
        "--kitchen",
        str(DATA / "kitchen.json"),
        "--utensils",
        str(DATA / "utensils.txt"),
    ]


# --- compare ----------------------------------------------------------------------------------


def test_compare_course_goals_json(capsys: Capture) -> None:
    need_shared()
    code = main(
        [
            "compare",
            *course_args(),
            "--motions",
            str(DATA / "motion.txt"),
            "--goals",
            str(DATA / "goal_nodes_25.json"),
            "--json",
        ]
    )
    assert code == 0
    d = json.loads(capsys.readouterr().out)
    # The methods and their order are the core's.
    methods = [m + " (course)" if m == "bfs" else m for m in foon.METHODS]
    sound = [m for m in methods if m != "bfs (course)"]
    assert len(d["rows"]) == 25 * len(methods)
    assert [s["method"] for s in d["summary"]] == methods
    by = {s["method"]: s for s in d["summary"]}
    for m in sound:
        assert (by[m]["solved_count"], by[m]["goals"]) == (23, 25)  # whipped cream, fried rice
    assert by["bfs (course)"]["solved_count"] == 25
    for s in d["summary"]:
        rows = [r for r in d["rows"] if r["method"] == s["method"]]
        assert s["seconds_total"] == pytest.approx(sum(r["seconds"] for r in rows))
    # The lowest trees come from ids: no method has a lower mean height over solved goals.
    assert by["ids"]["height"] == min(by[m]["height"] for m in sound)
    for r in d["rows"]:
        if r["solved"] and r["method"] != "bfs (course)":
            assert r["height"] is not None and 0 < r["success"] <= 1


def test_compare_text_and_csv_on_the_example(capsys: Capture) -> None:
    assert main(["compare", "--methods", "ids,greedy-success,bfs"]) == 0
    out = capsys.readouterr().out
    assert "goal" in out.splitlines()[0] and "(all: 5/6 solved; means, total ms)" in out
    assert main(["compare", "--csv", "--methods", "ids"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0].startswith("goal,method,solved,fu_count")
    assert len(lines) == 1 + 6 + 1


def test_compare_rejects_unknown_methods(capsys: Capture) -> None:
    assert main(["compare", "--methods", "ids,astar"]) == 2
    assert "unknown method 'astar'" in capsys.readouterr().err


# --- verify -----------------------------------------------------------------------------------


def test_verify_golden_trees(course: Course, capsys: Capture) -> None:
    for goal in course.goals5:
        name = goal.label.replace(" ", "_") + ".txt"
        r = course.foon.verify(GOLDEN / "bfs" / name, goal, course.kitchen, course.utensils)
        assert r.foreign_units == []  # every unit of a course tree is a unit of the FOON
        as_set = course.foon.plan(
            goal, course.kitchen, "bfs", compat="course", utensils=course.utensils
        ).is_valid()
        if goal.label == "whipped cream":  # circular: invalid in any order
            assert not r.valid and not as_set
            assert r.blocked is not None and r.blocked.line == 56
            assert r.blocked.missing[0].label == "mixing bowl"
        elif goal.label == "greek salad":
            # Executable as a set, but the course's reversed list is not an execution order.
            assert as_set and not r.valid
            assert r.blocked is not None and r.blocked.position == 8
        else:
            assert r.valid and as_set, goal.label
    whipped = next(g for g in course.goals5 if g.label == "whipped cream")
    code = main(
        [
            "verify",
            *course_args(),
            "--goal",
            json.dumps(whipped.to_dict()),
            str(GOLDEN / "bfs" / "whipped_cream.txt"),
        ]
    )
    out = capsys.readouterr().out
    assert code == 1
    assert "whipped_cream.txt:56: unit 4 cannot run: needs mixing bowl" in out
    assert "is never made" in out


def test_verify_sound_trees_written_by_plan(tmp_path: Path, capsys: Capture) -> None:
    ex = foon.example()
    for method in ("ids", "greedy-success", "greedy-inputs", "optimal-units"):
        t = ex.foon.plan(ex.goals[0], ex.kitchen, method, motions=ex.motions, utensils=ex.utensils)
        path = tmp_path / f"{method}.txt"
        path.write_text(t.to_text())
        assert main(["verify", "--label", "scrambled eggs", str(path)]) == 1  # other goal
        assert main(["verify", "--goal", json.dumps(ex.goals[0].to_dict()), str(path)]) == 0
    capsys.readouterr()
    # A unit that is not in the FOON is reported as such.
    bad = tmp_path / "bad.txt"
    bad.write_text(
        "//\nO\tice\nS\tfrozen\nM\tpray\nO\tice\nS\tcrushed\nS\tfrozen\nS\tin\t[drinking glass]\n//\n"
    )
    r = ex.foon.verify(bad, ex.goals[0], ex.kitchen, ex.utensils)
    assert r.foreign_units == [(0, 2)]


# --- check ------------------------------------------------------------------------------------


def test_check_reports_known_faults_of_the_data_set(capsys: Capture) -> None:
    need_shared()
    code = main(["check", "--json", str(DATA)])
    assert code == 1
    found = json.loads(capsys.readouterr().out)
    codes: dict[str, int] = {}
    for f in found:
        codes[f["code"]] = codes.get(f["code"], 0) + 1
    assert codes == {
        "no-motion": 2,
        "two-motions": 1,
        "spaced-ingredient": 38,
        "duplicate-ingredient": 530,
        "empty-container": 1,
        "duplicate-fu": 247,
        # Conflicting annotations of one object (the last one wins, as in the course parser).
        "two-containers": 251,
        "two-ingredient-lists": 70,
        "empty-ingredient": 17,
    }
    where = {(Path(f["path"]).name[:4], f["line"], f["code"]) for f in found}
    assert ("0083", 500, "no-motion") in where and ("0032", 114, "two-motions") in where
    assert not any(f["severity"] == "error" for f in found)


def test_check_with_the_course_kitchen(course: Course) -> None:
    found = foon.check(
        DATA / "FOON.txt", kitchen=course.kitchen, motions=course.motions, utensils=course.utensils
    )
    codes = {f.code for f in found}
    assert codes == {"cycle-only", "duplicate-ingredient", "spaced-ingredient"}
    assert sum(f.code == "duplicate-ingredient" for f in found) == 32  # as SEMANTICS.md says
    cyc = [f for f in found if f.code == "cycle-only"]
    assert any(
        "mixing bowl {condensed milk,cream cheese,pudding mix} in [mixer]" in f.message for f in cyc
    )


def test_check_lists_every_error_and_cross_checks(tmp_path: Path, capsys: Capture) -> None:
    p = tmp_path / "f.txt"
    p.write_text(
        "O\tbowl\nS\tin\tcup\nM\tpour\nO\tbowl\nS\tfull\n//\n"  # error line 2
        "O\tcup\nS\tempty\nM\tfill\nO\tcup\nS\tfull\n//\n"  # fine
        "Q\tx\n//\n"  # error line 13
        "O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n"
    )
    k = tmp_path / "k.json"
    k.write_text(
        json.dumps([{"label": "cup", "states": ["empty"], "ingredients": [], "container": None}])
    )
    m = tmp_path / "m.txt"
    m.write_text("fill\t0.5\n")
    code = main(["check", str(p), "--kitchen", str(k), "--motions", str(m)])
    out = capsys.readouterr().out.splitlines()
    assert code == 1
    assert out[0].startswith(f"{p}:2:6: error: expected")
    assert any(f"{p}:13:1: error: unknown line kind" in line for line in out)
    assert any("'egg (whole)' is used but never produced" in line for line in out)
    assert any("motion 'crack' has no success rate" in line for line in out)
    clean = tmp_path / "clean.txt"
    clean.write_text("O\tcup\nS\tempty\nM\tfill\nO\tcup\nS\tfull\n//\n")
    assert main(["check", str(clean)]) == 0


# --- planner ----------------------------------------------------------------------------------


def test_planner_matches_foon_plan(course: Course) -> None:
    p = course.foon.planner(course.kitchen, motions=course.motions, utensils=course.utensils)
    for m in ("ids", "greedy-success", "optimal-success"):
        a = [t.units for t in p.plan_many(course.goals25, m)]
        b = [
            course.foon.plan(
                g, course.kitchen, m, motions=course.motions, utensils=course.utensils
            ).units
            for g in course.goals25
        ]
        assert a == b
    assert p.ranks() == course.foon.ranks(course.kitchen, course.utensils)
