"""The Python API: objects, kitchens, rates, goals, results, and how errors map to
exceptions."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import foon
from conftest import DATA, Course
from foon import errors

SMALL = ("O\tglass\nS\tempty\nO\tice\nS\tin\t[bag]\nM\tpour\nO\tglass\nS\tcontains\t{ice}\n"
         "O\tice\nS\tin\t[glass]\n//\n")


def test_load_errors_map_to_builtin_and_typed_exceptions(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="nope.foon"):
        foon.load(tmp_path / "nope.foon")
    with pytest.raises(OSError):
        foon.load(tmp_path)
    bad = tmp_path / "bad.foon"
    bad.write_text("O\tx\nQ\ty\n")
    with pytest.raises(foon.ParseError) as e:
        foon.load(bad)
    assert isinstance(e.value, foon.FoonError)
    assert e.value.path == str(bad)  # type: ignore[attr-defined]
    assert (e.value.line, e.value.column) == (2, 1)  # type: ignore[attr-defined]
    assert errors.ParseError is foon.ParseError


def test_goal_not_found_message() -> None:
    f = foon.Foon.from_text(SMALL)
    with pytest.raises(foon.GoalNotFoundError, match="^The goal node does not exist: ice in \\[cup\\]$"):
        f.plan(foon.Object("ice", container="cup"))
    with pytest.raises(foon.GoalNotFoundError, match="The goal node does not exist: soup"):
        f.plan("soup")


def test_ambiguous_label_lists_the_objects() -> None:
    f = foon.Foon.from_text(SMALL)
    with pytest.raises(foon.GoalNotFoundError) as e:
        f.plan("ice")
    msg = str(e.value)
    assert "matches 2 objects" in msg and "ice in [bag]" in msg and "ice in [glass]" in msg


def test_missing_rate_is_an_error_unless_a_default_is_given() -> None:
    f = foon.Foon.from_text(SMALL)
    goal = foon.Object("ice", container="glass")
    k = [foon.Object("glass", ("empty",)), foon.Object("ice", container="bag")]
    with pytest.raises(foon.MissingRateError, match="'pour'") as e:
        f.plan(goal, k, "greedy-success", motions={"chop": 0.5})
    assert e.value.motion == "pour"  # type: ignore[attr-defined]
    t = f.plan(goal, k, "greedy-success", motions={"chop": 0.5}, default_rate=0.25)
    assert t.solved and t.units == [0] and t.success == 0.25


def test_bad_arguments_are_value_errors() -> None:
    f = foon.Foon.from_text(SMALL)
    with pytest.raises(ValueError, match="unknown method 'dfs'"):
        f.plan(0, method="dfs")
    with pytest.raises(ValueError, match="no course-compatible form"):
        f.plan(0, method="optimal-units", compat="course")
    with pytest.raises(ValueError, match="between 0 and 1"):
        foon.MotionRates({"pour": 2.0})
    with pytest.raises(IndexError):
        f.fu(5)


def test_plan_result_fields_and_json(course: Course) -> None:
    goal = course.goals5[0]
    t = course.foon.plan(goal, course.kitchen, "bfs", compat="course", motions=course.motions,
                         utensils=course.utensils)
    d = json.loads(t.to_json())
    assert d["goal"] == goal.to_dict()
    assert d["method"] == "bfs" and d["solved"] is True
    assert d["fu_count"] == len(d["units"]) == t.to_text().count("\nM\t") + t.to_text().startswith("M")
    assert 0 < d["success"] <= 1 and d["leaf_inputs"] > 0 and d["expanded"] > 0
    assert [fu.index for fu in t] == t.units
    # Success is the product of the units' motion rates.
    p = 1.0
    for fu in t:
        p *= course.motions[fu.motion]
    assert d["success"] == pytest.approx(p)


def test_kitchen_sources_agree(course: Course, tmp_path: Path) -> None:
    k1 = foon.Kitchen.load(DATA / "kitchen.json")
    k2 = foon.Kitchen.from_text((DATA / "kitchen.json").read_text())
    k3 = foon.Kitchen(json.loads((DATA / "kitchen.json").read_text()))
    assert k1.items == k2.items == k3.items and len(k1) == 1174
    blocks = foon.Kitchen.load(next(DATA.glob("lab_history/kitchen_ids_format_*.txt")))
    assert len(blocks) > 100 and blocks.items[0] == foon.Object("plate", ("empty",))


def test_plan_many_equals_plan(course: Course) -> None:
    kw = dict(motions=course.motions, utensils=course.utensils)
    many = course.foon.plan_many(course.goals25, course.kitchen, "greedy-success", **kw)  # type: ignore[arg-type]
    one = [course.foon.plan(g, course.kitchen, "greedy-success", **kw) for g in course.goals25]  # type: ignore[arg-type]
    assert [t.units for t in many] == [t.units for t in one]
    assert [t.solved for t in many].count(False) == 2


def test_failures_explain_themselves(course: Course) -> None:
    byname = {g.label: g for g in course.goals25}
    t = course.foon.plan(byname["whipped cream"], course.kitchen, "ids", utensils=course.utensils)
    assert not t.solved and t.units == []
    assert t.cycle and t.cycle[0] == t.cycle[-1]
    assert "circular step" in t.explanation()
    # Removing a raw item makes a goal fail with that item named as missing.
    sweet = byname["sweet potato"]
    k = course.kitchen.without([foon.Object("sweet potato", ("whole",))])
    t = course.foon.plan(sweet, k, "ids", utensils=course.utensils)
    assert not t.solved
    assert foon.Object("sweet potato", ("whole",)) in t.missing


def test_sound_trees_are_valid_and_course_trees_may_not_be(course: Course) -> None:
    kw = dict(motions=course.motions, utensils=course.utensils)
    sound_invalid = course_invalid = 0
    for g in course.goals25:
        for m in ("ids", "greedy-success", "greedy-inputs", "optimal-success"):
            t = course.foon.plan(g, course.kitchen, m, **kw)  # type: ignore[arg-type]
            sound_invalid += t.solved and not t.is_valid()
        c = course.foon.plan(g, course.kitchen, "bfs", compat="course", **kw)  # type: ignore[arg-type]
        course_invalid += not c.is_valid()
    assert sound_invalid == 0
    assert course_invalid > 0


def test_threads_release_the_interpreter_and_agree(course: Course) -> None:
    from concurrent.futures import ThreadPoolExecutor

    kw = dict(motions=course.motions, utensils=course.utensils)
    want = [course.foon.plan(g, course.kitchen, "ids", **kw).units for g in course.goals25]  # type: ignore[arg-type]
    with ThreadPoolExecutor(8) as pool:
        got = list(pool.map(lambda g: course.foon.plan(g, course.kitchen, "ids", **kw).units,  # type: ignore[arg-type]
                            course.goals25 * 4))
    assert got == want * 4
