"""Pictures in the FOON visual language: DOT from the core writer, rendered by Graphviz.

DOT is parsed back with ``pydot`` and checked by ``dot -Tcanon``; SVG is parsed as XML and its
nodes counted through their classes (``g.node.motion``, ``g.node.object``, ``goal``,
``leaf``); PNG and PDF are checked by their signatures. Tests that need Graphviz or
``pydot`` skip without them, and fail instead when ``CI`` is set (CI installs them).
"""

from __future__ import annotations

import os
import re
import shutil
import stat
import subprocess
import warnings
import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path
from typing import Any

import foon
import pytest
from conftest import Course
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

SVG = "{http://www.w3.org/2000/svg}"


def need_dot() -> None:
    """Skips without Graphviz's ``dot`` (fails when CI is set)."""
    if shutil.which("dot"):
        return
    if os.environ.get("CI"):
        pytest.fail("CI is set but Graphviz's dot is not installed (apt-get install graphviz)")
    pytest.skip("Graphviz's dot is not installed (apt-get install graphviz)")


def parse_dot(text: str) -> Any:
    """pydot's graphs of a DOT text (skips without pydot; fails when CI is set)."""
    # pydot 4.0 calls pyparsing names that pyparsing 3.3 deprecates: not our warning.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        try:
            import pydot
        except ImportError:
            if os.environ.get("CI"):
                pytest.fail("CI is set but pydot is not installed (pip install pydot)")
            pytest.skip("pydot is not installed (pip install pydot)")
        return pydot.graph_from_dot_data(text)


# --------------------------------------------------------------------------------------------
# Reading pictures back
# --------------------------------------------------------------------------------------------


def unquote(s: str) -> str:
    """A DOT label as Graphviz shows it (the writer's escapes undone)."""
    if s.startswith('"') and s.endswith('"'):
        s = s[1:-1]
    out = []
    i = 0
    while i < len(s):
        c = s[i]
        if c == "\\" and i + 1 < len(s):
            n = s[i + 1]
            out.append("\n" if n == "n" else n)
            i += 2
            continue
        out.append(c)
        i += 1
    return "".join(out).replace("&amp;", "&")


def dot_nodes(text: str) -> dict[str, dict[str, str]]:
    """Every node of a DOT text (clusters included): name -> attributes, through pydot."""
    graphs = parse_dot(text)
    assert graphs is not None and len(graphs) == 1, "pydot could not parse the DOT"
    nodes: dict[str, dict[str, str]] = {}

    def walk(g: Any) -> None:
        for n in g.get_nodes():
            name = n.get_name()
            if name in ("node", "edge", "graph"):
                continue
            assert name not in nodes, f"node {name} is declared twice"
            nodes[name] = n.get_attributes()
        for s in g.get_subgraphs():
            walk(s)

    walk(graphs[0])
    return nodes


def classes(nodes: dict[str, dict[str, str]]) -> Counter[str]:
    """How many nodes carry each class word."""
    c: Counter[str] = Counter()
    for attrs in nodes.values():
        for word in unquote(attrs.get("class", "")).split():
            c[word] += 1
    return c


def canon(text: str) -> str:
    """``dot -Tcanon`` of the text (it must accept it)."""
    need_dot()
    r = subprocess.run(["dot", "-Tcanon"], input=text.encode(), capture_output=True, check=False)
    assert r.returncode == 0, r.stderr.decode(errors="replace")
    return r.stdout.decode()


def svg_nodes(svg: str) -> Counter[str]:
    """How many SVG ``g.node`` elements carry each class word."""
    root = ET.fromstring(svg)
    c: Counter[str] = Counter()
    for g in root.iter(f"{SVG}g"):
        words = g.get("class", "").split()
        if "node" in words:
            c.update(w for w in words if w != "node")
    return c


def expected_label(o: foon.Object) -> str:
    """An object's label as the picture shows it, with line breaks as spaces."""
    parts = [o.label]
    if o.states:
        parts.append("(" + ", ".join(o.states) + ")")
    if o.ingredients:
        parts.append("{" + ", ".join(o.ingredients) + "}")
    if o.container is not None:
        parts.append(f"in [{o.container}]")
    return shown(" ".join(parts))


def shown(text: str) -> str:
    """Text as the picture shows it: control characters become U+FFFD."""
    return "".join("\ufffd" if (ord(ch) < 0x20 or 0x7F <= ord(ch) <= 0x9F) else ch for ch in text)


def tree_objects(tree: foon.TaskTree) -> set[int]:
    ids = {o for u in tree for o in (*u.input_ids, *u.output_ids)}
    return ids | {tree.goal_id}


