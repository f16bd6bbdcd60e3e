"""Checks of the pure-Python reference (tests/foon_reference.py) itself.

Two kinds of tests:
- small hand-written inputs for the parser and writer rules (always run);
- the real data in ../shared/data (course FOON.txt, kitchen, goals, golden course outputs, the
  lab's files); these are skipped, with a reason, when ../shared is missing.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import foon_reference as ref
import pytest

SHARED = Path(__file__).resolve().parents[1].parent / "shared"
DATA = SHARED / "data" / "foon"
GOLDEN = SHARED / "data" / "golden-course"

COURSE_METHODS = ("bfs", "greedy-success", "greedy-inputs")
SOUND_METHODS = ("ids", "greedy-success", "greedy-inputs")
UNSOLVABLE = ("whipped cream", "fried rice")


def _read(path: Path) -> str:
    return path.read_text(encoding="utf-8")


def _need_shared() -> None:
    if not SHARED.is_dir():
        pytest.skip(f"shared data directory not found: {SHARED}")


@dataclass
class Course:
    foon: ref.RefFoon
    kitchen: list[ref.Identity]
    k: set[int]
    utensils: set[str]
    rates: dict[str, float]
    goals5: list[ref.Identity]
    goals25: list[ref.Identity]
    rank: dict[int, int]


@pytest.fixture(scope="module")
def course() -> Course:
    _need_shared()
    foon = ref.parse(_read(DATA / "FOON.txt"))
    kitchen = ref.read_kitchen_json(_read(DATA / "kitchen.json"))
    utensils = ref.read_utensils(_read(DATA / "utensils.txt"))
    k = ref.kitchen_ids(foon, kitchen)
    return Course(
        foon=foon,
        kitchen=kitchen,
        k=k,
        utensils=utensils,
        rates=ref.read_rates(_read(DATA / "motion.txt")),
        goals5=ref.read_goals_json(_read(DATA / "goal_nodes.json")),
        goals25=ref.read_goals_json(_read(DATA / "goal_nodes_25.json")),
        rank=ref.ranks(foon, k, utensils),
    )


def _goal_id(c: Course, goal: ref.Identity) -> int:
    goal_id = c.foon.object_id(goal)
    assert goal_id is not None, goal
    return goal_id


def _executable_in_order(
    foon: ref.RefFoon, units: list[int], goal_id: int, k: set[int], utensils: set[str]
) -> bool:
    """The tree works in its own order: each FU's needed inputs exist when it runs."""
    have = set(k)
    for f in units:
        if not all(x in have for x in ref.needed_inputs(foon, f, utensils)):
            return False
        have.update(foon.fu_produced(f))
    return goal_id in have


# --------------------------------------------------------------------------------------------
# Parser and writer rules on small inputs
# --------------------------------------------------------------------------------------------

SMALL = (
    "# comment\r\n"
    "//\r\n"
    "O12\tOnion \t1\r\n"
    "S3\tWhole\r\n"
    "O\tknife\r\n"
    "   \r\n"
    "M7\tChop\t<1:10,1:11>\r\n"
    "O\tonion\r\n"
    "S\tsliced\r\n"
    "S\toff\t\r\n"
    "S\tin\t[cutting board] \r\n"
    "O\tbowl\r\n"
    "S\tcontains\t{jelly, peanut butter}\r\n"
    "O\tknife\r\n"
    "//\r\n"
)


def test_small_file_dialects_and_normalisation() -> None:
    foon = ref.parse(SMALL)
    assert foon.warnings == []
    assert len(foon.fus) == 1
    fu = foon.fus[0]
    assert fu.motion == "chop"
    assert [o.label for o in fu.inputs] == ["onion", "knife"]
    assert fu.inputs[0].states == ["whole"]
    onion = fu.outputs[0]
    assert onion.states == ["sliced", "off"]
    assert onion.container == "cutting board"
    assert fu.outputs[1].ingredients == ["jelly", " peanut butter"]
    assert foon.objects == [
        ("onion", ("whole",), (), None),
        ("knife", (), (), None),
        ("onion", ("off", "sliced"), (), "cutting board"),
        ("bowl", (), (" peanut butter", "jelly"), None),
    ]
    # The bare knife output is not produced; the others are.
    assert foon.producers(1) == []
    assert foon.producers(2) == [0]
    assert foon.fu_outputs(0) == [2, 3, 1]
    assert fu_text_lines(fu) == [
        "O\tonion", "S\twhole", "O\tknife", "M\tchop",
        "O\tonion", "S\tsliced", "S\toff", "S\tin\t[cutting board]",
        "O\tbowl", "S\tcontains\t{jelly, peanut butter}", "O\tknife", "//",
    ]  # fmt: skip


