"""JSON: every JSON document foon writes validates against ``schema/foon.schema.json``; a FOON
written as JSON (the lab's dialect) loads back to the same FOON, on every data file and on
generated FOONs; JSON FOONs load everywhere a FOON does, with located errors."""

from __future__ import annotations

import json
import os
import warnings
from pathlib import Path
from typing import Any

import foon
import pytest
from conftest import DATA, Course, need_shared
from foon import _foon
from foon.cli import main
from hypothesis import HealthCheck, given, settings
from test_differential import GenFoon, gen_foons

Capture = pytest.CaptureFixture[str]
SCHEMA_PATH = Path(__file__).resolve().parents[1] / "schema" / "foon.schema.json"

try:
    import jsonschema
    import referencing
except ImportError:  # pragma: no cover - CI installs it
    jsonschema = None


def _schema() -> dict[str, Any]:
    s: dict[str, Any] = json.loads(SCHEMA_PATH.read_text(encoding="utf-8"))
    return s


def validate(doc: Any, name: str) -> None:
    """Validates ``doc`` against ``$defs/name`` of the committed schema (and its root)."""
    if jsonschema is None:
        if os.environ.get("CI"):
            pytest.fail("CI is set but the jsonschema package is missing")
        pytest.skip("the jsonschema package is not installed (pip install jsonschema)")
    schema = _schema()
    registry = referencing.Registry().with_resource(
        schema["$id"], referencing.Resource.from_contents(schema)
    )
    cls = jsonschema.Draft202012Validator
    cls(schema, registry=registry).validate(doc)
    cls({"$ref": f"{schema['$id']}#/$defs/{name}"}, registry=registry).validate(doc)


def run(argv: list[str], capsys: Capture) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def quiet_load(path: Path | str) -> foon.Foon:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", foon.FoonWarning)
        return foon.load(path)


def quiet_text(text: str, path: str | None = None) -> foon.Foon:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", foon.FoonWarning)
        return foon.Foon.from_text(text, path=path)


# --- the schema ----------------------------------------------------------------------------


def test_schema_is_a_versioned_draft_2020_12_schema() -> None:
    s = _schema()
    assert s["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    assert s["$id"].endswith("/v1/foon.schema.json")
    want = {"object", "foon", "kitchen", "goals", "task_tree", "task_trees", "comparison",
            "verify", "check", "stats"}  # fmt: skip
    assert want <= set(s["$defs"])
    if jsonschema is not None:
        jsonschema.Draft202012Validator.check_schema(s)


def test_schema_refuses_what_foon_would_refuse() -> None:
    """The schema is not a rubber stamp: documents the loader refuses fail it too."""
    if jsonschema is None:
        validate(None, "foon")  # skips or fails with the reason
    good = [{"input_nodes": [{"label": "a"}], "motion_node": "m", "output_nodes": []}]
    validate(good, "foon")
    bad = [
        [{"input_nodes": [], "output_nodes": []}],
        [{"input_nodes": [{"label": ""}], "motion_node": "m", "output_nodes": []}],
        [{"input_nodes": [{"label": "a", "in_motion": 2}], "motion_node": "m", "output_nodes": []}],
        [
            {
                "input_nodes": [{"label": "a", "ingredients": ["x,y"]}],
                "motion_node": "m",
                "output_nodes": [],
            }
        ],
        [{"input_nodes": [{"label": "a\tb"}], "motion_node": "m", "output_nodes": []}],
    ]
    for doc in bad:
        with pytest.raises(jsonschema.ValidationError):
            validate(doc, "foon")
        with pytest.raises(foon.ParseError):
            quiet_text(json.dumps(doc))


# --- FOON <-> JSON round trips ------------------------------------------------------------


def assert_round_trip(f: foon.Foon, check_schema: bool = False) -> None:
    """FOON -> JSON -> FOON loses nothing: the same course text, the same units and objects
    (same identities, same ids), and the same JSON again (in-motion flags and motion
    metadata included)."""
    text = f.to_json()
    if check_schema:
        validate(json.loads(text), "foon")
    g = quiet_text(text, path="again.json")
    assert g.fu_count == f.fu_count and g.object_count == f.object_count
    assert g.to_text() == f.to_text()
    for i in range(f.object_count):
        assert g.object(i).identity() == f.object(i).identity(), i
        assert g.object(i) == f.object(i)
    for i in range(f.fu_count):
        a, b = f.fu(i), g.fu(i)
        assert (a.motion, a.input_ids, a.output_ids) == (b.motion, b.input_ids, b.output_ids)
    assert g.to_json() == text
    assert g.stats()["duplicates_dropped"] == 0


def foon_files() -> list[Path]:
    """Every data file that loads as a FOON with at least one unit (FOON text in every
    dialect, and the lab's JSON)."""
    out = []
    for p in sorted(DATA.rglob("*")):
        if not p.is_file() or p.suffix not in (".txt", ".json"):
            continue
        try:
            f = quiet_load(p)
        except foon.FoonError:
            continue  # kitchens, goal lists, motion tables
        if f.fu_count:
            out.append(p)
    return out


def test_every_data_file_round_trips() -> None:
    need_shared()
    files = foon_files()
    dirs = {p.parent.name for p in files}
    # Every dialect is among them: the course file, the lab's history, the subgraphs of
    # every source, and the lab's JSON.
    assert {"foon", "lab_history", "subgraphs_foon_api_FOON-111", "subgraphs_misc",
            "subgraphs_sakib_TXT", "subgraphs_sakib_JSON"} <= dirs  # fmt: skip
    for p in files:
        f = quiet_load(p)
        small = p.parent.name.startswith("subgraphs") or p.name == "FOON.txt"
        assert_round_trip(f, check_schema=small and p.name < "0020")


def test_course_foon_json_validates(course: Course) -> None:
    validate(json.loads(course.foon.to_json()), "foon")


def test_in_motion_flags_and_motion_times_survive() -> None:
    text = "//\nO1\tknife\t1\nS\tclean\nM\tchop\t<1:10,1:11>\nO2\tonion\t0\nS\tchopped\n//\n"
    f = foon.Foon.from_text(text)
    d = json.loads(f.to_json())
    assert d[0]["input_nodes"][0]["in_motion"] == 1
    assert d[0]["output_nodes"][0]["in_motion"] == 0
    assert d[0]["motion_meta"] == "<1:10,1:11>"
    plain = foon.Foon.from_text("//\nO\tknife\nS\tclean\nM\tchop\nO\tknife\nS\tdirty\n//\n")
    d = json.loads(plain.to_json())
    assert "in_motion" not in d[0]["input_nodes"][0] and "motion_meta" not in d[0]
    assert_round_trip(f)


GEN = settings(max_examples=200, deadline=None, derandomize=True,
               suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])  # fmt: skip


