"""Many kitchens at once (``Foon.derivable_many``, ``Foon.ranks_many``) against a pure-Python
forward chaining, round by round, on generated FOONs (cycles, self-loops, duplicate units)
with random kitchens, for 1, 63, 64, 65 and 130 kitchens, and on the course FOON."""

from __future__ import annotations

import random

import foon
import foon_reference as ref
import pytest
from foon import _foon
from hypothesis import given, settings
from hypothesis import strategies as st
from test_differential import UTENSILS, Course, GenFoon, gen_foons, load_course, rust_kitchen


def ref_ranks(rf: ref.RefFoon, kitchen: set[int], utensils: set[str]) -> dict[int, int]:
    """Rank of every derivable object, by the definition: round r + 1 adds the produced
    (not bare) outputs of every FU whose needed inputs were all derivable after round r."""
    needed = [ref.needed_inputs(rf, f, utensils) for f in range(len(rf.fus))]
    rank = dict.fromkeys(kitchen, 0)
    r = 0
    while True:
        new = {
            y
            for f in range(len(rf.fus))
            if all(x in rank for x in needed[f])
            for y in rf.fu_outputs(f)
            if y not in rank and not _bare(rf, y)
        }
        if not new:
            return rank
        r += 1
        rank.update(dict.fromkeys(new, r))


def _bare(rf: ref.RefFoon, o: int) -> bool:
    _, states, ings, cont = rf.objects[o]
    return not states and not ings and cont is None


def check(rf: ref.RefFoon, f: foon.Foon, kitchens: list[set[int]], utensils: set[str]) -> None:
    goals = list(range(len(rf.objects)))
    natives = [rust_kitchen([rf.objects[o] for o in sorted(k)]) for k in kitchens]
    got_d = f.derivable_many(natives, goals, utensils=sorted(utensils))
    got_r = f.ranks_many(natives, goals, utensils=sorted(utensils), threads=2)
    assert len(got_d) == len(got_r) == len(kitchens)
    # The baselines of the benchmark: each kitchen prepared on its own, or on a shared base.
    for mode in ("separate", "shared"):
        assert (
            foon._foon.derivable_many(f._native, [k._native for k in natives], goals,
                                      sorted(utensils), 3, True, None, mode)
            == got_r
        )  # fmt: skip
    for i, k in enumerate(kitchens):
        want = ref_ranks(rf, k, utensils)
        assert got_r[i] == [want.get(o) for o in goals], i
        assert got_d[i] == [o in want for o in goals], i


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    g=gen_foons(),
    seed=st.integers(0, 2**32),
    count=st.sampled_from((1, 63, 64, 65, 130)),
    utensils=st.sampled_from((UTENSILS, (), ("bowl",))),
)
def test_generated_foons(g: GenFoon, seed: int, count: int, utensils: tuple[str, ...]) -> None:
    rf = ref.parse(g.text)
    f = foon.Foon.from_text(g.text)
    rnd = random.Random(seed)
    n = len(rf.objects)
    kitchens = [{o for o in range(n) if rnd.random() < rnd.random()} for _ in range(count)]
    check(rf, f, kitchens, set(utensils))


@pytest.fixture(scope="module")
def course() -> Course:
    return load_course()


def test_course_foon(course: Course) -> None:
    rf = course.ref
    base = ref.kitchen_ids(rf, course.kitchen)
    rnd = random.Random(13)
    kitchens = [base] + [{o for o in base if rnd.random() < 0.8} for _ in range(64)]
    check(rf, course.foon, kitchens, course.utensils)
    # The course's 25 goals: some derivable in its kitchen, some not.
    goals = [course.foon.goal_id(g) for g in course.rgoals]
    row = course.foon.derivable_many([course.rkitchen], goals, utensils=course.rutensils)
    assert 0 < sum(row[0]) < len(goals) == 25
    made = ref.derivable(rf, base, course.utensils)
    assert row[0] == [g in made for g in goals]


def test_bad_arguments() -> None:
    f = foon.Foon.from_text("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    k = foon.Kitchen([foon.Object("egg", ("whole",))])
    assert f.derivable_many([k, None], [0, 1]) == [[True, True], [False, False]]
    assert f.ranks_many([k], [1, 0]) == [[1, 0]]
    assert f.derivable_many([], [0]) == []
    with pytest.raises(TypeError):
        f.derivable_many(k, [0])  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        f.derivable_many([k], "egg")
    with pytest.raises(ValueError):
        f.derivable_many([k], [0], level=4)  # type: ignore[arg-type]
    with pytest.raises(foon.GoalNotFoundError):
        f.derivable_many([k], [{"label": "tea"}])
    with pytest.raises(foon.GoalNotFoundError, match="object id 99"):
        f.derivable_many([k], [99])


def test_matched_kitchens(course: Course) -> None:
    """Kitchens matched once (what the benchmark times apart from the preparation) give the
    same answers in every mode, and only for the FOON and level they were matched to."""
    f = course.foon
    rnd = random.Random(5)
    items = list(course.rkitchen)
    kitchens = [foon.Kitchen(o for o in items if rnd.random() < 0.8) for _ in range(70)]
    natives = [k._native for k in kitchens]
    goals = [f.goal_id(g) for g in course.rgoals]
    uts = list(course.rutensils)
    want = f.ranks_many(kitchens, goals, utensils=course.rutensils)
    for level in (1, 2, 3):
        m = _foon.match_kitchens(f._native, natives, level)
        assert len(m) == 70 and m.level == level
        plain = _foon.derivable_many(f._native, natives, goals, uts, level, True, 1, "lanes")
        for mode in ("lanes", "separate", "shared"):
            assert _foon.derivable_many(f._native, m, goals, uts, level, True, 1, mode) == plain
        if level == 3:
            assert plain == want
    m = _foon.match_kitchens(f._native, natives, 3)
    with pytest.raises(ValueError, match="another FOON or at another level"):
        _foon.derivable_many(f._native, m, goals, uts, 2, True, 1, "lanes")
    other = foon.Foon.from_text("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    with pytest.raises(ValueError, match="another FOON or at another level"):
        _foon.derivable_many(other._native, m, [0], [], 3, True, 1, "lanes")


@pytest.mark.parametrize("most", [2, 8, 30])
def test_units_with_many_inputs(most: int) -> None:
    """Units with 1 to `most` inputs over few objects (cycles, self-loops, bare tools), so
    that the core's per-unit counters take one to four bit planes and the widest units are
    decided apart; sparse and dense kitchens, 65 of each."""
    rnd = random.Random(most)

    def obj(o: int) -> str:
        return f"O\ttool{o}\n" if o % 9 == 8 else f"O\tx\nS\ts{o}\n"

    parts = []
    for u in range(400):
        k = 20 if u == 7 else rnd.randint(1, most)
        ins = sorted({rnd.randrange(60) for _ in range(k)})
        outs = [rnd.randrange(60) for _ in range(rnd.randint(1, 2))]
        parts.append("".join(map(obj, ins)) + "M\tm\n" + "".join(map(obj, outs)) + "//\n")
    text = "".join(parts)
    rf = ref.parse(text)
    f = foon.Foon.from_text(text)
    n = len(rf.objects)
    for density in (0.25, 0.875):
        kitchens = [{o for o in range(n) if rnd.random() < density} for _ in range(65)]
        check(rf, f, kitchens, set())
