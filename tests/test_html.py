"""The HTML page (task trees and comparisons), checked in a real browser, and the
comparison's text table and CSV written by the core.

The browser tests open each page in headless Chromium: the page's own script counts the
drawn motion and object nodes (and the chart's bars) once it has loaded and writes the counts
into ``data-`` attributes, which the test reads from ``--dump-dom`` and compares with the
tree's units and objects; a screenshot must show the picture's red motions, green objects and
purple goal. They skip when Chromium or Graphviz's ``dot`` is missing, and fail instead when
the ``CI`` environment variable is set (CI installs both).
"""

from __future__ import annotations

import csv
import io
import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Iterator, Sequence
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import foon
import pytest
from conftest import Course
from foon import _foon
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

# --------------------------------------------------------------------------------------------
# Tools
# --------------------------------------------------------------------------------------------


def need_tool(*names: str) -> str:
    """The first of ``names`` on PATH; skips without one (fails when CI is set)."""
    for n in names:
        path = shutil.which(n)
        if path:
            return path
    why = f"{' / '.join(names)} is not installed (Debian: apt-get install graphviz chromium)"
    if os.environ.get("CI"):
        pytest.fail(f"CI is set but {why}")
    pytest.skip(why)


def need_dot() -> None:
    need_tool(os.environ.get("FOON_DOT") or "dot")


def need_pillow() -> Any:
    try:
        from PIL import Image
    except ImportError:
        if os.environ.get("CI"):
            pytest.fail("CI is set but pillow is not installed (pip install pillow)")
        pytest.skip("pillow is not installed (pip install pillow)")
    return Image


def chromium(page: Path, *args: str) -> bytes:
    """Runs headless Chromium on ``page`` with a fresh profile; returns its standard output."""
    exe = need_tool("chromium", "chromium-browser", "google-chrome")
    with tempfile.TemporaryDirectory(prefix="foon-chromium-") as profile:
        cmd = [
            exe,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-extensions",
            "--no-first-run",
            "--hide-scrollbars",
            f"--user-data-dir={profile}",
            *args,
            page.as_uri(),
        ]
        r = subprocess.run(cmd, capture_output=True, timeout=240, check=False)
    assert r.returncode == 0, r.stderr.decode(errors="replace")[-2000:]
    return r.stdout


class Attrs(HTMLParser):
    """The attributes of ``<body>``, of each ``section`` and of each ``svg.chart``."""

    def __init__(self) -> None:
        super().__init__()
        self.body: dict[str, str] = {}
        self.sections: list[dict[str, str]] = []
        self.charts: list[dict[str, str]] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = {k: v or "" for k, v in attrs}
        if tag == "body":
            self.body = a
        elif tag == "section":
            self.sections.append(a)
        elif tag == "svg" and "chart" in a.get("class", "").split():
            self.charts.append(a)


def rendered(page: Path) -> Attrs:
    """The page's attributes after its script ran in the browser."""
    dom = chromium(page, "--virtual-time-budget=10000", "--dump-dom").decode()
    p = Attrs()
    p.feed(dom)
    assert p.body.get("data-rendered") == "yes", "the page's script did not run"
    return p


def picture_height(page_text: str) -> int:
    """A window height (px) that shows every inlined picture whole."""
    pts = [float(h) for h in re.findall(r'<svg width="[0-9.]+pt" height="([0-9.]+)pt"', page_text)]
    return min(15000, int(600 + sum(pts) * 4 / 3 + 700 * max(1, len(pts))))


def screenshot(page: Path, height: int) -> Any:
    Image = need_pillow()
    shot = page.with_suffix(".png")
    chromium(page, f"--window-size=1280,{height}", f"--screenshot={shot}")
    return Image.open(shot).convert("RGB")