@GEN
@given(g=gen_foons())
def test_generated_foons_round_trip(g: GenFoon) -> None:
    f = foon.Foon.from_text(g.text)
    assert_round_trip(f)
    # The JSON of a FOON is deterministic: the same input, the same bytes.
    assert foon.Foon.from_text(g.text).to_json() == f.to_json()


# --- loading JSON FOONs everywhere ----------------------------------------------------------

LAB = """[
    {
        "input_nodes": [
            {"label": "Onion", "states": ["whole"], "ingredients": [], "container": null},
            {"label": "knife", "states": [], "ingredients": [], "container": null}
        ],
        "motion_node": "Chop",
        "output_nodes": [
            {"label": "onion", "states": ["chopped"], "ingredients": [], "container": null}
        ]
    }
]
"""


def test_json_detected_by_content_not_extension(tmp_path: Path) -> None:
    p = tmp_path / "recipe.txt"
    p.write_text("\ufeff  \n" + LAB, encoding="utf-8")
    f = foon.load(p)
    assert f.fu_count == 1 and f.fu(0).motion == "chop"
    # Labels, states and motions follow the text rules (lower-cased).
    assert f.fu(0).inputs[0] == foon.Object("onion", ("whole",))
    assert foon.Foon.from_text(LAB.encode()).to_text() == f.to_text()
    assert f.fu(0).line == 3  # the line where the unit starts (after a blank line and "[")


def test_cli_reads_json_foons(tmp_path: Path, capsys: Capture) -> None:
    p = tmp_path / "recipe.json"
    p.write_text(LAB, encoding="utf-8")
    kitchen = tmp_path / "kitchen.json"
    kitchen.write_text(
        foon.Kitchen([foon.Object("onion", ("whole",)), foon.Object("knife")]).to_json()
    )
    goal = json.dumps({"label": "onion", "states": ["chopped"]})
    code, out, err = run(["plan", "--foon", str(p), "--kitchen", str(kitchen), "--goal", goal,
                          "--format", "json"], capsys)  # fmt: skip
    assert code == 0, err
    trees = json.loads(out)
    validate(trees, "task_trees")
    assert trees[0]["solved"] and trees[0]["source"] == str(p)
    code, out, err = run(["stats", str(p), "--json"], capsys)
    assert code == 0
    rows = json.loads(out)
    validate(rows, "stats")
    assert rows[0]["file"] == str(p) and rows[0]["functional_units"] == 1
    code, out, err = run(["check", str(p), "--json"], capsys)
    validate(json.loads(out), "check")
    assert code == 0 and json.loads(out) == []


