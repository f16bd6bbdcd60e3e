"""``foon find`` / ``Foon.find_similar``: objects ranked by similarity to a free-text query."""

from __future__ import annotations

import argparse
import io
import json
from contextlib import redirect_stdout

import foon
import pytest
from conftest import DATA, Course
from foon._cli_find import add_find_options, cmd_find

TEXT = """O\tonion\nS\twhole\nM\tchop\nO\tonion\nS\tchopped\nS\tin\t[bowl]\n//
O\tonion\nS\tchopped\nS\tin\t[bowl]\nM\tfry\nO\tonion\nS\tfried\nS\tin\t[pan]\n//
O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\nS\tin\t[bowl]\n//
"""


def test_best_match_first_and_sorted() -> None:
    f = foon.Foon.from_text(TEXT)
    found = f.find_similar("chopped onoin in bowl", 10)
    assert found[0].object == foon.Object("onion", ("chopped",), (), "bowl")
    assert [s.score for s in found] == sorted((s.score for s in found), reverse=True)
    assert len(found) == len({s.object_id for s in found})
    assert all(0.0 <= s.score <= 1.0 for s in found)
    assert f.find_similar("egg", 1)[0].object.label == "egg"
    assert f.find_similar("fried onion in [pan]", 1)[0].object.states == ("fried",)
    assert f.find_similar("onion", 0) == []
    assert f.find_similar("chopped onoin in bowl", 10) == found  # deterministic


def test_bad_arguments() -> None:
    f = foon.Foon.from_text(TEXT)
    with pytest.raises(ValueError):
        f.find_similar("onion", -1)
    with pytest.raises(TypeError):
        f.find_similar(3, 1)  # type: ignore[arg-type]


def test_exact_objects_of_the_course_come_first(course: Course) -> None:
    """Every object of the course FOON written as a query scores 1 and comes first (or tied
    with others that score 1)."""
    f = course.foon
    for i in range(0, f.object_count, 97):
        o = f.object(i)
        if o.ingredients or not all(w.isalpha() for st in o.states for w in st.split()):
            continue
        q = " ".join((*o.states, o.label)) + (f" in {o.container}" if o.container else "")
        found = f.find_similar(q, 5)
        assert found[0].score == pytest.approx(1.0), q
        assert i in [s.object_id for s in found if s.score == pytest.approx(1.0)] or any(
            f.object(s.object_id).label == o.label for s in found
        ), q


def test_cli_json(course: Course) -> None:
    p = argparse.ArgumentParser()
    add_find_options(p)
    out = io.StringIO()
    with redirect_stdout(out):
        rc = cmd_find(p.parse_args(["--foon", str(DATA / "FOON.txt"), "chopped onion in bowl",
                                    "-k", "3", "--json"]))  # fmt: skip
    d = json.loads(out.getvalue())
    assert rc == 0 and len(d) == 3
    assert d[0]["object"]["label"] == "onion" and d[0]["object"]["container"] == "bowl"