def fu_text_lines(fu: ref.RefFU) -> list[str]:
    text = ref.fu_text(fu)
    assert text.endswith("//") and not text.endswith("\n")
    return text.split("\n")


def test_empty_braces_give_one_empty_ingredient() -> None:
    foon = ref.parse("O\tbowl\nS\tcontains\t{}\nM\tmix\nO\tbowl\nS\tmixed\n//\n")
    assert foon.fus[0].inputs[0].ingredients == [""]
    assert ref.fu_text(foon.fus[0]).split("\n")[1] == "S\tcontains\t{}"


@pytest.mark.parametrize(
    ("text", "line", "column"),
    [
        ("//\nX\tfoo\n//\n", 2, 1),  # unknown line kind
        ("O foo\n", 1, 1),  # no TAB after the kind
        ("O\t\n", 1, 3),  # missing label (trailing empty field dropped)
        ("O12\t  \t0\n", 1, 5),  # label that is empty after rstrip
        ("O\ta\nS\tin\tbowl\n", 2, 6),  # third field neither {..} nor [..]
        ("O\ta\nS\tin\t[bowl\n", 2, 6),  # unbalanced bracket
        ("O\ta\nS\tin\t{a}b}\n", 2, 6),  # unbalanced brace
        ("S\tempty\nO\ta\n", 1, 1),  # S before any O
        ("O\ta\n//\nS\tempty\n", 3, 1),  # S before any O of this FU
        ("O\ta\nM\t\t<1:00,1:02>\n", 2, 3),  # missing motion
        ("O\ta\nS\tin\t \n", 2, 6),  # third field empty after rstrip
        ("# x\x00y\n", 1, 4),  # NUL byte, even in a comment
    ],
)
def test_parse_errors(text: str, line: int, column: int) -> None:
    with pytest.raises(ref.RefParseError) as info:
        ref.parse(text)
    assert (info.value.line, info.value.column) == (line, column)


def test_warnings_and_strict_mode() -> None:
    text = (
        "//\n"
        "O\ta\nS\tx\nO\tb\nS\ty\n//\n"  # lines 2-6: no M line, warning at line 6
        "O\ta\nM\tm\nO\tb\nS\ty\nM\tn\nO\tc\nS\tz\n//\n"  # lines 7-14: second M at line 11
        "//\n"  # an empty block: ignored silently
        "O\ta\nM\tm\nO\tc\nS\tz\n"  # lines 16-19: unterminated, kept, warning at 19
    )
    foon = ref.parse(text)
    assert foon.warnings == [(6, "no-motion"), (11, "two-motions"), (19, "unterminated")]
    assert len(foon.fus) == 1 and foon.fus[0].motion == "m"
    with pytest.raises(ref.RefParseError) as info:
        ref.parse(text, strict=True)
    assert (info.value.line, info.value.column) == (6, 1)


def test_unterminated_block_without_motion() -> None:
    foon = ref.parse("O\ta\nM\tm\nO\tb\nS\tx\n//\nO\tc\nS\ty\n\n")
    assert foon.warnings == [(7, "no-motion")]
    assert len(foon.fus) == 1


def test_duplicate_fus_are_dropped() -> None:
    one = "O\ta\nS\tp\nS\tq\nO\tb\nM\tm\nO\tc\nS\tr\n//\n"
    same = "O\tb\nO\ta\nS\tq\nS\tp\nM\tm\nO\tc\nS\tr\n//\n"  # same multisets, other order
    other = "O\ta\nS\tp\nS\tq\nO\tb\nO\tb\nM\tm\nO\tc\nS\tr\n//\n"  # b twice: different
    foon = ref.parse(one + same + other)
    assert len(foon.fus) == 2
    assert [o.label for o in foon.fus[0].inputs] == ["a", "b"]  # the first copy is kept
    assert foon.fu_inputs(1) == [0, 1, 1]