def check_tree_dot(tree: foon.TaskTree) -> dict[str, dict[str, str]]:
    """The tree's DOT parses, and its nodes are the tree's: one red square per unit, numbered
    in execution order; one green circle per object, the goal purple, the kitchen leaves
    doubled; labels say each object's label, states, ingredients and container."""
    text = tree.to_dot()
    assert text == tree.to_dot(), "same tree, same bytes"
    nodes = dot_nodes(text)
    c = classes(nodes)
    assert c["motion"] == len(tree.units)
    assert c["object"] == len(tree_objects(tree))
    assert c["goal"] == 1
    if tree.units:
        assert c["leaf"] == tree.leaf_inputs
    for name, attrs in nodes.items():
        cls = unquote(attrs.get("class", "")).split()
        label = unquote(attrs["label"])
        if "motion" in cls:
            fu = int(name.lstrip("m"))
            pos = tree.units.index(fu) + 1
            assert label == shown(f"{pos}. {tree.foon.fu(fu).motion}")
            assert attrs["shape"] == "square" and unquote(attrs["fillcolor"]) == "#e74c3c"
        elif "object" in cls:
            o = int(name.lstrip("o"))
            assert label.replace("\n", " ") == expected_label(tree.foon.object(o))
            assert attrs["shape"] == "circle"
            colour = "#9b59b6" if o == tree.goal_id else "#8fd18f"
            assert unquote(attrs["fillcolor"]) == colour
            assert ("goal" in cls) == (o == tree.goal_id)
            assert attrs["peripheries"] == ("2" if "leaf" in cls else "1")
        else:
            assert cls == ["legend"], name
    return nodes


# --------------------------------------------------------------------------------------------
# The course data
# --------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def planner(course: Course) -> foon.Planner:
    return course.foon.planner(course.kitchen, motions=course.motions, utensils=course.utensils)


@pytest.fixture(scope="module")
def trees(course: Course, planner: foon.Planner) -> list[foon.TaskTree]:
    return [planner.plan(g, "greedy-success") for g in course.goals25]


def test_course_trees_in_the_visual_language(trees: list[foon.TaskTree]) -> None:
    """Every course goal's tree (solved or not): DOT parses with pydot and dot -Tcanon, with
    the right nodes."""
    assert sum(t.solved for t in trees) >= 20
    for t in trees:
        check_tree_dot(t)
        canon(t.to_dot())


def test_course_tree_edges(trees: list[foon.TaskTree]) -> None:
    """Arrows go input -> motion -> output, one per distinct object of a unit (plus the
    legend's one)."""
    t = next(t for t in trees if t.goal.label == "greek salad")
    g = parse_dot(t.to_dot())[0]
    edges: set[tuple[str, str]] = set()

    def walk(x: Any) -> None:
        for e in x.get_edges():
            edges.add((e.get_source(), e.get_destination()))
        for s in x.get_subgraphs():
            walk(s)

    walk(g)
    want = {("legend_object", "legend_motion")}
    for u in t:
        want |= {(f"o{o}", f"m{u.index}") for o in u.input_ids}
        want |= {(f"m{u.index}", f"o{o}") for o in u.output_ids}
    assert edges == want


def test_course_svg_png_pdf(trees: list[foon.TaskTree]) -> None:
    """The Greek salad tree renders: the SVG is XML with one g.node.motion per unit, one
    g.node.object per object; PNG and PDF have their signatures."""
    need_dot()
    t = next(t for t in trees if t.goal.label == "greek salad")
    svg = t.to_svg()
    assert svg == t._repr_svg_()
    c = svg_nodes(svg)
    assert c["motion"] == len(t.units) > 20
    assert c["object"] == len(tree_objects(t))
    assert c["goal"] == 1
    assert c["leaf"] == t.leaf_inputs
    assert c["legend"] == 4
    png = t.write("png")
    assert isinstance(png, bytes) and png.startswith(b"\x89PNG\r\n\x1a\n")
    pdf = t.write("pdf")
    assert isinstance(pdf, bytes) and pdf.startswith(b"%PDF")


def test_several_trees_in_one_picture(planner: foon.Planner, trees: list[foon.TaskTree]) -> None:
    """many=True: one cluster per tree (labelled with its goal), node names unique per
    cluster, every tree's units and objects; failed goals have no place in the picture."""
    trees = trees[:10]  # pydot takes a minute over all 25
    w = foon._foon.TreeWriter("dot", True)
    parts = [w.begin()]
    for t in trees:
        parts.append(w.tree(planner._native, t._plan))
    parts.append(w.failed(("nothing", [], [], None), True, "ids", "not in the FOON"))
    parts.append(w.end())
    text = b"".join(parts).decode()
    assert text.count("subgraph cluster_t") == len(trees)
    nodes = dot_nodes(text)
    c = classes(nodes)
    assert c["motion"] == sum(len(t.units) for t in trees)
    assert c["object"] == sum(len(tree_objects(t)) for t in trees)
    assert c["goal"] == len(trees)
    for i, t in enumerate(trees):
        mine = {n for n in nodes if n.startswith(f"t{i}_")}
        assert {n for n in mine if n.startswith(f"t{i}_m")} == {f"t{i}_m{u}" for u in t.units}
        assert {n for n in mine if n.startswith(f"t{i}_o")} == {
            f"t{i}_o{o}" for o in tree_objects(t)
        }
    canon(text)