MALFORMED = [
    # (text, line, column, words of the reason)
    ('{"input_nodes": []}', 1, 1, "not one object"),
    ('[\n  {"input_nodes": [], "output_nodes": []}\n]', 2, 3, "missing field `motion_node`"),
    (
        '[\n {"input_nodes": [\n  {"states": ["x"]}\n ], "motion_node": "m", "output_nodes": []}]',
        3,
        3,
        "missing field `label`",
    ),
    (
        '[{"input_nodes": [{"label": ""}], "motion_node": "m", "output_nodes": []}]',
        1,
        31,
        "empty object label",
    ),
    (
        '[{"input_nodes": [{"label": "a", "states": [1]}], "motion_node": "m", "output_nodes": []}]',
        1,
        45,
        "expected a string",
    ),
    (
        '[{"input_nodes": [], "motion_node": "m", "output_nodes": [], "colour": 1}]',
        1,
        69,
        "unknown field `colour`",
    ),
    ('[{"input_nodes": [], "motion_node": "  ", "output_nodes": []}]', 1, 40, "empty motion"),
    ('[{"input_nodes": [], "motion_node": "m", "output_nodes": []},\n]', 2, 1, "trailing comma"),
    ('[{"input_nodes": [], "motion_node": "m", "output_nodes": []}', 1, 61, "no closing ']'"),
    ('[{"input_nodes": [], "motion_node": "m", "output_nodes": []}] x', 1, 63, "unexpected text"),
    ('[["a"]]', 1, 2, "expected a functional unit"),
    (
        (
            '[{"input_nodes": [{"label": "é", "ingredients": ["a,b"]}], "motion_node": "m", '
            '"output_nodes": []}]'
        ),
        1,
        56,
        "holds a ','",
    ),
    (
        '[{"input_nodes": [{"label": "a", "in_motion": 3}], "motion_node": "m", "output_nodes": []}]',
        1,
        48,
        "in_motion is 0 or 1",
    ),
    (
        '[{"input_nodes": [{"label": "a\\nb"}], "motion_node": "m", "output_nodes": []}]',
        1,
        35,
        "control character",
    ),
    ('[{"input_nodes": [}]', 1, 19, "expected value"),
]


@pytest.mark.parametrize(("text", "line", "column", "reason"), MALFORMED)
def test_malformed_json_foons_name_file_line_and_column(
    tmp_path: Path, text: str, line: int, column: int, reason: str, capsys: Capture
) -> None:
    p = tmp_path / "bad.json"
    p.write_text(text, encoding="utf-8")
    with pytest.raises(foon.ParseError) as e:
        foon.load(p)
    msg = str(e.value)
    assert msg.startswith(f"{p}:{line}:{column}: FOON error: "), msg
    assert reason in msg and "\n" not in msg
    # The command line says the same, on one line, with no traceback.
    code, out, err = run(["stats", str(p)], capsys)
    assert code != 0 and out == ""
    assert f"{p}:{line}:{column}" in err and "Traceback" not in err


def test_invalid_utf8_in_a_json_foon(tmp_path: Path) -> None:
    p = tmp_path / "bad.json"
    p.write_bytes(b'[\n  {"input_nodes": [{"label": "\xff"}]}]')
    with pytest.raises(foon.ParseError, match=r"bad.json:2:\d+: FOON error: invalid UTF-8"):
        foon.load(p)


