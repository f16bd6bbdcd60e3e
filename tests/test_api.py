"""The Python API: objects, kitchens, rates, goals, results, and how errors map to
exceptions."""

from __future__ import annotations

import json
import os
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import foon
import pytest
from conftest import DATA, Course
from foon import errors

SMALL = (
    "O\tglass\nS\tempty\nO\tice\nS\tin\t[bag]\nM\tpour\nO\tglass\nS\tcontains\t{ice}\n"
    "O\tice\nS\tin\t[glass]\n//\n"
)


def test_load_errors_map_to_builtin_and_typed_exceptions(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match=r"nope.foon"):
        foon.load(tmp_path / "nope.foon")
    with pytest.raises(OSError):
        foon.load(tmp_path)
    bad = tmp_path / "bad.foon"
    bad.write_text("O\tx\nQ\ty\n")
    with pytest.raises(foon.ParseError) as e:
        foon.load(bad)
    assert isinstance(e.value, foon.FoonError)
    assert e.value.path == str(bad)
    assert (e.value.line, e.value.column) == (2, 1)
    assert errors.ParseError is foon.ParseError


def test_goal_not_found_message() -> None:
    f = foon.Foon.from_text(SMALL)
    with pytest.raises(
        foon.GoalNotFoundError,
        match=r"^The goal node does not exist: ice in \[cup\]; nearest: ice in \[bag\]; "
        r"ice in \[glass\]$",
    ):
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
    assert e.value.motion == "pour"
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
    t = course.foon.plan(
        goal,
        course.kitchen,
        "bfs",
        compat="course",
        motions=course.motions,
        utensils=course.utensils,
    )
    d = json.loads(t.to_json())
    assert d["goal"] == goal.to_dict()
    assert d["method"] == "bfs" and d["solved"] is True
    assert (
        d["fu_count"] == len(d["units"]) == t.to_text().count("\nM\t") + t.to_text().startswith("M")
    )
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
    kw = {"motions": course.motions, "utensils": course.utensils}
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
    kw = {"motions": course.motions, "utensils": course.utensils}
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

    kw = {"motions": course.motions, "utensils": course.utensils}
    want = [course.foon.plan(g, course.kitchen, "ids", **kw).units for g in course.goals25]  # type: ignore[arg-type]
    with ThreadPoolExecutor(8) as pool:
        got = list(
            pool.map(
                lambda g: course.foon.plan(g, course.kitchen, "ids", **kw).units,  # type: ignore[arg-type]
                course.goals25 * 4,
            )
        )
    assert got == want * 4


# --- arguments: types, indices, paths ---------------------------------------------------------


def test_type_errors_name_the_argument_and_the_expected_type() -> None:
    f = foon.Foon.from_text(SMALL)
    k = [foon.Object("glass", ("empty",))]
    for bad, shown in ((None, "NoneType"), (1.0, "float"), (["ice"], "list")):
        with pytest.raises(TypeError, match=f"^goal must be an Object.* not {shown}$"):
            f.plan(bad, k)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"goals must be an iterable of goals.*not a single str"):
        f.plan_many("ice", k)
    with pytest.raises(TypeError, match=r"^threads must be an int or None, not str$"):
        f.plan_many([0], k, threads="2")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="kitchen must be a Kitchen, a path or an iterable"):
        f.plan(0, 5)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="method"):
        f.plan(0, k, 5)  # type: ignore[arg-type]


def test_threads_out_of_range_are_clear_errors() -> None:
    f = foon.Foon.from_text(SMALL)
    with pytest.raises(OverflowError, match=r"^threads=10{20} is too large .*capped"):
        f.plan_many([0, 1], threads=10**20)
    for n in (0, -1):
        with pytest.raises(ValueError, match=f"^threads must be at least 1, not {n}$"):
            f.plan_many([0, 1], threads=n)
    with pytest.raises(TypeError, match="not bool"):
        f.plan_many([0, 1], threads=True)


