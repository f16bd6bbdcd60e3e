"""GraphML: the object-motion bipartite graph of a FOON or a task tree (the core's writer).

Every document is checked the same way: it validates against the GraphML 1.0 schema vendored
in tests/xsd (with ``xmlschema``; no network), and networkx loads it into a DiGraph whose
nodes, edges and attributes are those of the FOON: one motion node per unit (its index,
motion, line, rate, step), one object node per object the units use or make (its id, label,
states, ingredients, container, goal and kitchen flags), an edge input -> motion -> output
per (object, unit, direction) with the object's multiplicity in that list as ``count``.
Checked on the course FOON, every subgraph file, the 25 course goal trees, several trees in
one document, and generated FOONs (hypothesis), including arbitrary label text.
``Foon.to_networkx()`` / ``TaskTree.to_networkx()`` give the same graph, and say how to
install networkx when it is missing.

xmlschema validation is slow (about 13 us per byte), so the XSD check runs on every tree,
every generated FOON and a sample of the subgraph files; networkx loads all of them.
"""

from __future__ import annotations

import importlib
import io
import json
import math
import os
import sys
from collections import Counter
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import foon
import pytest
from conftest import DATA, Course, need_shared
from hypothesis import given, settings
from hypothesis import strategies as st
from test_differential import GEN_SETTINGS, GenFoon, draw_case, gen_foons

XSD = Path(__file__).resolve().parent / "xsd" / "graphml.xsd"


def need(module: str) -> Any:
    """The module, or a skip when it is not installed (a failure under CI, which installs
    it)."""
    try:
        return importlib.import_module(module)
    except ImportError:
        if os.environ.get("CI"):
            pytest.fail(f"CI is set but the Python package {module} is not installed")
        pytest.skip(f"the Python package {module} is not installed (pip install {module})")


_SCHEMA: list[Any] = []


def load_schema() -> Any:
    if not _SCHEMA:
        _SCHEMA.append(need("xmlschema").XMLSchema(str(XSD)))
    return _SCHEMA[0]


@pytest.fixture(scope="module")
def schema() -> Any:
    return load_schema()


@pytest.fixture(scope="module")
def nx() -> Any:
    return need("networkx")


def validate(schema: Any, text: str) -> None:
    schema.validate(io.StringIO(text))


def check_graph(
    f: foon.Foon,
    g: Any,
    units: Iterable[int],
    *,
    goal: int | None = None,
    kitchen: foon.Kitchen | None = None,
    rates: dict[str, float] | None = None,
    steps: bool = False,
) -> None:
    """The networkx graph ``g`` is the bipartite graph of ``units`` of ``f``."""
    units = list(units)
    objects: set[int] = set()
    edges: dict[tuple[str, str], tuple[str, int]] = {}
    for u in units:
        fu = f.fu(u)
        objects.update(fu.input_ids, fu.output_ids)
        for role, ids in (("input", fu.input_ids), ("output", fu.output_ids)):
            for o, n in Counter(ids).items():
                pair = (f"o{o}", f"m{u}") if role == "input" else (f"m{u}", f"o{o}")
                edges[pair] = (role, n)
    if goal is not None:
        objects.add(goal)
    assert g.is_directed() and not g.is_multigraph()
    assert g.number_of_nodes() == len(objects) + len(units)
    assert g.number_of_edges() == len(edges)
    for o in objects:
        d = g.nodes[f"o{o}"]
        obj = f.object(o)
        assert d["kind"] == "object" and d["object"] == o
        assert d["label"] == obj.label
        assert json.loads(d["states"]) == list(obj.states)
        assert json.loads(d["ingredients"]) == list(obj.ingredients)
        # No container: no attribute; an empty one ([]): the empty string.
        assert d.get("container") == obj.container
        assert d["goal"] is (o == goal)
        if kitchen is None:
            assert "kitchen" not in d
        else:
            assert d["kitchen"] is (obj in kitchen)
    for i, u in enumerate(units):
        d = g.nodes[f"m{u}"]
        fu = f.fu(u)
        assert d["kind"] == "motion" and d["fu"] == u
        assert d["motion"] == d["label"] == fu.motion
        assert d["line"] == fu.line
        if rates is not None and fu.motion in rates:
            assert math.isclose(d["rate"], rates[fu.motion], rel_tol=1e-15)
        else:
            assert "rate" not in d
        assert d.get("step") == (i + 1 if steps else None)
    for (s, t), (role, n) in edges.items():
        assert g.edges[s, t] == {"role": role, "count": n}