def test_check_reports_every_bad_unit_of_a_json_foon(tmp_path: Path) -> None:
    """foon check goes on after a unit with a bad value (the unit is dropped)."""
    units = [
        {
            "input_nodes": [{"label": "a"}],
            "motion_node": "m",
            "output_nodes": [{"label": "b", "states": ["x"]}],
        },
        {"input_nodes": [{"label": ""}], "motion_node": "m", "output_nodes": []},
        {
            "input_nodes": [{"label": "b", "states": ["x"]}],
            "motion_node": "n",
            "output_nodes": [{"label": "c", "ingredients": [" d"]}],
        },
        {"input_nodes": [], "output_nodes": []},
    ]
    p = tmp_path / "recipe.json"
    p.write_text(json.dumps(units, indent=2), encoding="utf-8")
    found = foon.check([p])
    errors = [f for f in found if f.severity == "error"]
    assert [f.message for f in errors] == ["empty object label", "missing field `motion_node`"]
    text = p.read_text().splitlines()
    for f in errors:
        assert f.path == str(p) and 1 <= f.line <= len(text)
    assert text[errors[1].line - 1].strip() == "{"  # the unit that lacks the field
    spaced = [f for f in found if f.code == "spaced-ingredient"]
    # Notes are placed at the node they concern.
    assert len(spaced) == 1 and text[spaced[0].line - 1].strip() == "{"
    assert any('" d"' in line for line in text[spaced[0].line : spaced[0].line + 4])


def test_strict_mode_refuses_an_empty_ingredient(tmp_path: Path) -> None:
    doc = (
        '[{"input_nodes": [{"label": "a", "ingredients": [""]}], "motion_node": "m", '
        '"output_nodes": []}]'
    )
    f = foon.Foon.from_text(doc)
    assert f.fu(0).inputs[0].ingredients == ("",)  # kept, as the text parser keeps '{}'
    p = tmp_path / "empty.json"
    p.write_text(doc)
    assert [x.code for x in foon.check([p])] == ["empty-ingredient"]
    with pytest.raises(foon.ParseError, match=r"empty ingredient.*strict mode"):
        foon.Foon.from_text(doc, strict=True)


# --- task trees ------------------------------------------------------------------------------


def course_args() -> list[str]:
    return ["--foon", str(DATA / "FOON.txt"), "--kitchen", str(DATA / "kitchen.json"),
            "--motions", str(DATA / "motion.txt"), "--utensils", str(DATA / "utensils.txt")]  # fmt: skip


@pytest.mark.parametrize("method", ["ids", "optimal-success", "bfs"])
def test_plan_json_for_the_25_course_goals_validates(
    course: Course, method: str, capsys: Capture
) -> None:
    code, out, err = run(["plan", *course_args(), "--goals", str(DATA / "goal_nodes_25.json"),
                          "--method", method, "--format", "json", "--quiet"], capsys)  # fmt: skip
    assert "Traceback" not in err
    trees = json.loads(out)
    validate(trees, "task_trees")
    assert out.startswith('[\n  {\n    "goal": {\n      ')  # 2-space indentation
    assert len(trees) == 25 and code == (0 if all(t["solved"] for t in trees) else 1)
    kitchen = set(course.kitchen)
    for t, goal in zip(trees, course.goals25, strict=True):
        assert foon.Object.from_dict(t["goal"]) == goal
        assert t["fu_count"] == len(t["units"]) == len(t["functional_units"])
        # The units are written out as the FOON has them: together they load as a FOON.
        units = [json.loads(course.foon.write("json", units=[u]))[0] for u in t["units"]]
        assert t["functional_units"] == units
        leaves = [foon.Object.from_dict(o) for o in t["leaves"]]
        assert all(o in kitchen for o in leaves)
        assert len(set(leaves)) == len(leaves) <= t["leaf_inputs"] or not t["solved"]
        motions = [course.foon.fu(u).motion for u in t["units"]]
        assert t["rates"] == [course.motions.get(m) for m in motions]
        assert t["source"] == str(DATA / "FOON.txt")
        if t["functional_units"]:
            sub = quiet_text(json.dumps(t["functional_units"]))
            assert sub.fu_count == len(set(t["units"]))


def test_tree_json_single_and_streamed(course: Course) -> None:
    p = course.foon.planner(course.kitchen, motions=course.motions, utensils=course.utensils)
    trees = p.plan_many(course.goals5, "greedy-success")
    one = trees[0].to_json()
    validate(json.loads(one), "task_tree")
    assert json.loads(one) == trees[0].to_dict()
    assert json.loads(trees[0].to_json(indent=None)) == trees[0].to_dict()
    w = _foon.TreeWriter("json", True)
    parts = [w.begin()]
    for t in trees:
        item = w.tree(p._native, t._plan)
        assert item  # written as it comes, not kept for the end
        parts.append(item)
    parts.append(w.failed(("truffle", [], [], None), True, "ids", "The goal node does not exist"))
    parts.append(w.failed(("truffle", ["sliced"], [], None), False, "ids", "not found"))
    parts.append(w.end())
    doc = json.loads(b"".join(parts))
    validate(doc, "task_trees")
    assert [d["goal"] for d in doc[-2:]] == [
        {"label": "truffle"},
        {"label": "truffle", "states": ["sliced"], "ingredients": [], "container": None},
    ]
    assert all(d["solved"] is False for d in doc[-2:])
    assert doc[: len(trees)] == [t.to_dict() for t in trees]
    empty = _foon.TreeWriter("json", True)
    assert json.loads(empty.begin() + empty.end()) == []
    single = _foon.TreeWriter("json", False)
    single.begin()
    single.tree(p._native, trees[0]._plan)
    with pytest.raises(ValueError, match="holds one task tree"):
        single.tree(p._native, trees[1]._plan)


