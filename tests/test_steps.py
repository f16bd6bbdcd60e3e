"""``--format steps``: numbered plain-English steps, in execution order.

Checked on the 25 course goals (one step per unit, numbered 1..n, each naming its motion
and the object it works on), on hand-checked units of the course FOON (the sentences below
were written from reading the data), and on generated FOONs with arbitrary labels and
motions. The coverage of the verb templates over the course FOON is measured by the core's
unit test (``write::steps`` in foon-core), which reads the same data.
"""

from __future__ import annotations

import re

import foon
import pytest
from conftest import Course
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

STEP = re.compile(r"^(\d+)\. (\S.*\.)$")


def words(s: str) -> set[str]:
    return set(re.findall(r"[a-z0-9]+", s.lower()))


def motion_words(motion: str) -> set[str]:
    """The words a step must say for its motion (`pick-and-place`: pick, place)."""
    return words(motion) - {"and"}


def check_lines(lines: list[str], n: int) -> None:
    assert len(lines) == n
    for i, line in enumerate(lines, 1):
        m = STEP.match(line)
        assert m, line
        assert int(m.group(1)) == i
        assert line == line.strip() and "  " not in line
        assert line.endswith(".")


@pytest.fixture(scope="module")
def planner(course: Course) -> foon.Planner:
    return course.foon.planner(course.kitchen, motions=course.motions, utensils=course.utensils)


def test_course_goals(course: Course, planner: foon.Planner) -> None:
    solved = 0
    for goal in course.goals25:
        tree = planner.plan(goal)
        lines = tree.steps()
        check_lines(lines, len(tree.units))
        solved += bool(tree.units)
        for line, fu in zip(lines, tree, strict=True):
            said = words(line)
            assert motion_words(fu.motion) <= said, (fu.motion, line)
            # The object worked on: an input that the unit changes (else any input).
            changed = [o for o in fu.inputs if o not in fu.outputs] or list(fu.inputs)
            assert any(words(o.label) <= said for o in changed), (fu.inputs, line)
        # Same input, same bytes.
        assert tree.write("steps") == planner.plan(goal).write("steps")
        assert tree.write("steps") == "".join(f"{x}\n" for x in lines)
    assert solved >= 20


def test_many_trees_have_a_goal_line_each(course: Course, planner: foon.Planner) -> None:
    trees = [planner.plan(g) for g in course.goals25[:4]]
    w = foon._foon.TreeWriter("steps", True)
    out = w.begin()
    for t in trees:
        out += w.tree(planner._native, t._plan)
    out += w.end()
    text = out.decode()
    assert text.count("# goal: ") == len(trees)
    body = [x for x in text.splitlines() if not x.startswith("# goal: ")]
    assert body == [x for t in trees for x in t.steps()]


def one_unit(course: Course, motion: str, inputs: list[str], outputs: list[str]) -> str:
    """The step of the course FU with this motion and exactly these inputs and outputs (as
    one-line object texts): the tree of one of its outputs from its inputs."""
    hits = []
    for i in range(course.foon.fu_count):
        fu = course.foon.fu(i)
        if (
            fu.motion == motion
            and sorted(map(str, fu.inputs)) == sorted(inputs)
            and sorted(map(str, fu.outputs)) == sorted(outputs)
        ):
            hits.append(fu)
    assert hits, (motion, inputs, outputs)
    fu = hits[0]
    goal = next(o for o in fu.outputs if o not in fu.inputs and (o.states or o.ingredients))
    tree = course.foon.plan(goal, list(fu.inputs))
    assert tree.units == [fu.index]
    lines = tree.steps()
    assert len(lines) == 1
    return lines[0]