def test_every_bad_index_is_the_same_index_error() -> None:
    f = foon.Foon.from_text(SMALL)
    for i in (-1, 10**6, 10**12, 10**30):
        with pytest.raises(IndexError, match=f"^functional unit {i} is out of range"):
            f.fu(i)
        with pytest.raises(IndexError, match=f"^object id {i} is out of range"):
            f.object(i)
        with pytest.raises(IndexError, match="out of range"):
            f.producers(i)
    with pytest.raises(TypeError, match="must be an int, not str"):
        f.fu("0")  # type: ignore[arg-type]


def test_bytes_paths_work_everywhere(tmp_path: Path) -> None:
    ex = foon.example()
    p = {k: bytes(v) for k, v in ((k, str(v).encode()) for k, v in ex.paths.items())}
    f = foon.load(p["foon"])
    assert f == ex.foon and f.fu_count == ex.foon.fu_count
    assert foon.Foon.load(p["foon"]).fu_count == ex.foon.fu_count
    assert foon.Kitchen.load(p["kitchen"]).items == ex.kitchen.items
    assert dict(foon.MotionRates.load(p["motions"])) == dict(ex.motions)
    assert foon.load_utensils(p["utensils"]) == ex.utensils
    assert foon.load_goals(p["goals"]) == ex.goals
    tree = f.plan(ex.goals[0], p["kitchen"], motions=p["motions"], utensils=p["utensils"])
    assert tree.solved
    assert foon.check([p["foon"]]) == foon.check(ex.paths["foon"])
    with pytest.raises(TypeError, match=r"path must be a path .* not int"):
        foon.load(5)  # type: ignore[arg-type]


# --- objects cross the boundary as typed values -------------------------------------------------


def test_object_fields_are_checked_with_the_field_named() -> None:
    cases: list[tuple[dict[str, object], str]] = [
        ({"label": None}, "^label must be a str, not NoneType$"),
        ({"label": 5}, "^label must be a str, not int$"),
        (
            {"label": "ice", "states": "crushed"},
            "^states must be a sequence of str, not a single str",
        ),
        ({"label": "ice", "states": 5}, "^states must be a sequence of str, not int$"),
        ({"label": "ice", "states": [1]}, r"^states\[0\] must be a str, not int$"),
        ({"label": "ice", "states": None}, "^states must be a sequence of str, not NoneType$"),
        ({"label": "ice", "ingredients": "ab"}, "^ingredients must be a sequence of str"),
        ({"label": "ice", "states": {"a": 1}}, "^states must be a sequence of str, not dict$"),
        ({"label": "ice", "container": 5}, "^container must be a str or None, not int$"),
        ({"label": "ice", "container": ["cup"]}, "^container must be a str or None, not list$"),
    ]
    for d, message in cases:
        with pytest.raises(TypeError, match=message):
            foon.Object.from_dict(d)
    with pytest.raises(TypeError, match=r"^states must be a sequence of str, not a single str"):
        foon.Object("ice", "crushed")
    with pytest.raises(TypeError, match=r"^label must be a str, not NoneType$"):
        foon.Object(None)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="empty label"):
        foon.Object("")
    with pytest.raises(ValueError, match=r"^an object needs a 'label'"):
        foon.Object.from_dict({"states": []})
    with pytest.raises(ValueError, match="unknown field 'colour'"):
        foon.Object.from_dict({"label": "ice", "colour": "white"})
    with pytest.raises(TypeError, match="must be a mapping"):
        foon.Object.from_dict(["ice"])  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="a kitchen item must be an Object or a mapping, not str"):
        foon.Kitchen(["ice"])  # type: ignore[list-item]
    o = foon.Object.from_dict({"label": "ice", "states": ("b", "a"), "container": None})
    assert o == foon.Object("ice", ["a", "b"]) and o.states == ("b", "a")
    assert o.ingredients == () and o.container is None
    with pytest.raises(AttributeError, match="immutable"):
        o.label = "x"