def test_unsolved_and_unrated_trees_validate(course: Course) -> None:
    empty = course.foon.plan(course.goals5[0], foon.Kitchen(), "ids")
    d = empty.to_dict()
    validate(d, "task_tree")
    assert not d["solved"] and d["explanation"] and d["rates"] is None
    course_tree = course.foon.plan(course.goals5[0], course.kitchen, "bfs",
                                   utensils=course.utensils)  # fmt: skip
    d = course_tree.to_dict()
    validate(d, "task_tree")
    assert d["rates"] is None and d["success"] is None


# --- the other documents -----------------------------------------------------------------------


def test_kitchen_and_goal_json_validate(course: Course) -> None:
    text = course.kitchen.to_json()
    validate(json.loads(text), "kitchen")
    assert foon.Kitchen.from_text(text) == course.kitchen
    validate(json.loads((DATA / "goal_nodes_25.json").read_text()), "goals")
    validate(course.goals5[0].to_dict(), "goals")
    assert json.loads(foon.Kitchen().to_json()) == []


def test_comparison_json_validates(course: Course, capsys: Capture) -> None:
    p = course.foon.planner(course.kitchen, motions=course.motions, utensils=course.utensils)
    rows: list[Any] = [(m, t._plan) for m in ("ids", "optimal-success")
                       for t in p.plan_many(course.goals5, m)]  # fmt: skip
    rows.append(("ids", "truffle", "The goal node does not exist: truffle"))
    doc = json.loads(_foon.write_comparison(course.foon._native, rows, "json"))
    validate(doc, "comparison")
    assert [s["goals"] for s in doc["summary"]] == [6, 5]
    _code, out, _err = run(["compare", *course_args(), "--goals", str(DATA / "goal_nodes.json"),
                          "--methods", "ids,bfs", "--json"], capsys)  # fmt: skip
    validate(json.loads(out), "comparison")


def test_verify_json_validates(course: Course, tmp_path: Path, capsys: Capture) -> None:
    tree = course.foon.plan(course.goals5[2], course.kitchen, "ids", utensils=course.utensils)
    good = tmp_path / "tree.txt"
    good.write_text(tree.to_text())
    goal = json.dumps(course.goals5[2].to_dict())
    args = ["verify", "--foon", str(DATA / "FOON.txt"), "--kitchen", str(DATA / "kitchen.json"),
            "--utensils", str(DATA / "utensils.txt"), "--goal", goal]  # fmt: skip
    code, out, _err = run([*args, str(good), "--json"], capsys)
    report = json.loads(out)
    validate(report, "verify")
    assert code == 0 and report["valid"] and report["units"] == len(tree.units)
    # The tree as JSON verifies too (a JSON FOON is a tree file like any other).
    as_json = tmp_path / "tree.json"
    as_json.write_text(json.dumps(tree.to_dict()["functional_units"]))
    code, out2, _err = run([*args, str(as_json), "--json"], capsys)
    assert code == 0 and json.loads(out2)["valid"]
    # A tree that cannot run: its units in reverse order.
    assert len(tree.units) > 1
    bad = tmp_path / "bad.txt"
    bad.write_text(course.foon._native.tree_text(tree.units[::-1]))
    code, out, _err = run([*args, str(bad), "--json"], capsys)
    report = json.loads(out)
    validate(report, "verify")
    assert code == 1 and not report["valid"]
    assert report["blocked"] is not None or not report["goal_made"]


