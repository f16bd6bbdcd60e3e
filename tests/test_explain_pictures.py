"""Pictures of ``foon explain`` (the blocking part of a goal) and the page of ``foon split``
(the front as a chart).

The DOT of a blocked goal is checked against what the explanation says, on the course's
blocked goals and on generated FOONs: one motion node per producer and cycle unit, one object
node per goal, blocking input and cycle object, each blocking input marked by its kind. The
SVG and the pages are rendered (Graphviz, headless Chromium) and their nodes, colours and
chart points counted (see ``test_html.py`` for the browser helpers).
"""

from __future__ import annotations

import argparse
import re
from collections import Counter
from pathlib import Path

import foon
import pytest
from conftest import DATA, Course
from foon._cli_explain import add_explain_options, cmd_explain
from foon._cli_split import add_split_options, cmd_split
from hypothesis import given, settings
from hypothesis import strategies as st
from test_differential import GEN_SETTINGS, GenFoon, draw_case, gen_foons
from test_html import colours, need_dot, rendered, screenshot

SUFFIX = {"missing": "[missing]", "cycle": "[cycle]", "not-derivable": "[not derivable]"}
BORDER = {"missing": "filled,dashed", "cycle": "filled,bold", "not-derivable": "filled,dotted"}


def expected_nodes(e: foon.GoalExplanation) -> tuple[set[int], set[int]]:
    """(objects, motions) the picture of a blocked goal must draw."""
    objects = {e.goal_id} | set(e.cycle_ids)
    objects |= {b.object_id for p in e.producers for b in p.blockers}
    motions = {p.unit for p in e.producers} | set(e.cycle_units)
    return objects, motions


def node_lines(dot: str) -> dict[str, str]:
    """Node name -> its attribute text, legend left out."""
    out = {}
    for line in dot.splitlines():
        m = re.match(r"\s*([om]\d+) \[(.*)\];$", line)
        if m:
            out[m.group(1)] = m.group(2)
    return out


def check_dot(e: foon.GoalExplanation) -> str:
    dot = e.to_dot()
    objects, motions = expected_nodes(e)
    nodes = node_lines(dot)
    assert {n for n in nodes if n[0] == "o"} == {f"o{o}" for o in objects}
    assert {n for n in nodes if n[0] == "m"} == {f"m{u}" for u in motions}
    assert 'class="object goal' in nodes[f"o{e.goal_id}"]
    assert 'fillcolor="#9b59b6"' in nodes[f"o{e.goal_id}"]
    for u in motions:
        assert 'shape=square, fillcolor="#e74c3c"' in nodes[f"m{u}"]
    for p in e.producers:
        assert 'class="motion producer' in nodes[f"m{p.unit}"]
        assert f"m{p.unit} -> o{e.goal_id}" in dot
        for b in p.blockers:
            attrs = nodes[f"o{b.object_id}"]
            assert f"blocker {b.kind}" in attrs, attrs
            assert f'style="{BORDER[b.kind]}"' in attrs
            assert SUFFIX[b.kind] + '"' in attrs
            assert f"o{b.object_id} -> m{p.unit}" in dot
    # Every arrow is drawn once; the cycle's arrows are marked.
    arrows = re.findall(r"^\s*([om]\d+ -> [om]\d+)", dot, re.MULTILINE)
    assert len(arrows) == len(set(arrows))
    cycle = {
        pair
        for i, u in enumerate(e.cycle_units)
        for pair in (f"o{e.cycle_ids[i + 1]} -> m{u}", f"m{u} -> o{e.cycle_ids[i]}")
    }
    assert len(re.findall(r'\[class="cycle"', dot)) == len(cycle)
    for pair in cycle:
        assert f'{pair} [class="cycle"' in dot
    return dot


@pytest.mark.parametrize("label", ["whipped cream", "fried rice"])
def test_course_blocked_goals_as_pictures(course: Course, label: str, tmp_path: Path) -> None:
    """Blocked by cycles: DOT with the producers, blockers and cycle; the SVG has the same
    nodes; the page shows red, green and purple in Chromium and its script counts them."""
    goal = next(g for g in course.goals25 if g.label == label)
    e = course.foon.explain(goal, course.kitchen, motions=course.motions, utensils=course.utensils)
    assert e.status == "blocked" and e.cycle
    check_dot(e)
    objects, motions = expected_nodes(e)
    need_dot()
    svg = str(e.write("svg"))
    assert len(re.findall(r'class="node motion[ "]', svg)) == len(motions)
    assert len(re.findall(r'class="node object[ "]', svg)) == len(objects)
    png = e.write("png")
    assert isinstance(png, bytes) and png.startswith(b"\x89PNG\r\n\x1a\n")
    text = str(e.write("html"))
    for fetch in ("<link", " src=", "@import", "url(", "href="):
        assert fetch not in text
    assert "blocking cycle: " in text
    page = tmp_path / "explain.html"
    page.write_text(text, encoding="utf-8")
    got = rendered(page)
    assert got.body["data-page"] == "explain"
    assert got.body["data-motions"] == got.body["data-motions-shown"] == str(len(motions))
    assert got.body["data-objects"] == got.body["data-objects-shown"] == str(len(objects))
    c = colours(screenshot(page, 1400))
    assert c["red"] > 200 and c["green"] > 200 and c["purple"] > 200, c


def test_a_derivable_goal_is_drawn_as_its_tree(course: Course) -> None:
    goal = course.goals5[1]
    e = course.foon.explain(goal, course.kitchen, motions=course.motions, utensils=course.utensils)
    assert e.status == "derivable" and e.tree is not None
    dot = e.to_dot()
    assert dot.count('class="motion"') == len(e.tree.units)
    assert "derivable" in dot.splitlines()[1]