def check_tree(tree: foon.TaskTree, g: Any, kitchen: foon.Kitchen, rates: dict[str, float]) -> None:
    """``g`` is the graph of ``tree``, with its figures as graph attributes."""
    check_graph(tree.foon, g, tree.units, goal=tree.goal_id, kitchen=kitchen, rates=rates,
                steps=True)  # fmt: skip
    a = g.graph
    assert a["kind"] == "tree"
    assert a["method"] == tree.method and a["solved"] is tree.solved
    assert a["units"] == len(tree.units)
    assert a.get("height") == tree.height
    if tree.success is None:
        assert "success" not in a
    else:
        assert math.isclose(a["success"], tree.success, rel_tol=1e-15)
    assert a.get("explanation", "") == tree.explanation()
    assert a["goal"] == a["title"] and tree.goal.label in a["goal"]


# --------------------------------------------------------------------------------------------
# Real data
# --------------------------------------------------------------------------------------------


def subgraph_files() -> list[Path]:
    return sorted(p for d in sorted(DATA.glob("subgraphs_*")) for p in d.glob("*.txt"))


def test_course_foon(course: Course, nx: Any) -> None:
    """The whole course FOON loads in networkx as its bipartite graph (the XSD check of its
    3.5 MB takes xmlschema most of a minute: the same writer is validated on the trees, the
    neighbourhoods and the subgraph files below)."""
    f = course.foon
    text = str(f.write("graphml"))
    assert f.write("graphml") == text  # deterministic
    g = nx.parse_graphml(text)
    check_graph(f, g, range(f.fu_count))
    assert g.graph["kind"] == "foon" and g.graph["title"] == "FOON.txt"
    assert g.graph["units"] == f.fu_count == 2376
    assert "goal" not in g.graph


def test_course_neighbourhood_with_kitchen(course: Course, schema: Any, nx: Any) -> None:
    """A neighbourhood of the course FOON, with the kitchen marked, validates and loads."""
    f = course.foon
    goal = course.goals25[0]
    text = str(f.write("graphml", goal=goal, depth=1, kitchen=course.kitchen))
    validate(schema, text)
    g = nx.parse_graphml(text)
    gid = f.goal_id(goal)
    units = sorted(int(n[1:]) for n in g if n.startswith("m"))
    assert any(gid in (*f.fu(u).input_ids, *f.fu(u).output_ids) for u in units)
    check_graph(f, g, units, goal=gid, kitchen=course.kitchen)
    assert g.graph["goal"] and goal.label in g.graph["goal"]
    assert g.graph["units"] == len(units)


@pytest.mark.filterwarnings("ignore::foon.FoonWarning")
def test_every_subgraph_file(nx: Any, schema: Any) -> None:
    """Every subgraph file loads in networkx as its bipartite graph; every eighth one (and
    any with an empty container) also validates against the XSD. (A few files have units
    the loader drops with a warning, SEMANTICS.md section 1: the graph has the units kept.)"""
    need_shared()
    files = subgraph_files()
    assert len(files) >= 230
    validated = empties = 0
    for i, p in enumerate(files):
        f = foon.load(p)
        text = str(f.write("graphml"))
        g = nx.parse_graphml(text)
        check_graph(f, g, range(f.fu_count))
        assert g.graph["title"] == p.name
        empty = any(o.container == "" for o in f.objects())
        if empty:
            empties += 1
            assert '<data key="node.container"></data>' in text
        if i % 8 == 0 or empty:
            validate(schema, text)
            validated += 1
    assert validated >= 30 and empties >= 1