def test_reprs() -> None:
    f = foon.Foon.from_text(SMALL)
    k = [foon.Object("glass", ("empty",)), foon.Object("ice", container="bag")]
    p = f.planner(k, motions={"pour": 0.5}, utensils=["glass"])
    assert repr(p) == (
        "<Planner <Foon 1 unit, 4 objects>: 2 kitchen items, 1 utensil, 1 motion rate>"
    )
    t = p.plan(foon.Object("ice", container="glass"))
    assert repr(t) == "<TaskTree ice in [glass] by ids: solved, 1 unit>"
    assert repr(p.plan(0)) == "<TaskTree glass (empty) by ids: solved, 0 units>"
    assert repr(foon.Object("ice", ("cold",))) == (
        "Object(label='ice', states=('cold',), ingredients=(), container=None)"
    )


def test_load_warnings_point_at_the_callers_line(tmp_path: Path) -> None:
    text = "O\tglass\nM\tpour\nO\tice\nS\tin\t[glass]\n"  # no closing //
    path = tmp_path / "open.foon"
    path.write_text(text)
    calls: dict[str, Callable[[], foon.Foon]] = {
        "load": lambda: foon.load(path),
        "Foon.load": lambda: foon.Foon.load(path),
        "from_text": lambda: foon.Foon.from_text(text),
    }
    for name, call in calls.items():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            call()
        assert len(caught) == 1, name
        w = caught[0]
        assert issubclass(w.category, foon.FoonWarning), name
        assert "no closing '//'" in str(w.message), name
        # The lambda's line: the caller's code, not a line inside foon.
        assert w.filename == __file__, (name, w.filename)
        assert w.lineno == calls_line(name), (name, w.lineno)


def calls_line(name: str) -> int:
    """The line of this file where the lambda for ``name`` is written."""
    src = Path(__file__).read_text().splitlines()
    return next(i for i, s in enumerate(src, 1) if s.strip().startswith(f'"{name}": lambda'))


def test_load_goals_reads_every_goal_file_form(tmp_path: Path) -> None:
    assert "load_goals" in foon.__all__
    one = tmp_path / "one.json"
    one.write_text(json.dumps({"label": "ice", "states": ["crushed"], "container": "glass"}))
    many = tmp_path / "many.json"
    many.write_text(json.dumps([{"label": "ice"}, {"label": "tea", "ingredients": ["leaf"]}]))
    blocks = tmp_path / "goals.txt"
    blocks.write_text("O\tice\nS\tcrushed\nS\tin\t[glass]\n//\nO\ttea\n")
    assert foon.load_goals(one) == [foon.Object("ice", ("crushed",), (), "glass")]
    assert foon.load_goals(many) == [foon.Object("ice"), foon.Object("tea", (), ("leaf",))]
    assert foon.load_goals(blocks) == [
        foon.Object("ice", ("crushed",), (), "glass"),
        foon.Object("tea"),
    ]
    bad = tmp_path / "bad.json"
    bad.write_text('[{"label": "ice", "states": "crushed"}]')
    with pytest.raises(foon.ParseError) as e:
        foon.load_goals(bad)
    assert e.value.path == str(bad) and e.value.line == 1


def test_to_dict_has_the_unrated_motion() -> None:
    ex = foon.example()
    t = ex.foon.plan(ex.goals[0], ex.kitchen, motions=ex.motions, utensils=ex.utensils)
    d = t.to_dict()
    assert "unrated_motion" in d and d["unrated_motion"] == t.unrated_motion
    assert t.unrated_motion is None  # every motion of the example has a rate


# --- batches: threads -----------------------------------------------------------------------


def test_results_are_the_same_for_every_thread_count(course: Course) -> None:
    p = course.foon.planner(course.kitchen, motions=course.motions, utensils=course.utensils)
    goals = course.goals25 * 3
    for method in ("ids", "greedy-success", "optimal-units"):
        want = [(t.units, t.solved, t.success) for t in p.plan_many(goals, method, threads=1)]
        for threads in (2, 7, None):
            got = [
                (t.units, t.solved, t.success) for t in p.plan_many(goals, method, threads=threads)
            ]
            assert got == want, (method, threads)