def colours(img: Any) -> dict[str, int]:
    """How many clearly red, green and purple pixels the image has, and how many not white."""
    from PIL import ImageChops

    h, s, v = img.convert("HSV").split()
    strong = ImageChops.multiply(
        s.point(lambda x: 255 if x >= 60 else 0), v.point(lambda x: 255 if x >= 80 else 0)
    )

    def hue(*ranges: tuple[float, float]) -> int:
        def inside(x: int) -> int:
            deg = x * 360 / 255
            return 255 if any(lo <= deg <= hi for lo, hi in ranges) else 0

        return int(ImageChops.multiply(h.point(inside), strong).histogram()[255])

    ink = img.convert("L").point(lambda x: 255 if x < 235 else 0).histogram()[255]
    return {
        "red": hue((0, 15), (345, 360)),
        "green": hue((90, 150)),
        "purple": hue((260, 310)),
        "blue": hue((195, 215)),
        "ink": int(ink),
    }


# --------------------------------------------------------------------------------------------
# What a tree should show
# --------------------------------------------------------------------------------------------


def tree_objects(tree: foon.TaskTree) -> set[int]:
    """The distinct objects of a tree's picture: its units' inputs and outputs, and the goal."""
    out = {tree.goal_id}
    for fu in tree:
        out.update(fu.input_ids)
        out.update(fu.output_ids)
    return out


def planner(c: Course) -> foon.Planner:
    return c.foon.planner(c.kitchen, motions=c.motions, utensils=c.utensils)


def write_many(trees: Sequence[foon.TaskTree], failed: Sequence[tuple[foon.Object, str]]) -> str:
    w = _foon.TreeWriter("html", True)
    data = w.begin()
    for t in trees:
        data += w.tree(t._planner()._native, t._plan)
    for goal, error in failed:
        data += w.failed(goal._tuple(), False, "ids", error)
    data += w.end()
    return data.decode()


def check_page_structure(page: str, trees: Sequence[foon.TaskTree]) -> None:
    """Without a browser: one section per tree, as many motion and object nodes in each
    section's SVG as the tree has units and objects, and nothing fetched at view time."""
    sections = re.split(r'<section class="tree"', page)[1:]
    assert len(sections) == len(trees)
    for s, t in zip(sections, trees, strict=True):
        s = s.split("</section>")[0]
        assert len(re.findall(r'class="node motion[ "]', s)) == len(t.units)
        assert len(re.findall(r'class="node object[ "]', s)) == len(tree_objects(t))
        assert len(re.findall(r'class="node object [^"]*\bgoal\b', s)) == 1
        assert s.count("<li>") >= len(t.units)
    for fetch in ("<link", " src=", "@import", "url(", "href="):
        assert fetch not in page


# --------------------------------------------------------------------------------------------
# Task-tree pages in the browser
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["ids", "greedy-success", "optimal-units"])
def test_course_tree_pages_render_their_nodes(course: Course, method: str, tmp_path: Path) -> None:
    """Each of the 5 course goals (one of them unsolvable: its page shows the goal alone):
    the browser draws one motion node per unit and one object node per distinct object, all
    of them with a non-empty box."""
    need_dot()
    p = planner(course)
    for i, goal in enumerate(course.goals5):
        t = p.plan(goal, method)
        text = str(t.write("html"))
        check_page_structure(text, [t])
        page = tmp_path / f"tree{i}.html"
        page.write_text(text, encoding="utf-8")
        got = rendered(page)
        (section,) = got.sections
        assert section["data-motions"] == str(len(t.units)), (method, goal)
        assert section["data-motions-shown"] == str(len(t.units))
        assert section["data-objects"] == str(len(tree_objects(t))), (method, goal)
        assert section["data-objects-shown"] == section["data-objects"]
        assert got.body["data-motions"] == str(len(t.units))


def test_course_tree_screenshot_shows_the_visual_language(course: Course, tmp_path: Path) -> None:
    """The screenshot of a solved course tree has red (motions), green (objects) and purple
    (the goal) pixels."""
    need_dot()
    p = planner(course)
    trees = [t for t in (p.plan(g, "ids") for g in course.goals5) if t.units]
    assert len(trees) >= 3
    for i, t in enumerate(trees[:3]):
        text = str(t.write("html"))
        page = tmp_path / f"shot{i}.html"
        page.write_text(text, encoding="utf-8")
        c = colours(screenshot(page, picture_height(text)))
        assert c["red"] > 200 and c["green"] > 200 and c["purple"] > 200, (str(t.goal), c)