def test_course_goal_trees(course: Course, schema: Any, nx: Any) -> None:
    """The 25 course goals, for a sound method and the course's own: each tree's GraphML is
    deterministic and loads with the tree's units (numbered in order), rates, goal and
    kitchen; the sound method's trees also validate against the XSD."""
    f = course.foon
    rates = dict(course.motions)
    for method, compat in (("optimal-success", None), ("bfs", "course")):
        trees = f.plan_many(course.goals25, course.kitchen, method, compat=compat,
                            motions=course.motions, utensils=course.utensils)  # fmt: skip
        assert len(trees) == 25
        for tree in trees:
            text = str(tree.write("graphml"))
            assert tree.write("graphml") == text
            if compat is None:
                validate(schema, text)
            check_tree(tree, nx.parse_graphml(text), course.kitchen, rates)


def test_sound_failures_explain_themselves(course: Course, nx: Any) -> None:
    """Whipped cream has no sound tree with the course kitchen: its graph says why."""
    f = course.foon
    goal = next(g for g in course.goals25 if g.label == "whipped cream")
    tree = f.plan(goal, course.kitchen, "optimal-success", motions=course.motions,
                  utensils=course.utensils)  # fmt: skip
    assert not tree.solved
    g = nx.parse_graphml(str(tree.write("graphml")))
    assert g.graph["solved"] is False
    assert g.graph["explanation"] == tree.explanation() != ""


def test_many_trees_in_one_document(course: Course, schema: Any, nx: Any) -> None:
    """Several trees (and a goal that could not be planned) are one <graph> each, in order;
    each is the graph of that tree written alone."""
    f = course.foon
    trees = f.plan_many(course.goals5, course.kitchen, "greedy-success",
                        motions=course.motions, utensils=course.utensils)  # fmt: skip
    w = foon._foon.TreeWriter("graphml", True)
    parts = [w.begin()]
    for t in trees:
        assert t.planner is not None
        parts.append(w.tree(t.planner._native, t._plan))
    parts.append(w.failed(("no such thing", [], [], None), True, "ids", "no goal"))
    parts.append(w.end())
    text = b"".join(parts).decode()
    validate(schema, text)
    graphs = list(nx.readwrite.graphml.GraphMLReader()(string=text))
    assert len(graphs) == len(trees) + 1
    for t, g in zip(trees, graphs, strict=False):
        check_tree(t, g, course.kitchen, dict(course.motions))
        alone = nx.parse_graphml(str(t.write("graphml")))
        assert dict(g.nodes(data=True)) == dict(alone.nodes(data=True))
        assert dict(g.graph) == dict(alone.graph)
    last = graphs[-1]
    assert last.number_of_nodes() == 0
    assert last.graph["error"] == "no goal" and last.graph["goal"] == "no such thing"
    assert last.graph["solved"] is False and last.graph["method"] == "ids"


def test_one_tree_document_holds_one_tree(course: Course) -> None:
    trees = course.foon.plan_many(course.goals5[:2], course.kitchen, "ids",
                                  utensils=course.utensils)  # fmt: skip
    w = foon._foon.TreeWriter("graphml", False)
    w.begin()
    assert trees[0].planner is not None and trees[1].planner is not None
    w.tree(trees[0].planner._native, trees[0]._plan)
    with pytest.raises(ValueError, match="holds one task tree"):
        w.tree(trees[1].planner._native, trees[1]._plan)


# --------------------------------------------------------------------------------------------
# networkx
# --------------------------------------------------------------------------------------------


def test_to_networkx_is_the_graphml_graph(course: Course, nx: Any) -> None:
    f = course.foon
    tree = f.plan(course.goals5[0], course.kitchen, "ids", utensils=course.utensils)
    g = tree.to_networkx()
    assert isinstance(g, nx.DiGraph)
    assert nx.utils.graphs_equal(g, nx.parse_graphml(str(tree.write("graphml"))))
    check_graph(f, g, tree.units, goal=tree.goal_id, kitchen=course.kitchen, steps=True)
    part = f.to_networkx(goal=course.goals5[0], depth=0)
    same = nx.parse_graphml(str(f.write("graphml", goal=course.goals5[0], depth=0)))
    assert nx.utils.graphs_equal(part, same)
    assert part.graph["kind"] == "foon" and part.number_of_nodes() > 0


