"""The course-compatible methods reproduce the course output files byte for byte, through the
Python API and through the command line."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import DATA, GOLDEN, Course, golden_name, need_shared
from foon.cli import main

CASES = [("bfs", "bfs"), ("greedy-success", "greedy-success"), ("greedy-inputs", "greedy-inputs")]


@pytest.mark.parametrize(("folder", "method"), CASES)
def test_api_matches_golden(course: Course, folder: str, method: str) -> None:
    for goal in course.goals5:
        tree = course.foon.plan(
            goal,
            course.kitchen,
            method,
            compat="course",
            motions=course.motions,
            utensils=course.utensils,
        )
        assert tree.solved
        want = (GOLDEN / folder / golden_name(goal.label)).read_text(encoding="utf-8")
        assert tree.to_text() == want


def test_course_ids_is_the_bfs_tree(course: Course) -> None:
    for goal in course.goals5:
        kw = {"compat": "course", "motions": course.motions, "utensils": course.utensils}
        ids = course.foon.plan(goal, course.kitchen, "ids", **kw)  # type: ignore[arg-type]
        bfs = course.foon.plan(goal, course.kitchen, "bfs", **kw)  # type: ignore[arg-type]
        assert ids.units == bfs.units


@pytest.mark.parametrize(("folder", "method"), CASES)
def test_cli_out_dir_matches_golden(
    tmp_path: Path, folder: str, method: str, capsys: pytest.CaptureFixture[str]
) -> None:
    need_shared()
    out = tmp_path / "out"
    argv = [
        "plan",
        "--foon",
        str(DATA / "FOON.txt"),
        "--kitchen",
        str(DATA / "kitchen.json"),
        "--motions",
        str(DATA / "motion.txt"),
        "--utensils",
        str(DATA / "utensils.txt"),
        "--goals",
        str(DATA / "goal_nodes.json"),
        "--method",
        method,
        "--out",
        str(out),
    ]
    if method != "bfs":
        argv += ["--compat", "course"]
    assert main(argv) == 0
    written = sorted(p.name for p in out.iterdir())
    assert written == sorted(p.name for p in (GOLDEN / folder).iterdir())
    for name in written:
        assert (out / name).read_bytes() == (GOLDEN / folder / name).read_bytes(), name
    err = capsys.readouterr().err
    assert err.count("\n") == 5  # one summary line per goal


def test_greedy_inputs_counting_ingredients_differs_somewhere(course: Course) -> None:
    """--count ingredients is a different heuristic: on the 25 goals it changes some tree."""
    diffs = 0
    for goal in course.goals25:
        kw = {"compat": "course", "motions": course.motions, "utensils": course.utensils}
        a = course.foon.plan(goal, course.kitchen, "greedy-inputs", count="nodes", **kw)  # type: ignore[arg-type]
        b = course.foon.plan(goal, course.kitchen, "greedy-inputs", count="ingredients", **kw)  # type: ignore[arg-type]
        diffs += a.units != b.units
    assert diffs > 0