def test_a_page_of_many_trees(course: Course, tmp_path: Path) -> None:
    """The 25 course goals (and a goal that could not be planned) as one page: a section per
    goal, the failed goal with its error, and per section the right node counts."""
    need_dot()
    p = planner(course)
    trees = p.plan_many(course.goals25, "greedy-success")
    missing = foon.Object("unicorn <steak>", ("grilled",))
    text = write_many(trees, [(missing, "goal not found: unicorn & co")])
    check_page_structure(text, trees)
    assert "unicorn &lt;steak&gt;" in text and "unicorn &amp; co" in text
    assert "<steak>" not in text
    page = tmp_path / "many.html"
    page.write_text(text, encoding="utf-8")
    got = rendered(page)
    trees_sections = [s for s in got.sections if s.get("class") == "tree"]
    failed = [s for s in got.sections if s.get("class") == "failed"]
    assert len(trees_sections) == len(trees) and len(failed) == 1
    for s, t in zip(trees_sections, trees, strict=True):
        assert s["data-goal"] == str(t.goal)
        assert s["data-motions"] == s["data-motions-shown"] == str(len(t.units))
        assert s["data-objects"] == s["data-objects-shown"] == str(len(tree_objects(t)))
    assert got.body["data-motions"] == str(sum(len(t.units) for t in trees))
    # A screenshot of the first few trees of a page of several.
    few = [t for t in trees if t.units][:3]
    small = write_many(few, [])
    shot_page = tmp_path / "few.html"
    shot_page.write_text(small, encoding="utf-8")
    c = colours(screenshot(shot_page, picture_height(small)))
    assert c["red"] > 200 and c["green"] > 200 and c["purple"] > 200, c


# --------------------------------------------------------------------------------------------
# Comparison pages
# --------------------------------------------------------------------------------------------


def compare_rows(c: Course, goals: Sequence[foon.Object]) -> tuple[list[Any], list[dict[str, Any]]]:
    """What ``foon compare`` compares (every method, sound), as the writer's rows and as
    the CLI's row dicts, with one goal that is not in the FOON."""
    p = planner(c)
    missing = foon.Object("dragon fruit", ("sliced, thin",), (), 'bowl "big"')
    native: list[Any] = []
    dicts: list[dict[str, Any]] = []
    for m in foon.METHODS:
        for t in p.plan_many(goals, m):
            native.append((m, t._plan))
            dicts.append(
                {
                    "goal": str(t.goal),
                    "method": m,
                    "solved": t.solved,
                    "fu_count": t.fu_count if t.solved else None,
                    "height": t.height,
                    "success": t.success if t.solved else None,
                    "leaf_inputs": t.leaf_inputs if t.solved else None,
                    "expanded": t.expanded,
                    "peak_frontier": t.peak_frontier,
                    "seconds": t.seconds,
                    "error": None,
                    # The columns after the CLI's (level, optimal-shared's, the split's).
                    "level": 3,
                    "objective": t.objective,
                    "bound": t.bound if t.solved else None,
                    "proven": t.proven if t.solved else None,
                    "gap": t.gap if t.solved else None,
                    "max_human": None,
                    "split_success": None,
                    "fixed_tree_success": None,
                }
            )
        err = f"goal not found: {missing}"
        native.append((m, str(missing), err))
        dicts.append(
            dict.fromkeys(dicts[0])
            | {"goal": str(missing), "method": m, "solved": False}
            | {"error": err, "level": 3}
        )
    return native, dicts