def test_check_and_stats_json_validate(course: Course, capsys: Capture) -> None:
    files = [str(DATA / "FOON.txt"), str(DATA / "subgraphs_sakib_JSON" / "0001-whipped_cream.json"),
             str(DATA / "subgraphs_sakib_TXT" / "0001-whipped_cream.txt")]  # fmt: skip
    _code, out, _err = run(["check", *files, "--json"], capsys)
    found = json.loads(out)
    validate(found, "check")
    want = [
        {
            "path": f.path,
            "line": f.line,
            "column": f.column,
            "severity": f.severity,
            "code": f.code,
            "message": f.message,
        }
        for f in foon.check(files)
    ]
    assert found == want
    _code, out, _err = run(["stats", *files, "--json"], capsys)
    rows = json.loads(out)
    validate(rows, "stats")
    assert [r["file"] for r in rows] == files
    assert rows[0] == {"file": files[0], **course.foon.stats()}


# --- optimal-shared's figures and hierarchy levels in task trees ------------------------------


def test_optimal_shared_trees_carry_bound_proven_gap_and_objective(
    course: Course, capsys: Capture
) -> None:
    goals = str(DATA / "goal_nodes.json")
    p = course.foon.planner(course.kitchen, motions=course.motions, utensils=course.utensils)
    for extra, kw in [
        ([], {}),
        (["--node-limit", "3"], {"node_limit": 3}),
        (
            ["--objective", "success", "--node-limit", "50"],
            {"objective": "success", "node_limit": 50},
        ),
    ]:
        code, out, err = run(["plan", *course_args(), "--goals", goals, "--method", "optimal-shared",
                              *extra, "--format", "json", "--quiet"], capsys)  # fmt: skip
        assert "Traceback" not in err, err
        trees = json.loads(out)
        validate(trees, "task_trees")
        assert code == (0 if all(t["solved"] for t in trees) else 1)
        objective = kw.get("objective", "units")
        native = p.plan_many(course.goals5, "optimal-shared", **kw)  # type: ignore[arg-type]
        for t, tree in zip(trees, native, strict=True):
            assert t["method"] == "optimal-shared" and t["objective"] == objective
            assert t["level"] == 3
            want = tree.to_dict()
            assert tree.objective == objective
            assert {k: t[k] for k in ("cost", "bound", "proven", "gap", "objective", "units")} == {
                k: want[k] for k in ("cost", "bound", "proven", "gap", "objective", "units")
            }
            if not t["solved"]:  # no tree: no cost, so no bound either
                assert [t[k] for k in ("cost", "bound", "proven", "gap")] == [None] * 4
                continue
            assert isinstance(t["proven"], bool)
            cost, bound = t["cost"], t["bound"]
            assert t["gap"] == abs(cost - bound)
            # A lower bound on the unit count; an upper bound on the success.
            assert bound <= cost if objective == "units" else bound >= cost
            if t["proven"]:
                assert t["gap"] == 0
        if kw.get("node_limit") == 3:
            assert not all(t["proven"] for t in trees)  # the limit stopped some search
    # Pickling keeps the objective.
    import pickle

    tree = p.plan(course.goals5[1], "optimal-shared", objective="success", node_limit=5)
    back = pickle.loads(pickle.dumps(tree))
    assert back.objective == "success" and back == tree
    # The other methods have none of these figures: null, always present.
    for method in ("ids", "optimal-units"):
        d = p.plan(course.goals5[1], method).to_dict()
        validate(d, "task_tree")
        assert [d[k] for k in ("bound", "proven", "gap", "objective")] == [None] * 4


@pytest.mark.parametrize("level", [1, 2, 3])
def test_plan_json_carries_the_identity_level(course: Course, level: int, capsys: Capture) -> None:
    args = ["plan", *course_args(), "--goals", str(DATA / "goal_nodes.json"), "--format", "json",
            "--quiet", "--method", "optimal-units"]  # fmt: skip
    if level != 3:
        args += ["--level", str(level)]
    _code, out, err = run(args, capsys)
    assert "Traceback" not in err, err
    trees = json.loads(out)
    validate(trees, "task_trees")
    assert [t["level"] for t in trees if "level" in t] == [level] * len(course.goals5)
    p = course.foon.planner(course.kitchen, motions=course.motions, utensils=course.utensils,
                            level=level)  # type: ignore[arg-type]  # fmt: skip
    for t, goal in zip(trees, course.goals5, strict=True):
        tree = p.plan(goal, "optimal-units")
        assert tree.level == level == tree.to_dict()["level"]
        assert t["units"] == tree.units
    # A tree planned without a planner of its own reports level 3.
    assert course.foon.plan(course.goals5[0], course.kitchen, "ids").to_dict()["level"] == 3
