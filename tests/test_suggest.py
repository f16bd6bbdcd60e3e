"""A goal that is not in the FOON: the error (``GoalNotFoundError``, one line) names the objects
nearest to it, at most three, best first, as ``Foon.find_similar`` ranks them for the goal's
states, label and container; for a goal given by object id, none."""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import foon
import pytest
from conftest import DATA, Course
from foon.cli import main
from hypothesis import given, settings
from hypothesis import strategies as st
from test_differential import GEN_SETTINGS, GenFoon, gen_foons

Capture = pytest.CaptureFixture[str]

SMALL = (
    "O\tglass\nS\tempty\nO\tice\nS\tin\t[bag]\nM\tpour\nO\tglass\nS\tcontains\t{ice}\n"
    "O\tice\nS\tin\t[glass]\n//\n"
    "O\tonion\nS\twhole\nM\tchop\nO\tonion\nS\tchopped\nO\tknife\nS\tclean\n//\n"
)

PREFIX = "The goal node does not exist: "


def quiet_text(text: str) -> foon.Foon:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", foon.FoonWarning)
        return foon.Foon.from_text(text)


def nearest(message: str) -> list[str]:
    """The suggestions of a "not found" message (the objects after ``; nearest: ``)."""
    assert message.startswith(PREFIX) and "\n" not in message, message
    _, sep, rest = message.partition("; nearest: ")
    return rest.split("; ") if sep else []


def query_of(goal: foon.Object) -> str:
    """The query the suggestions are ranked for: states, label, ``in`` container."""
    q = " ".join([*goal.states, goal.label])
    return f"{q} in {goal.container}" if goal.container is not None else q


def not_found(f: foon.Foon, goal: object) -> foon.GoalNotFoundError:
    with pytest.raises(foon.GoalNotFoundError) as e:
        f.goal_id(goal)  # type: ignore[arg-type]
    assert isinstance(e.value, foon.FoonError)
    return e.value


def test_a_missing_object_suggests_the_nearest_ones() -> None:
    f = quiet_text(SMALL)
    e = not_found(f, foon.Object("onion", ["sliced"]))
    msg = str(e)
    assert msg == (
        "The goal node does not exist: onion (sliced); nearest: onion (whole); onion (chopped); "
        "ice in [bag]"
    )
    e = not_found(f, foon.Object("ice", container="cup"))
    assert nearest(str(e)) == ["ice in [bag]", "ice in [glass]"]
    # Planning raises the same error, with the same message.
    with pytest.raises(foon.GoalNotFoundError, match=re.escape(msg)):
        f.plan(foon.Object("onion", ["sliced"]))


def test_a_missing_label_suggests_at_most_three_objects() -> None:
    f = quiet_text(SMALL)
    got = nearest(str(not_found(f, "onions")))
    assert got[:2] == ["onion (whole)", "onion (chopped)"] and len(got) <= 3
    assert nearest(str(not_found(f, "glas")))[0].startswith("glass")


def test_the_suggestions_are_find_similar_for_the_goal() -> None:
    f = quiet_text(SMALL)
    for goal in [foon.Object("onion", ["sliced"]), foon.Object("ice", container="cup"),
                 foon.Object("knife", ["dirty"], container="sink")]:  # fmt: skip
        want = [str(s.object) for s in f.find_similar(query_of(goal), 3)]
        assert nearest(str(not_found(f, goal))) == want


def test_an_object_id_out_of_range_has_no_suggestions() -> None:
    f = quiet_text(SMALL)
    n = f.object_count
    assert str(not_found(f, n)) == f"{PREFIX}object id {n} (the FOON has {n} objects)"
    assert nearest(str(not_found(f, -1))) == []


def test_nothing_alike_gives_no_suggestions() -> None:
    f = quiet_text(SMALL)
    assert str(not_found(f, "xyzzy")) == f"{PREFIX}xyzzy"


def test_a_goal_missing_at_a_level_suggests_too() -> None:
    f = quiet_text(SMALL)
    with pytest.raises(foon.GoalNotFoundError) as e:
        f.plan(foon.Object("onion", ["sliced"]), level=2)
    assert str(e.value).startswith(f"{PREFIX}onion (sliced) (at level 2); nearest: onion (whole)")


@given(gen_foons(), st.sampled_from(["onion", "eggs", "ric", "sauce", "pots"]),
       st.lists(st.sampled_from(["whole", "hot", "minced"]), max_size=2))  # fmt: skip
@settings(GEN_SETTINGS, max_examples=80)
def test_generated_foons_suggest_objects_of_the_foon(
    g: GenFoon, label: str, states: list[str]
) -> None:
    f = quiet_text(g.text)
    goal = foon.Object(label, states, container="drawer")
    if f.find(goal) is not None:
        return
    got = nearest(str(not_found(f, goal)))
    described = {str(f.object(o)) for o in range(f.object_count)}
    assert len(got) <= 3 and set(got) <= described
    assert got == [str(s.object) for s in f.find_similar(query_of(goal), 3)]


# --- the command line ---------------------------------------------------------------------------


def run(argv: list[str], capsys: Capture) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_goal_and_label_not_found_name_the_nearest(tmp_path: Path, capsys: Capture) -> None:
    path = tmp_path / "small.foon"
    path.write_text(SMALL)
    base = ["plan", "--foon", str(path), "--quiet"]
    goal = json.dumps({"label": "onion", "states": ["sliced"]})
    code, out, err = run([*base, "--goal", goal], capsys)
    assert code != 0 and "Traceback" not in err
    lines = [ln for ln in (out + err).splitlines() if "does not exist" in ln]
    assert len(lines) == 1
    assert lines[0].endswith(
        "The goal node does not exist: onion (sliced); nearest: onion (whole); onion (chopped); "
        "ice in [bag]"
    )
    code, out, err = run([*base, "--label", "onions"], capsys)
    assert code != 0 and "Traceback" not in err
    lines = [ln for ln in (out + err).splitlines() if "does not exist" in ln]
    assert len(lines) == 1 and "; nearest: onion (whole); onion (chopped)" in lines[0]


def test_cli_json_failed_goal_keeps_the_suggestions(tmp_path: Path, capsys: Capture) -> None:
    path = tmp_path / "small.foon"
    path.write_text(SMALL)
    goal = json.dumps({"label": "onion", "states": ["sliced"]})
    _code, out, _err = run(["plan", "--foon", str(path), "--goal", goal, "--format", "json",
                            "--quiet"], capsys)  # fmt: skip
    doc = json.loads(out)
    items = doc if isinstance(doc, list) else [doc]
    errors = [d["error"] for d in items if "error" in d]
    assert errors and nearest(errors[0]) == ["onion (whole)", "onion (chopped)", "ice in [bag]"]


def test_course_goal_typo_suggests_the_real_goal(course: Course) -> None:
    goal = course.goals5[0]
    typo = foon.Object(goal.label + "x", goal.states, goal.ingredients, goal.container)
    got = nearest(str(not_found(course.foon, typo)))
    assert len(got) == 3
    assert DATA.exists()