def test_foon_threads_gives_the_default(monkeypatch: pytest.MonkeyPatch) -> None:
    ex = foon.example()
    p = ex.foon.planner(ex.kitchen, motions=ex.motions, utensils=ex.utensils)
    want = [t.units for t in p.plan_many(ex.goals)]
    monkeypatch.setenv("FOON_THREADS", "1")
    assert [t.units for t in p.plan_many(ex.goals)] == want
    monkeypatch.setenv("FOON_THREADS", "many")
    with pytest.raises(ValueError, match=r"^FOON_THREADS must be a positive integer, not 'many'$"):
        p.plan_many(ex.goals)
    assert [t.units for t in p.plan_many(ex.goals, threads=2)] == want  # explicit wins


def os_threads() -> int:
    return len(os.listdir("/proc/self/task"))


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="needs /proc (Linux)")
def test_thread_counts_do_not_leave_threads_behind() -> None:
    ex = foon.example()
    p = ex.foon.planner(ex.kitchen, motions=ex.motions, utensils=ex.utensils)
    p.plan_many(ex.goals, threads=2)  # the one pool exists from here on
    before = os_threads()
    for threads in (50, 51, 90, 3, 1000):
        p.plan_many(ex.goals * 40, threads=threads)
    # One pool of at most max_threads() workers, whatever was asked for.
    assert os_threads() <= before
    assert os_threads() <= before - 2 + foon._foon.max_threads() + 1


def test_iterating_a_tree_builds_no_objects(monkeypatch: pytest.MonkeyPatch) -> None:
    ex = foon.example()
    tree = ex.foon.plan(ex.goals[0], ex.kitchen, motions=ex.motions, utensils=ex.utensils)
    built: list[int] = []
    real = foon.Foon.object

    def counting(self: foon.Foon, i: int) -> foon.Object:
        built.append(i)
        return real(self, i)

    monkeypatch.setattr(foon.Foon, "object", counting)
    units = list(tree)
    assert [u.index for u in units] == tree.units and built == []
    assert [u.motion for u in units] == [ex.foon.fu(i).motion for i in tree.units]
    assert built == []
    first = units[0]
    assert first.inputs == tuple(real(ex.foon, o) for o in first.input_ids)
    assert built == list(first.input_ids)
    assert first == ex.foon.fu(first.index)


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"method": 5}, "method must be a str"),
        ({"compat": 1}, "compat must be a str"),
        ({"method": "greedy-inputs", "count": None}, "count must be a str"),
        ({"motions": 5}, "motions must be"),
        ({"motions": {"mix": "x"}}, "the rate of 'mix' in motions"),
        ({"motions": {1: 0.5}}, "a motion of motions must be a str"),
        ({"default_rate": "0.5"}, "default_rate must be a number"),
        ({"default_rate": True}, "default_rate must be a number"),
        ({"utensils": [1]}, "utensils[0] must be a str"),
        ({"utensils": 5}, "utensils must be"),
    ],
)
def test_every_planning_argument_is_type_checked(kwargs: dict[str, Any], named: str) -> None:
    ex = foon.example()
    with pytest.raises(TypeError) as e:
        ex.foon.plan(ex.goals[0], ex.kitchen, **kwargs)
    assert named in str(e.value)


def test_check_paths_are_type_checked() -> None:
    with pytest.raises(TypeError, match="paths must be a path or an iterable of paths"):
        foon.check(5)  # type: ignore[arg-type]


def test_rate_tables_in_code_follow_the_rate_file_rule() -> None:
    """Motion names given in code are trimmed and lower-cased as a rate file's are, so they
    match the FOON's (lower-cased) motions; two spellings of one motion are one motion."""
    ex = foon.example()
    shouting = {m.upper() + " ": r for m, r in ex.motions.items()}
    assert dict(foon.MotionRates(shouting)) == dict(ex.motions)
    a = ex.foon.plan(ex.goals[0], ex.kitchen, "greedy-success", motions=shouting)
    b = ex.foon.plan(ex.goals[0], ex.kitchen, "greedy-success", motions=ex.motions)
    assert a.units == b.units and a.success == b.success
    with pytest.raises(ValueError, match="has two rates"):
        foon.MotionRates({"mix": 0.5, "Mix": 0.6})
    assert len(foon.MotionRates({"mix": 0.5, "Mix ": 0.5})) == 1