def test_comparison_page_has_a_bar_per_method(course: Course, tmp_path: Path) -> None:
    """Every method over the 5 course goals: the summary and per-goal tables, and a chart per
    measure with one drawn bar per method that has a value (all of them for goals solved)."""
    native, dicts = compare_rows(course, course.goals5)
    text = _foon.write_comparison(course.foon._native, native, "html").decode()
    methods = list(foon.METHODS)
    for m in methods:
        assert f"<td>{m}</td>" in text
    assert text.count("<tr>") == 1 + len(methods) + 1 + len(dicts)
    page = tmp_path / "compare.html"
    page.write_text(text, encoding="utf-8")
    got = rendered(page)
    assert [c["data-measure"] for c in got.charts] == [
        "solved",
        "fu_count",
        "success",
        "peak_frontier",
    ]
    solved = {m for m in methods if any(r["solved"] for r in dicts if r["method"] == m)}
    for c in got.charts:
        want = len(methods) if c["data-measure"] in ("solved", "peak_frontier") else len(solved)
        assert c["data-bars"] == c["data-bars-shown"] == str(want), c
    assert got.body["data-bars"] == got.body["data-bars-shown"]
    img = screenshot(page, 1600)
    c = colours(img)
    assert c["ink"] > 0.01 * img.width * img.height, c
    # The first method's bars are blue (#1f77b4).
    assert colours(img)["blue"] > 100, c


def test_comparison_page_is_deterministic_and_escaped(course: Course) -> None:
    native, _ = compare_rows(course, course.goals5[:2])
    a = _foon.write_comparison(course.foon._native, native, "html", title="<b>A & B</b>")
    b = _foon.write_comparison(course.foon._native, native, "html", title="<b>A & B</b>")
    assert a == b
    text = a.decode()
    assert "<title>&lt;b&gt;A &amp; B&lt;/b&gt;</title>" in text
    assert "bowl &quot;big&quot;" in text and 'bowl "big"' not in text


# --------------------------------------------------------------------------------------------
# The comparison's text table and CSV: what `foon compare` printed before they moved to the
# core (python/foon/_cli_commands.py: _cell, _print_compare_table, the csv branch).
# --------------------------------------------------------------------------------------------


def _mean(vals: list[Any]) -> float | None:
    # Left to right, as the core sums (Python >= 3.12's sum() of floats is compensated).
    if not vals:
        return None
    total = 0.0
    for v in vals:
        total += v
    return total / len(vals)