def test_a_missing_raw_item_and_formats() -> None:
    """A raw item missing from the kitchen is marked so; text formats are refused."""
    text = "O\tsalt\nS\tdry\nO\twater\nS\thot\nM\tmix\nO\tbrine\nS\tsalty\n//\n"
    f = foon.Foon.from_text(text)
    e = f.explain(foon.Object("brine", ("salty",)), [foon.Object("water", ("hot",))])
    assert e.status == "blocked" and e.buyable
    dot = check_dot(e)
    assert dot.count("[missing]") == 2  # the node and the legend
    with pytest.raises(ValueError, match="cannot write an explanation"):
        e.write("json")
    with pytest.raises(ValueError, match="unknown format"):
        e.write("gif")


@settings(GEN_SETTINGS, max_examples=60)
@given(g=gen_foons(), data=st.data())
def test_generated_blocking_parts(g: GenFoon, data: st.DataObject) -> None:
    """Cycles, self-loops and duplicates: the picture of every blocked goal has exactly the
    explanation's nodes and arrows, each blocker marked by its kind."""
    case = draw_case(data, g)
    planner = case.f.planner(case.rkitchen, utensils=sorted(case.utensils))
    for goal in case.goals:
        e = planner.explain(goal)
        if e.status == "blocked":
            check_dot(e)


# --------------------------------------------------------------------------------------------
# The split page
# --------------------------------------------------------------------------------------------


def split_points(page: str) -> list[tuple[int, float]]:
    return [
        (int(x), float(y))
        for x, y in re.findall(r'<circle class="point" data-x="(\d+)" data-y="([^"]+)"', page)
    ]


def test_course_split_page(course: Course, tmp_path: Path) -> None:
    """The chart's points are the front's points (exactly); each point lists its steps;
    nothing is fetched; Chromium draws every point."""
    profiles = foon.Profiles({"robot": course.motions})
    goal = course.goals5[1]
    r = course.foon.split(goal, course.kitchen, profiles, 3, utensils=course.utensils)
    assert r.solved and r.front
    text = r.write("html")
    assert split_points(text) == [(p.human, p.success) for p in r.front]
    for fetch in ("<link", " src=", "@import", "url(", "href="):
        assert fetch not in text
    for i, p in enumerate(r.front):
        sec = text.split(f'id="point-{i}"')[1].split("</section>")[0]
        who = Counter(re.findall(r'<li class="(robot|human)">', sec))
        assert who == Counter(s.actor for s in p.steps)
    page = tmp_path / "split.html"
    page.write_text(text, encoding="utf-8")
    got = rendered(page)
    assert got.body["data-page"] == "split"
    assert got.body["data-points"] == got.body["data-points-shown"] == str(len(r.front))
    with pytest.raises(ValueError, match="cannot write a split"):
        r.write("svg")


def test_an_unsolved_split_has_no_points() -> None:
    f = foon.Foon.from_text("O\tbroth\nS\thot\nM\tcook\nO\tsoup\nS\thot\n//\n")
    r = f.split(foon.Object("soup", ("hot",)), [], {"robot": {"cook": 0.5}}, 2)
    assert not r.solved
    text = r.write("html")
    assert split_points(text) == [] and "no front" in text


# --------------------------------------------------------------------------------------------
# Command line
# --------------------------------------------------------------------------------------------


def run(add: object, cmd: object, argv: list[str]) -> int:
    p = argparse.ArgumentParser()
    add(p)  # type: ignore[operator]
    return int(cmd(p.parse_args(argv)))  # type: ignore[operator]


def test_cli_writes_pictures(course: Course, tmp_path: Path) -> None:
    need_dot()
    common = ["--foon", str(DATA / "FOON.txt"), "--kitchen", str(DATA / "kitchen.json"),
              "--motions", str(DATA / "motion.txt")]  # fmt: skip
    goal = '{"label": "whipped cream", "states": ["whipped", "creamy"], "container": "mixing bowl"}'
    out = tmp_path / "wc.svg"
    rc = run(add_explain_options, cmd_explain,
             [*common, "--goal", goal, "--format", "svg", "-o", str(out)])  # fmt: skip
    assert rc == 1  # blocked, as without --format
    assert out.read_text().rstrip().endswith("</svg>")
    page = tmp_path / "split.html"
    g1 = course.goals5[1].to_dict()
    import json

    rc = run(add_split_options, cmd_split,
             [*common, "--goal", json.dumps(g1), "--format", "html", "-o", str(page)])  # fmt: skip
    assert rc == 0 and 'data-page="split"' in page.read_text()
    with pytest.raises(foon.cli.UsageError):
        run(add_explain_options, cmd_explain, [*common, "--goal", goal, "-o", str(out)])
    with pytest.raises(foon.cli.UsageError):
        run(add_split_options, cmd_split,
            [*common, "--goal", json.dumps(g1), "--format", "html", "--json"])  # fmt: skip


def test_copies_pickle_without_the_picture() -> None:
    """Explanations and splits still copy and pickle (equal to the original); a copy says
    how to get its picture back."""
    import copy
    import pickle

    f = foon.Foon.from_text("O\tsalt\nS\tdry\nM\tmix\nO\tbrine\nS\tsalty\n//\n")
    goal = foon.Object("brine", ("salty",))
    e = f.explain(goal, [])
    r = f.split(goal, [], {"robot": {"mix": 0.5}}, 1)
    for x, again in ((e, "explain the goal again"), (r, "split the goal again")):
        for y in (copy.deepcopy(x), pickle.loads(pickle.dumps(x))):
            assert y == x
            with pytest.raises(ValueError, match=again):
                y.write("html")
    assert "digraph" in e.to_dot() and 'data-page="split"' in r.write("html")