# Each case: a unit of the course FOON (motion, inputs, outputs) and the sentence a cook
# would write for it.
HAND_CHECKED = [
    (
        "chop",
        ["onion (whole)", "knife"],
        ["onion (ring shaped)", "knife"],
        "1. Chop the whole onion with the knife.",
    ),
    (
        "slice",
        ["onion (whole, peeled) in [cutting board]", "knife"],
        ["onion (sliced) in [cutting board]"],
        "1. Slice the whole, peeled onion on the cutting board with the knife.",
    ),
    (
        "pour",
        ["pot (hot) {salt,water} in [stove]", "jar {macaroni}", "macaroni (raw) in [jar]"],
        ["pot (hot) {macaroni,salt,water} in [stove]", "macaroni (raw) in [pot]"],
        "1. Pour the raw macaroni from the jar into the hot pot of salt and water.",
    ),
    (
        "pick-and-place",
        ["cutting board (empty)", "sweet pepper (whole)"],
        ["cutting board {sweet pepper}", "sweet pepper (whole) in [cutting board]"],
        "1. Pick up the whole sweet pepper and place it onto the empty cutting board.",
    ),
    (
        "crack",
        ["measuring cup (empty)", "egg (uncracked)"],
        ["measuring cup {egg}", "egg (cracked) in [measuring cup]"],
        "1. Crack the uncracked egg into the empty measuring cup.",
    ),
    (
        "cover",
        ["pot {butter,rice,water} in [stove]", "pot lid"],
        ["pot (covered) {butter,rice,water} in [stove]", "pot lid in [pot]"],
        "1. Cover the pot of butter, rice, and water with the pot lid.",
    ),
    (
        "cook",
        ["pot (hot) {macaroni,salt,water} in [stove]", "macaroni (raw) in [pot]"],
        ["macaroni (cooked) in [pot]"],
        "1. Cook the raw macaroni in the pot.",
    ),
    (
        "turn off",
        ["faucet (on)"],
        ["faucet (off)"],
        "1. Turn off the faucet.",
    ),
]


@pytest.mark.parametrize(("motion", "ins", "outs", "expected"), HAND_CHECKED)
def test_hand_checked_units(
    course: Course, motion: str, ins: list[str], outs: list[str], expected: str
) -> None:
    assert one_unit(course, motion, ins, outs) == expected


def test_fallback_names_the_motion_as_written() -> None:
    f = foon.Foon.from_text(
        "//\nO\tdough\nS\tflat\nO\trolling pin\nM\tzigzag twice\n"
        "O\tdough\nS\tzigzagged\nO\trolling pin\n//\n"
    )
    tree = f.plan(
        foon.Object("dough", ("zigzagged",)),
        [foon.Object("dough", ("flat",)), foon.Object("rolling pin")],
    )
    assert tree.steps() == [
        "1. Zigzag twice the flat dough with the rolling pin to get the zigzagged dough."
    ]


# --------------------------------------------------------------------------------------------
# Generated FOONs: arbitrary labels and motions never break the writer.
# --------------------------------------------------------------------------------------------

NAME = st.text(
    st.characters(
        codec="utf-8",
        categories=("L", "N", "P", "S", "Zs"),
        exclude_characters="\t\r\n{}[](),/\\#",
    ),
    min_size=1,
    max_size=12,
).filter(lambda s: s.strip() != "" and not s.strip().startswith("/"))
MOTION = st.sampled_from(("pour", "pick-and-place", "mix", "chop", "cover", "turn on")) | NAME
STATE = st.sampled_from(("empty", "on", "whole", "chopped")) | NAME


@st.composite
def gen_object(draw: st.DrawFn, labels: list[str]) -> str:
    lines = [f"O\t{draw(st.sampled_from(labels))}"]
    for s in draw(st.lists(STATE, max_size=2)):
        lines.append(f"S\t{s}")
    if draw(st.booleans()):
        lines.append(
            "S\tcontains\t{" + ",".join(draw(st.lists(NAME, min_size=1, max_size=3))) + "}"
        )
    if draw(st.booleans()):
        lines.append(f"S\tin\t[{draw(st.sampled_from(labels))}]")
    return "\n".join(lines)


@st.composite
def gen_text(draw: st.DrawFn) -> str:
    labels = draw(st.lists(NAME, min_size=2, max_size=6))
    units = []
    for _ in range(draw(st.integers(1, 8))):
        ins = draw(st.lists(gen_object(labels), max_size=4))
        outs = draw(st.lists(gen_object(labels), min_size=1, max_size=3))
        units.append("\n".join([*ins, f"M\t{draw(MOTION)}", *outs, "//"]))
    return "//\n" + "\n".join(units) + "\n"


@settings(max_examples=150, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
@given(text=gen_text())
def test_generated_foons(text: str) -> None:
    f = foon.Foon.from_text(text)
    raw = [o for i, o in enumerate(f.objects()) if not f.producers(i)]
    for goal in range(f.object_count):
        tree = f.plan(goal, raw)
        lines = tree.steps()
        check_lines(lines, len(tree.units))
        for line, fu in zip(lines, tree, strict=True):
            assert "\n" not in line
            m = fu.motion.strip()
            # A templated motion names each of its words; any other reads as written (its
            # first letter capitalised).
            assert motion_words(m) <= words(line) or m[1:] in line, (m, line)
        assert tree.write("steps") == f.plan(goal, raw).write("steps")
