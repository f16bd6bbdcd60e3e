"""Planning at identity levels 1 and 2 (``level=``): kitchen items and goals match every
object equal to them at the level (the levels of merging), checked against a pure-Python
reference on generated FOONs, and an example where the levels give different trees."""

from __future__ import annotations

import foon
import foon_reference as ref
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_differential import GEN_SETTINGS, GenFoon, draw_case, gen_foons, gen_objects


def key(level: int, ident: ref.Identity) -> object:
    """Merge's levels: 1 the label, 2 label, states and container, 3 the full identity."""
    label, states, ingredients, container = ident
    if level == 1:
        return label
    if level == 2:
        return (label, tuple(sorted(states)), container)
    return (label, tuple(sorted(states)), tuple(sorted(ingredients)), container)


def kitchen_at(rf: ref.RefFoon, kitchen: list[ref.Identity], level: int) -> set[int]:
    keys = {key(level, k) for k in kitchen}
    return {o for o, ident in enumerate(rf.objects) if key(level, ident) in keys}


def goal_at(
    rf: ref.RefFoon, goal: ref.Identity, k: set[int], ranks: dict[int, int], level: int
) -> int | None:
    cands = [o for o, ident in enumerate(rf.objects) if key(level, ident) == key(level, goal)]
    if not cands:
        return None
    inside = [o for o in cands if o in k]
    if inside:
        return inside[0]
    made = sorted((ranks[o], o) for o in cands if o in ranks)
    return made[0][1] if made else cands[0]


@settings(GEN_SETTINGS, max_examples=50)
@given(g=gen_foons(), data=st.data(), level=st.sampled_from([1, 2]))
def test_levels_match_the_reference(g: GenFoon, data: st.DataObject, level: int) -> None:
    case = draw_case(data, g)
    rf, f, ut = case.rf, case.f, case.utensils
    extra = data.draw(st.lists(gen_objects(), max_size=3), label="items not in the FOON")
    kitchen = case.kitchen + [(o.label, o.states, o.ingredients, o.container) for o in extra]
    rk = foon.Kitchen(foon.Object(*i) for i in kitchen)
    k = kitchen_at(rf, kitchen, level)
    ranks = ref.ranks(rf, k, ut)
    planner = f.planner(rk, utensils=sorted(ut), level=level)
    assert {o for o, r in enumerate(planner.ranks()) if r is not None} == set(ranks)
    exact = foon.Kitchen(f.object(o) for o in sorted(k))
    goals = [rf.objects[o] for o in case.goals] + [
        (o.label, o.states, o.ingredients, o.container) for o in extra[:1]
    ]
    for goal in goals:
        want = goal_at(rf, goal, k, ranks, level)
        obj = foon.Object(*goal)
        if want is None:
            with pytest.raises(foon.GoalNotFoundError):
                planner.plan(obj)
            continue
        for method in ("ids", "optimal-units"):
            t = planner.plan(obj, method)
            assert t.goal_id == want and t.level == level
            # The same tree as at level 3 with the level's kitchen written out in full.
            t3 = f.plan(want, exact, method, utensils=sorted(ut))
            assert (t.solved, t.units) == (t3.solved, t3.units)
            if t.solved:
                assert ref.is_valid(rf, t.units, want, k, ut)


EXAMPLE = """O\tonion\nS\twhole\nM\tchop\nO\tonion\nS\tchopped\nS\tin\t[bowl]\n//
O\tonion\nS\tchopped\nS\tin\t[bowl]\nO\tpot\nM\tpour\nO\tpot\nS\tcontains\t{onion}\n//
O\tpot\nS\tcontains\t{onion}\nM\tboil\nO\tsoup\nS\thot\nS\tin\t[pot]\n//
O\tsoup\nS\tcold\nS\tin\t[pot]\nM\theat\nO\tsoup\nS\thot\nS\tin\t[pot]\n//
"""


def test_levels_give_different_trees() -> None:
    """The METHODS.md example: a whole onion, a pot and cold soup in a bowl; the goal hot
    soup in a pot. Level 3 chops, pours and boils; at level 2 the empty pot stands for the pot
    holding the onion (ingredients are ignored), so boiling is enough; at level 1 the cold
    soup stands for every soup, the goal included: nothing to do."""
    f = foon.Foon.from_text(EXAMPLE)
    kitchen = [foon.Object("onion", ("whole",)), foon.Object("pot"),
               foon.Object("soup", ("cold",), (), "bowl")]  # fmt: skip
    goal = foon.Object("soup", ("hot",), (), "pot")
    trees = {lv: f.plan(goal, kitchen, "optimal-units", level=lv) for lv in (1, 2, 3)}
    assert [f.fu(u).motion for u in trees[3].units] == ["chop", "pour", "boil"]
    assert [f.fu(u).motion for u in trees[2].units] == ["boil"]
    assert trees[1].units == [] and trees[1].solved
    assert [t.level for t in trees.values()] == [1, 2, 3]
    with pytest.raises(ValueError):
        f.plan(goal, kitchen, level=4)  # type: ignore[arg-type]