def unit_objects(f: foon.Foon) -> list[set[int]]:
    """Each unit's objects (inputs and outputs)."""
    return [set(f.fu(i).input_ids) | set(f.fu(i).output_ids) for i in range(f.fu_count)]


def reference_neighbourhood(units: list[set[int]], focus: int, depth: int) -> list[int]:
    """Depth 0: the units that have ``focus`` as an input or an output; each further level
    adds the units that have an object of an already selected unit."""
    objs = {focus}
    chosen: set[int] = set()
    for level in range(depth + 1):
        new = {i for i, u in enumerate(units) if objs & u} - chosen
        chosen |= new
        if level < depth:
            objs |= {o for i in new for o in units[i]}
    return sorted(chosen)


def drawn_units(text: str) -> list[int]:
    return sorted(int(m) for m in re.findall(r"^\s*m(\d+) \[", text, re.MULTILINE))


def test_course_neighbourhoods(course: Course, trees: list[foon.TaskTree]) -> None:
    """Foon.write(goal=, depth=) draws exactly the units within depth steps of the goal."""
    f = course.foon
    units = unit_objects(f)
    for t in trees:
        for depth in (0, 1, 2):
            text = str(f.write("dot", goal=t.goal_id, depth=depth))
            want = reference_neighbourhood(units, t.goal_id, depth)
            assert drawn_units(text) == want
            if depth == 0:
                c = classes(dot_nodes(text))
                assert c["goal"] == 1 and c["motion"] == len(want)


def test_course_neighbourhood_svg(course: Course, trees: list[foon.TaskTree]) -> None:
    need_dot()
    t = next(t for t in trees if t.goal.label == "greek salad")
    svg = str(course.foon.write("svg", goal=t.goal_id, depth=1))
    c = svg_nodes(svg)
    assert c["motion"] == len(reference_neighbourhood(unit_objects(course.foon), t.goal_id, 1))
    assert c["goal"] == 1


def test_whole_course_foon(course: Course) -> None:
    """The whole course FOON is too big to draw: DOT is still written (text, at any size,
    one cluster per connected piece when there are several); SVG is refused with what to do,
    before Graphviz runs, and max_nodes raises the limit."""
    f = course.foon
    text = str(f.write("dot"))
    assert drawn_units(text) == list(range(f.fu_count))
    assert len(re.findall(r"^\s*o\d+ \[", text, re.MULTILINE)) == f.object_count
    with pytest.raises(foon.OutputError) as e:
        f.write("svg")
    msg = str(e.value)
    for hint in ("--goal", "--depth", "--max-nodes", "--format dot"):
        assert hint in msg, msg
    assert "\n" not in msg
    with pytest.raises(foon.OutputError):
        f.write("svg", max_nodes=10, units=range(10))


def test_kitchen_marks_leaves_in_a_foon_picture(course: Course) -> None:
    f = course.foon
    text = str(f.write("dot", units=range(30), kitchen=course.kitchen))
    nodes = dot_nodes(text)
    for name, attrs in nodes.items():
        if name.startswith("o"):
            leaf = f.object(int(name[1:])) in course.kitchen
            assert ("leaf" in unquote(attrs["class"]).split()) == leaf
            assert attrs["peripheries"] == ("2" if leaf else "1")


def test_bad_object_or_unit_is_an_error(course: Course) -> None:
    f = course.foon
    n = f.object_count
    with pytest.raises(foon.FoonError):
        f.write("dot", goal=n, depth=0)
    with pytest.raises((IndexError, ValueError), match="out of range"):
        foon._foon.write_foon(f._native, "dot", focus=n, depth=0)
    with pytest.raises((IndexError, ValueError), match="out of range"):
        f.write("dot", units=[f.fu_count])


# --------------------------------------------------------------------------------------------
# Graphviz missing or failing
# --------------------------------------------------------------------------------------------


def small_tree() -> foon.TaskTree:
    f = foon.Foon.from_text("O\ta\nS\traw\nM\tcut\nO\ta\nS\tcut\n//\n")
    return f.plan(foon.Object("a", ("cut",)), [foon.Object("a", ("raw",))])