def expected_summary(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    out = []
    for m in dict.fromkeys(r["method"] for r in rows):
        rs = [r for r in rows if r["method"] == m]
        planned = [r for r in rs if r["error"] is None]
        ok = [r for r in rs if r["solved"]]

        def mean(key: str, rows_: list[dict[str, Any]] = ok) -> float | None:
            return _mean([r[key] for r in rows_ if r[key] is not None])

        out.append(
            {
                "method": m,
                "solved_count": len(ok),
                "goals": len(rs),
                "fu_count": mean("fu_count"),
                "height": mean("height"),
                "success": mean("success"),
                "leaf_inputs": mean("leaf_inputs"),
                "expanded": mean("expanded", planned),
                "peak_frontier": mean("peak_frontier", planned),
                "seconds_total": sum_left(r["seconds"] for r in planned),
                "proven_count": sum(r["proven"] is True for r in rs)
                if any(r["objective"] is not None for r in rs)
                else None,
                "gap": mean("gap"),
                "split_success": None,
                "fixed_tree_success": None,
            }
        )
    return out


def sum_left(vals: Iterator[float]) -> float:
    total = 0.0
    for v in vals:
        total += v
    return total


def _cell(v: Any, kind: str = "") -> str:
    if v is None:
        return "-"
    if kind == "pct":
        return f"{100 * v:.2f}%"
    if kind == "ms":
        return f"{1000 * v:.3f}"
    if isinstance(v, float):
        return f"{v:.1f}"
    return str(v)


def _figure(v: float | None, objective: str | None) -> str:
    """optimal-shared's bound or gap: a success in percent, a whole count as an integer."""
    if v is not None and objective == "success":
        return _cell(v, "pct")
    if v is not None and v == int(v):
        return str(int(v))
    return _cell(v)


def expected_table(rows: list[dict[str, Any]], summary: list[dict[str, Any]]) -> str:
    out = io.StringIO()
    head = ["goal", "method", "units", "height", "success", "leaves", "expanded", "peak", "ms"]
    # optimal-shared's columns when it is compared (the level's are for levels other than 3,
    # the split's for --split: neither here).
    shared = any(r["objective"] is not None for r in rows)
    if shared:
        head += ["bound", "gap", "proven"]

    def cells(first: str, r: dict[str, Any], last: str) -> list[str]:
        metrics = [_cell(r["fu_count"]), _cell(r["height"]), _cell(r["success"], "pct")]
        search = [_cell(r["leaf_inputs"]), _cell(r["expanded"]), _cell(r["peak_frontier"])]
        return [first, r["method"], *metrics, *search, last]

    def proven(p: bool | None) -> str:
        return "-" if p is None else "yes" if p else "no"

    body = [
        cells(r["goal"][:48], r, "not found" if r["error"] else _cell(r["seconds"], "ms"))
        + (
            [
                _figure(r["bound"], r["objective"]),
                _figure(r["gap"], r["objective"]),
                proven(r["proven"]),
            ]
            if shared
            else []
        )
        for r in rows
    ]
    body += [
        cells(
            f"(all: {srow['solved_count']}/{srow['goals']} solved; means, total ms)",
            srow,
            _cell(srow["seconds_total"], "ms"),
        )
        + (
            [
                "-",
                _cell(srow["gap"]),
                "-"
                if srow["proven_count"] is None
                else f"{srow['proven_count']}/{srow['solved_count']}",
            ]
            if shared
            else []
        )
        for srow in summary
    ]
    widths = [max(len(x[i]) for x in [head, *body]) for i in range(len(head))]

    def fmt(cells: list[str]) -> str:
        return "  ".join(
            c.ljust(w) if i < 2 else c.rjust(w)
            for i, (c, w) in enumerate(zip(cells, widths, strict=True))
        )

    line = fmt(head)
    print(line, file=out)
    print("-" * len(line), file=out)
    for i, row in enumerate(body):
        if i == len(rows):
            print("-" * len(line), file=out)
        print(fmt(row), file=out)
    return out.getvalue()


def expected_csv(rows: list[dict[str, Any]], summary: list[dict[str, Any]]) -> str:
    out = io.StringIO(newline="")
    base = [*rows[0].keys()][:11]
    more = [*rows[0].keys()][11:]
    fields = [*base, "solved_count", "goals", "seconds_total", *more, "proven_count"]
    w = csv.DictWriter(out, fieldnames=fields)
    w.writeheader()
    w.writerows(rows)
    for srow in summary:
        w.writerow({"goal": "(all)", **srow})
    return out.getvalue()


@pytest.mark.parametrize("goals", ["goals5", "goals25"])
def test_comparison_text_and_csv_are_what_the_cli_printed(course: Course, goals: str) -> None:
    native, dicts = compare_rows(course, getattr(course, goals))
    summary = expected_summary(dicts)
    text = _foon.write_comparison(course.foon._native, native, "text").decode()
    assert text == expected_table(dicts, summary)
    got_csv = _foon.write_comparison(course.foon._native, native, "csv").decode()
    assert got_csv == expected_csv(dicts, summary)
    # And it reads back.
    back = list(csv.DictReader(io.StringIO(got_csv, newline="")))
    assert len(back) == len(dicts) + len(summary)
    assert back[-1]["goal"] == "(all)" and back[-1]["method"] == foon.METHODS[-1]


def test_an_empty_comparison() -> None:
    f = foon.Foon.from_text("O\tegg\nS\traw\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    assert _foon.write_comparison(f._native, [], "text") == b""
    head = _foon.write_comparison(f._native, [], "csv").decode()
    assert "seconds_total," in head and head.endswith("proven_count\r\n")
    assert head.count("\r\n") == 1
    page = _foon.write_comparison(f._native, [], "html").decode()
    assert "<svg" not in page and page.endswith("</html>\n")


def test_formats_that_cannot_write_a_comparison_say_which_can() -> None:
    f = foon.Foon.from_text("O\tegg\nS\traw\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    with pytest.raises(ValueError, match=r"cannot write a comparison \(choose from .*html"):
        _foon.write_comparison(f._native, [], "steps")


# --------------------------------------------------------------------------------------------
# Generated FOONs (no browser): structure, escaping, determinism, errors
# --------------------------------------------------------------------------------------------

NASTY = ("pan <hot>", "salt & pepper", 'the "big" pot', "chef's knife", "crème", "egg")
STATES = ("raw", "<b>chopped</b>", "a&b", "whole")


@st.composite
def chains(draw: st.DrawFn) -> tuple[str, list[foon.Object], foon.Object]:
    """A FOON of 1 to 8 units that turn kitchen items, step by step, into one goal: each unit
    takes the previous result and 0 to 2 more kitchen items, so every goal is solvable and
    its tree is the chain. Labels and states carry HTML's special characters."""
    n = draw(st.integers(1, 8))
    labels = draw(st.lists(st.sampled_from(NASTY), min_size=n + 1, max_size=n + 1))
    kitchen = [foon.Object(labels[0], ("raw",))]
    text: list[str] = []
    prev = kitchen[0]
    for i in range(n):
        pairs = st.tuples(st.sampled_from(NASTY), st.sampled_from(STATES))
        extra = [
            foon.Object(label, (f"{state} {i}",))
            for label, state in draw(st.lists(pairs, max_size=2, unique=True))
        ]
        kitchen += extra
        out = foon.Object(labels[i + 1], (f"step {i}", draw(st.sampled_from(STATES))))
        for o in (prev, *extra):
            text.append(f"O\t{o.label}")
            text += [f"S\t{s}" for s in o.states]
        text.append(f"M\t{draw(st.sampled_from(('mix <well>', 'chop', 'pour & stir')))}")
        text.append(f"O\t{out.label}")
        text += [f"S\t{s}" for s in out.states]
        text.append("//")
        prev = out
    return "\n".join(text) + "\n", kitchen, prev


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=chains(), many=st.booleans())
def test_generated_tree_pages(case: tuple[str, list[foon.Object], foon.Object], many: bool) -> None:
    """Every unit drawn, every object once, all text escaped, same bytes twice."""
    need_dot()
    text, kitchen, goal = case
    f = foon.Foon.from_text(text)
    t = f.plan(goal, kitchen, "ids")
    assert t.solved and t.units
    page = write_many([t, t], []) if many else str(t.write("html"))
    check_page_structure(page, [t, t] if many else [t])
    assert page == (write_many([t, t], []) if many else str(t.write("html")))
    for raw in ("<hot>", "<b>", "& pepper", '"big"', "<well>"):
        assert raw not in page
    p = Attrs()
    p.feed(page)
    assert [s["data-goal"] for s in p.sections] == [str(goal)] * (2 if many else 1)


def test_missing_dot_is_an_output_error_and_writes_nothing(
    course: Course, monkeypatch: pytest.MonkeyPatch
) -> None:
    t = planner(course).plan(course.goals5[2], "ids")
    monkeypatch.setenv("FOON_DOT", "/nonexistent/dot")
    with pytest.raises(foon.OutputError, match="not found: install Graphviz"):
        t.write("html")
    w = _foon.TreeWriter("html", True)
    assert w.begin() == b""
    with pytest.raises(foon.OutputError):
        w.tree(t._planner()._native, t._plan)


def test_a_tree_too_large_for_a_picture_is_refused(course: Course) -> None:
    need_dot()
    t = planner(course).plan(course.goals5[1], "ids")
    with pytest.raises(foon.OutputError, match="narrow it"):
        t.write("html", max_nodes=5)