def test_to_networkx_without_networkx(monkeypatch: pytest.MonkeyPatch) -> None:
    """networkx is an optional extra: without it, a clear ImportError that says how to get
    it (and importing foon never needs it)."""
    f = foon.Foon.from_text("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    tree = f.plan(foon.Object("egg", ["cracked"]), [foon.Object("egg", ["whole"])])
    monkeypatch.setitem(sys.modules, "networkx", None)
    for call, name in ((f.to_networkx, "Foon.to_networkx()"),
                       (tree.to_networkx, "TaskTree.to_networkx()")):  # fmt: skip
        with pytest.raises(ImportError, match=r"pip install 'foon\[networkx\]'") as e:
            call()
        assert name in str(e.value) and e.value.name == "networkx"


# --------------------------------------------------------------------------------------------
# Generated FOONs
# --------------------------------------------------------------------------------------------


@settings(GEN_SETTINGS, max_examples=60)
@given(g=gen_foons(), data=st.data())
def test_generated_foons(g: GenFoon, data: st.DataObject) -> None:
    """A generated FOON, whole and as the tree of each goal drawn: valid GraphML that
    networkx loads as its bipartite graph."""
    schema = load_schema()
    nx = need("networkx")
    case = draw_case(data, g)
    f = case.f
    text = str(f.write("graphml"))
    validate(schema, text)
    check_graph(f, nx.parse_graphml(text), range(f.fu_count))
    rates = dict(foon.MotionRates(case.rates))
    for goal in case.goals:
        tree = f.plan(goal, case.rkitchen, "ids", utensils=sorted(case.utensils),
                      motions=case.rates)  # fmt: skip
        text = str(tree.write("graphml"))
        validate(schema, text)
        check_graph(f, nx.parse_graphml(text), tree.units, goal=tree.goal_id,
                    kitchen=case.rkitchen, rates=rates, steps=True)  # fmt: skip


# Any text but the field and line separators, and NUL (which the parser refuses).
FIELD = st.text(
    st.characters(blacklist_categories=("Cs",), blacklist_characters="\t\n\x00"),
    min_size=1,
    max_size=12,
)
XML_ILLEGAL = {chr(c) for c in range(0x20) if chr(c) not in "\t\n\r"} | {"\ufffe", "\uffff"}


@settings(max_examples=150, deadline=None, derandomize=True)
@given(label=FIELD, state=FIELD, motion=FIELD, ingredient=FIELD, container=FIELD)
def test_any_text_is_escaped(
    label: str, state: str, motion: str, ingredient: str, container: str
) -> None:
    """Whatever the labels, states, ingredients, containers and motions hold (markup,
    quotes, ampersands, carriage returns, any Unicode), the GraphML is valid and networkx
    reads the text back as the core parsed it; a character XML 1.0 cannot hold is a clear
    error instead, and nothing is written."""
    schema = load_schema()
    nx = need("networkx")
    src = (f"O\t{label}\nS\t{state}\nS\tcontains\t{{{ingredient}}}\nS\tin\t[{container}]\n"
           f"M\t{motion}\nO\t{label}\nS\tdone\n//\n")  # fmt: skip
    try:
        f = foon.Foon.from_text(src)
    except foon.FoonError:
        return  # text the parser refuses (an empty label once stripped, ...)
    if f.fu_count == 0:
        return
    objs = list(f.objects())
    # Labels, containers and motions are written as they are; states and ingredients as
    # JSON arrays, whose escapes cover the control characters but not U+FFFE and U+FFFF.
    plain = [o.label for o in objs] + [o.container or "" for o in objs] + [f.fu(0).motion]
    listed = [s for o in objs for s in (*o.states, *o.ingredients)]
    bad = any(c in XML_ILLEGAL for t in plain for c in t)
    bad = bad or any(c in "\ufffe\uffff" for t in listed for c in t)
    if bad:
        with pytest.raises(foon.OutputError, match=r"XML 1\.0\) cannot hold"):
            f.write("graphml")
        return
    text = str(f.write("graphml"))
    validate(schema, text)
    check_graph(f, nx.parse_graphml(text), range(f.fu_count))