def test_container_rule_and_course_loop() -> None:
    text = (
        "O\tbowl\nS\tcontains\t{onion}\nO\tonion\nS\tin\t[bowl]\nM\tmix\n"
        "O\tbowl\nS\tmixed\n//\n"  # FU 0: the bowl holding {onion} is the onion in [bowl]
        "O\tonion\nS\twhole\nM\tcut\nO\tonion\nS\tin\t[bowl]\n//\n"  # FU 1
    )
    foon = ref.parse(text)
    bowl_with_onion, onion_in_bowl, goal, whole_onion = 0, 1, 2, 3
    assert foon.objects[whole_onion] == ("onion", ("whole",), (), None)
    assert ref.needed_inputs(foon, 0, {"bowl"}) == [onion_in_bowl]
    assert ref.needed_inputs(foon, 0, set()) == [bowl_with_onion, onion_in_bowl]
    kitchen = [foon.objects[whole_onion]]
    goal_ident = foon.objects[goal]
    for method in ("bfs", "ids", "greedy-inputs"):
        for compat in (None, "course"):
            result = ref.plan(foon, goal_ident, kitchen, {"bowl"}, None, method, compat)
            assert result.solved and result.units == [1, 0] and result.height == 2
    # Without the utensil list the bowl with {onion} has no producer.
    course_result = ref.plan(foon, goal_ident, kitchen, set(), None, "bfs")
    assert not course_result.solved and course_result.unresolved == [bowl_with_onion]
    sound = ref.plan(foon, goal_ident, kitchen, set(), None, "ids")
    assert not sound.solved and sound.unresolved == [bowl_with_onion]
    assert ref.explain(foon, goal, {whole_onion}, set()) == ([bowl_with_onion], [])


def test_missing_rate_is_a_key_error_naming_the_motion() -> None:
    foon = ref.parse("O\ta\nM\tstir\nO\tb\nS\tx\n//\n")
    goal = foon.objects[1]
    kitchen = [foon.objects[0]]
    for compat in (None, "course"):
        with pytest.raises(KeyError, match="stir"):
            ref.plan(foon, goal, kitchen, set(), {"mix": 0.5}, "greedy-success", compat)
    assert ref.plan(foon, goal, kitchen, set(), {"stir": 0.5}, "greedy-success").solved


def test_readers() -> None:
    item = '{"label": "a", "states": ["z", "y"], "ingredients": ["q", "p"], "container": null}'
    assert ref.read_kitchen_json("[" + item + "]") == [("a", ("y", "z"), ("p", "q"), None)]
    assert ref.read_goals_json(item) == [("a", ("y", "z"), ("p", "q"), None)]
    assert ref.read_rates("chop\t0.10\n\npour\t0.9\n") == {"chop": 0.1, "pour": 0.9}
    assert ref.read_utensils("cup \n\nbowl\r\npot") == {"cup", "bowl", "pot"}


# --------------------------------------------------------------------------------------------
# Real data
# --------------------------------------------------------------------------------------------


def test_course_foon_counts(course: Course) -> None:
    foon = course.foon
    assert foon.warnings == []
    assert len(foon.fus) == 2376
    assert len(foon.objects) == 4305
    produced = [o for o in range(len(foon.objects)) if len(foon.producers(o)) > 0]
    assert len(produced) == 3371
    assert len({fu.motion for fu in foon.fus}) == 129
    assert len(course.goals5) == 5 and len(course.goals25) == 25


def test_course_foon_round_trips_through_the_writer(course: Course) -> None:
    foon = course.foon
    again = ref.parse(ref.course_file(foon, list(range(len(foon.fus)))))
    assert again.fus == foon.fus
    assert again.objects == foon.objects


@pytest.mark.parametrize("method", COURSE_METHODS)
def test_golden_course_files(course: Course, method: str) -> None:
    for goal in course.goals5:
        result = ref.plan(
            course.foon, goal, course.kitchen, course.utensils, course.rates, method,
            compat="course", count="nodes",
        )  # fmt: skip
        assert result.solved, goal
        expected = (GOLDEN / method / (goal[0].replace(" ", "_") + ".txt")).read_bytes()
        actual = ref.course_file(course.foon, result.units).encode("utf-8")
        assert actual == expected, f"{method} {goal[0]}"


