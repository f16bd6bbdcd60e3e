"""The embedded example: the tree table of ``python/foon/data/README.md`` is what the planners
give, and the methods really differ on it (which is what the example is for)."""

from __future__ import annotations

from pathlib import Path

import foon
import pytest

README = Path(__file__).resolve().parents[1] / "python" / "foon" / "data" / "README.md"

#: The columns of the README's "Trees" table: (method, compat).
COLUMNS = (
    ("bfs", "course"),
    ("greedy-success", "course"),
    ("greedy-inputs", "course"),
    ("greedy-success", None),
    ("greedy-inputs", None),
    ("ids", None),
)


def tree_table() -> dict[int, list[str]]:
    """Goal number -> the six cells of the README's "Trees" table."""
    lines = README.read_text(encoding="utf-8").splitlines()
    start = next(
        i for i, line in enumerate(lines) if line.startswith("Trees (FUs in output order)")
    )
    rows: dict[int, list[str]] = {}
    for line in lines[start + 1 :]:
        if rows and not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells and cells[0].isdigit():
            rows[int(cells[0])] = cells[1:]
    return rows


def test_the_readme_tree_table_is_what_the_planners_give() -> None:
    ex = foon.example()
    rows = tree_table()
    assert sorted(rows) == list(range(len(ex.goals))) == [0, 1, 2, 3, 4, 5]
    for number, cells in rows.items():
        assert len(cells) == len(COLUMNS), number
        previous = ""
        for (method, compat), cell in zip(COLUMNS, cells, strict=True):
            if cell == "same":
                cell = previous
            previous = cell
            tree = ex.foon.plan(ex.goals[number], ex.kitchen, method, compat=compat,  # type: ignore[arg-type]
                                motions=ex.motions, utensils=ex.utensils)  # fmt: skip
            where = f"goal {number}, {method} {compat or 'sound'}: {cell!r}"
            if cell.startswith("fails"):
                assert not tree.solved, where
                assert tree.units == [] or compat == "course", where
                if ":" in cell:  # the missing or unresolved item is named
                    named = cell.split(":", 1)[1].strip().strip("`").split("`")[0]
                    blocked = tree.unresolved if compat else tree.missing
                    assert [o.label for o in blocked] == [named], where
                continue
            circular = cell.endswith("(circular)")
            units = [int(u) for u in cell.removesuffix("(circular)").split()]
            assert tree.solved, where
            assert tree.units == units, where
            # A circular course tree reaches its leaves but cannot be carried out.
            assert tree.is_valid() == (not circular), where


def test_methods_differ_on_the_default_goal() -> None:
    ex = foon.example()
    trees = {
        (m, c): tuple(ex.foon.plan(ex.goals[0], ex.kitchen, m, compat=c,  # type: ignore[arg-type]
                                   motions=ex.motions, utensils=ex.utensils).units)
        for m, c in COLUMNS
    }  # fmt: skip
    assert len(set(trees.values())) >= 3, trees
    course = {trees[(m, "course")] for m in ("bfs", "greedy-success", "greedy-inputs")}
    assert len(course) == 3  # the three course methods take three different producers


@pytest.mark.parametrize("number", [0, 3])
def test_the_course_bfs_tree_is_circular_and_the_sound_one_is_not(number: int) -> None:
    ex = foon.example()
    goal = ex.goals[number]
    course = ex.foon.plan(goal, ex.kitchen, "bfs", motions=ex.motions, utensils=ex.utensils)
    sound = ex.foon.plan(goal, ex.kitchen, "ids", motions=ex.motions, utensils=ex.utensils)
    assert course.solved and not course.is_valid() and course.height is None
    assert sound.solved and sound.is_valid() and sound.height is not None