def test_dot_missing(monkeypatch: pytest.MonkeyPatch) -> None:
    """FOON_DOT names a program that does not exist: pictures raise OutputError saying how
    to install Graphviz; DOT still works; Jupyter shows nothing instead of failing."""
    t = small_tree()
    monkeypatch.setenv("FOON_DOT", "/nonexistent/dot")
    for fmt in ("svg", "png", "pdf"):
        with pytest.raises(foon.OutputError, match="apt-get install graphviz"):
            t.write(fmt)
        with pytest.raises(foon.OutputError, match="not found"):
            t.foon.write(fmt)
    assert t._repr_svg_() is None
    assert 'class="motion"' in t.to_dot()
    assert 'class="motion"' in str(t.foon.write("dot"))


def test_dot_failing(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """A failing dot: OutputError with the first line of its stderr."""
    prog = tmp_path / "dot"
    prog.write_text(
        "#!/bin/sh\ncat >/dev/null\necho 'Error: out of memory' >&2\necho more >&2\nexit 2\n"
    )
    prog.chmod(prog.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("FOON_DOT", str(prog))
    with pytest.raises(foon.OutputError) as e:
        small_tree().to_svg()
    assert str(e.value).endswith(": Error: out of memory")


# --------------------------------------------------------------------------------------------
# Generated FOONs with any text
# --------------------------------------------------------------------------------------------

#: Characters that need care in DOT, in Graphviz labels or in XML.
ODD = ['"', "\\", "{", "}", "<", ">", "&", ";", "é", "中", "\u00a0", "\x01", "\x85", "#", "'"]
WORD = st.lists(st.sampled_from([*ODD, "a", "b", " ", "&lt;", "\\n", "\\N"]), max_size=6).map(
    "".join
)


def word(plain: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    return st.builds(lambda a, b: (a + b).strip() or "x", st.sampled_from(["p", "q", "r"]), plain)


@st.composite
def odd_foons(draw: st.DrawFn) -> str:
    """FOON text over a few labels full of odd characters, so objects are shared and labels
    need escaping."""
    labels = draw(st.lists(word(WORD), min_size=1, max_size=4, unique=True))
    states = draw(st.lists(word(WORD), min_size=1, max_size=3, unique=True))
    items = word(st.text(alphabet=["a", "é", '"', "\\", "&", "<", " "], max_size=4))

    def obj() -> str:
        s = f"O\t{draw(st.sampled_from(labels))}\n"
        for state in draw(st.lists(st.sampled_from(states), max_size=2)):
            s += f"S\t{state}\n"
        if draw(st.booleans()):
            s += "S\tcontains\t{" + ",".join(draw(st.lists(items, min_size=1, max_size=2))) + "}\n"
        if draw(st.booleans()):
            s += f"S\tin\t[{draw(st.sampled_from(labels))}]\n"
        return s

    n = draw(st.integers(1, 8))
    text = ""
    for _ in range(n):
        ins = "".join(obj() for _ in range(draw(st.integers(0, 3))))
        outs = "".join(obj() for _ in range(draw(st.integers(1, 2))))
        text += f"{ins}M\t{draw(word(WORD))}\n{outs}//\n"
    return text


@settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow], database=None
)
@given(text=odd_foons())
def test_generated_foons_with_odd_text(text: str) -> None:
    """A whole generated FOON and the tree of every object: DOT parses with pydot and dot
    -Tcanon, has one node per unit and per object with the labels as written; the SVG parses
    as XML with the same counts."""
    need_dot()
    f = foon.Foon.from_text(text)
    whole = str(f.write("dot"))
    assert whole == str(f.write("dot"))
    nodes = dot_nodes(whole)
    c = classes(nodes)
    assert c["motion"] == f.fu_count
    assert c["object"] == f.object_count
    for name, attrs in nodes.items():
        if name.startswith("o"):
            label = unquote(attrs["label"]).replace("\n", " ")
            assert label == expected_label(f.object(int(name[1:])))
        elif name.startswith("m"):
            assert unquote(attrs["label"]) == shown(f.fu(int(name[1:])).motion)
    canon(whole)
    svg = svg_nodes(str(f.write("svg")))
    assert svg["motion"] == f.fu_count and svg["object"] == f.object_count
    made = {o for i in range(f.fu_count) for o in f.fu(i).output_ids}
    kitchen = [f.object(o) for o in range(f.object_count) if o not in made]
    p = f.planner(kitchen)
    for o in range(f.object_count):
        t = p.plan(o, "ids")
        check_tree_dot(t)
    t = p.plan(f.object_count - 1, "ids")
    c = svg_nodes(t.to_svg())
    assert c["motion"] == len(t.units) and c["goal"] == 1