@pytest.mark.parametrize("method", SOUND_METHODS)
def test_sound_results_on_25_goals(course: Course, method: str) -> None:
    foon = course.foon
    for goal in course.goals25:
        goal_id = _goal_id(course, goal)
        result = ref.plan(foon, goal, course.kitchen, course.utensils, course.rates, method)
        if goal[0] in UNSOLVABLE:
            assert not result.solved and result.units == [] and result.height is None
            assert len(result.unresolved) > 0
            continue
        assert result.solved, goal[0]
        assert ref.is_valid(foon, result.units, goal_id, course.k, course.utensils), goal[0]
        assert _executable_in_order(foon, result.units, goal_id, course.k, course.utensils)
        assert goal_id in foon.fu_produced(result.units[-1])  # the goal's FU is last
        assert len(set(result.units)) == len(result.units)
        rank = course.rank[goal_id]
        assert result.height is not None and result.height >= rank
        if method == "ids":
            assert result.height == rank, goal[0]


@pytest.mark.parametrize("name", UNSOLVABLE)
def test_unsolvable_goals_fail_soundly_and_succeed_with_course_compat(
    course: Course, name: str
) -> None:
    foon = course.foon
    goal = next(g for g in course.goals25 if g[0] == name)
    goal_id = _goal_id(course, goal)
    assert goal_id not in ref.derivable(foon, course.k, course.utensils)

    missing, cycle = ref.explain(foon, goal_id, course.k, course.utensils)
    assert len(missing) + len(cycle) > 0
    assert missing == sorted(missing)
    # Each cycle object's first producer needs the next cycle object.
    for i, o in enumerate(cycle):
        following = cycle[(i + 1) % len(cycle)]
        assert following in ref.needed_inputs(foon, foon.producers(o)[0], course.utensils)

    for method in SOUND_METHODS:
        result = ref.plan(foon, goal, course.kitchen, course.utensils, course.rates, method)
        assert not result.solved
        assert result.unresolved == (missing if len(missing) > 0 else cycle)
    for method in ("bfs", "ids", "greedy-success", "greedy-inputs"):
        result = ref.plan(
            foon, goal, course.kitchen, course.utensils, course.rates, method, compat="course"
        )
        assert result.solved and len(result.units) > 0, method
        # The course tree relies on a circular step, so it is not valid.
        assert not ref.is_valid(foon, result.units, goal_id, course.k, course.utensils)
        assert result.height is None


def test_lab_file_warnings() -> None:
    _need_shared()
    (no_motion,) = (DATA / "subgraphs_sakib_TXT").glob("0083-*.txt")
    (two_motions,) = (DATA / "subgraphs_sakib_TXT").glob("0032-*.txt")
    assert (500, "no-motion") in ref.parse(_read(no_motion)).warnings
    assert (114, "two-motions") in ref.parse(_read(two_motions)).warnings
    with pytest.raises(ref.RefParseError) as info:
        ref.parse(_read(no_motion), strict=True)
    assert (info.value.line, info.value.column, info.value.reason) == (500, 1, "no-motion")
    with pytest.raises(ref.RefParseError) as info:
        ref.parse(_read(two_motions), strict=True)
    assert (info.value.line, info.value.column, info.value.reason) == (114, 1, "two-motions")


def test_every_real_subgraph_file_loads() -> None:
    _need_shared()
    paths = sorted(DATA.glob("subgraphs_*/*.txt"))
    assert len(paths) > 200
    for path in paths:
        foon = ref.parse(_read(path))
        assert len(foon.fus) > 0, path.name


_SOURCES_ROW = re.compile(
    r"^\| (lab_history/\S*FOON\S+\.txt) \|.*?\| (\d+) FU blocks \((\d+) unique\), "
    r"(\d+) distinct objects, (\d+) motion labels \|"
)


def test_lab_history_counts_match_sources_md() -> None:
    _need_shared()
    rows = [_SOURCES_ROW.match(line) for line in _read(DATA / "SOURCES.md").splitlines()]
    expected = [m.groups() for m in rows if m is not None]
    assert len(expected) >= 10
    for name, _blocks, unique, objects, motions in expected:
        foon = ref.parse(_read(DATA / name))
        assert foon.warnings == [], name
        assert len(foon.fus) == int(unique), name
        assert len(foon.objects) == int(objects), name
        assert len({fu.motion for fu in foon.fus}) == int(motions), name
