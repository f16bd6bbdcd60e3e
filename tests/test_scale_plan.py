"""Plans on connected FOONs from what a planner computes once per kitchen (ranks, each optimal
objective's costs and choices, the shopping costs of explanations, the choices of ``ids``).

- On a connected FOON built from the course data (copies of the course FOON whose
  intermediates are shared by neighbouring copies, so that they have several producers from
  different copies; raw items and utensils shared by all), with the course kitchen and a sparse
  one: every sound method's trees and explanations equal the pure-Python reference's, for
  goals spread over the copies.
- One planner reused for many goals gives the trees of a fresh preparation per goal, with one
  thread or two (both may compute the same shared values at once).
- On generated FOONs (cycles, self-loops, duplicates, shared intermediates) with kitchens of
  several densities, every object planned with one planner equals the reference.
"""

from __future__ import annotations

import json
from pathlib import Path

import foon
import foon_reference as ref
import pytest
from hypothesis import given
from hypothesis import strategies as st
from test_differential import (
    GEN_SETTINGS,
    MOTIONS,
    RATES,
    SOUND_CONFIGS,
    UTENSILS,
    GenFoon,
    compare,
    gen_foons,
    memoized_reference,
    need_data,
)

#: Copies of the course FOON, and how many neighbouring copies share an intermediate.
COPIES = 3
WINDOW = 2


def _tag(copy: int, o: int) -> str:
    return f"share {(copy + o % WINDOW) // WINDOW}"


class Connected:
    """The connected FOON, its kitchens (full and sparse) and goals, on both sides."""

    def __init__(self, data: Path) -> None:
        course = foon.load(data / "FOON.txt")
        inter = {o for o in range(course.object_count) if course.producers(o)}
        out: list[str] = []
        for k in range(COPIES):
            for i in range(course.fu_count):
                u = course.fu(i)
                ids = iter(list(u.input_ids) + list(u.output_ids))
                for line in course.fu_text(i).split("\n"):
                    out.append(line)
                    if line.startswith("O\t") and (o := next(ids)) in inter:
                        out.append(f"S\t{_tag(k, o)}")
        self.text = "\n".join(out) + "\n"
        self.f = foon.Foon.from_text(self.text)
        self.rf = ref.parse(self.text)
        self.utensils = foon.load_utensils(data / "utensils.txt")
        self.rates = dict(foon.MotionRates.load(data / "motion.txt"))

        def tagged(o: foon.Object, copies: range) -> list[foon.Object]:
            i = course.find(o)
            if i is None or i not in inter:
                return [o]
            tags = sorted({_tag(k, i) for k in copies})
            return [foon.Object(o.label, [t, *o.states], o.ingredients, o.container) for t in tags]

        items = list(foon.Kitchen.load(data / "kitchen.json"))
        raw = [o for o in items if (i := course.find(o)) is None or i not in inter]
        drop = set(raw[::3])
        self.kitchens = {
            "full": [t for o in items for t in tagged(o, range(COPIES))],
            "sparse": [t for o in items if o not in drop for t in tagged(o, range(COPIES))],
        }
        goals = [foon.Object.from_dict(d)
                 for d in json.loads((data / "goal_nodes_25.json").read_text())]  # fmt: skip
        self.goals: list[int] = []
        for k in range(COPIES):
            for g in goals:
                i = course.find(g)
                assert i is not None
                (t,) = tagged(g, range(k, k + 1))
                self.goals.append(self.f.goal_id(t))


@pytest.fixture(scope="module")
def connected() -> Connected:
    return Connected(need_data())


def _identities(items: list[foon.Object]) -> list[ref.Identity]:
    return [o.identity() for o in items]


@pytest.mark.parametrize("kitchen", ["full", "sparse"])
def test_connected_foon_matches_the_reference(connected: Connected, kitchen: str) -> None:
    c = connected
    # Every intermediate of the course has a producer in more than one copy.
    shared = [o for o in range(c.f.object_count) if len(c.f.producers(o)) > 1]
    assert len(shared) > 1000
    items = c.kitchens[kitchen]
    p = c.f.planner(items, motions=c.rates, utensils=c.utensils)
    failed = 0
    with memoized_reference():
        for cfg in SOUND_CONFIGS:
            trees = p.plan_many(c.goals, cfg.method, count=cfg.count, threads=1)  # type: ignore[arg-type]
            for goal, tree in zip(c.goals, trees, strict=True):
                compare(c.rf, c.f, tree, goal, _identities(items), set(c.utensils), c.rates, cfg)
                failed += not tree.solved
    # The sparse kitchen fails most goals (explanations), the full one solves most.
    if kitchen == "sparse":
        assert failed > len(c.goals) * len(SOUND_CONFIGS) // 2
    else:
        assert failed < len(c.goals) * len(SOUND_CONFIGS) // 2


@pytest.mark.parametrize("kitchen", ["full", "sparse"])
def test_one_planner_gives_the_trees_of_a_fresh_preparation(
    connected: Connected, kitchen: str
) -> None:
    c = connected
    items = c.kitchens[kitchen]
    goals = c.goals[::5]
    for cfg in SOUND_CONFIGS:
        fresh = [
            c.f.plan(g, items, cfg.method, count=cfg.count, motions=c.rates,  # type: ignore[arg-type]
                     utensils=c.utensils).to_dict()
            for g in goals
        ]  # fmt: skip
        for threads in (1, 2):
            p = c.f.planner(items, motions=c.rates, utensils=c.utensils)
            reused = p.plan_many(goals, cfg.method, count=cfg.count, threads=threads)  # type: ignore[arg-type]
            got = [t.to_dict() for t in reused]
            for a, b in zip(got, fresh, strict=True):
                for d in (a, b):
                    for k in ("seconds", "expanded", "peak_frontier"):
                        d.pop(k, None)
                assert a == b, (cfg, threads)


@given(g=gen_foons(), density=st.integers(0, 4), seed=st.integers(0, 2**16), data=st.data())
@GEN_SETTINGS
def test_generated_foons_every_object_one_planner(
    g: GenFoon, density: int, seed: int, data: st.DataObject
) -> None:
    rf = ref.parse(g.text)
    f = foon.Foon.from_text(g.text)
    n = len(rf.objects)
    # Kitchens from empty (density 0) to every object (density 4).
    kitchen = [rf.objects[o] for o in range(n) if (o * 7919 + seed) % 4 < density]
    items = foon.Kitchen(foon.Object(lab, tuple(s), tuple(i), c) for lab, s, i, c in kitchen)
    rates = {m: data.draw(st.sampled_from(RATES), label=f"rate {m}") for m in MOTIONS}
    utensils = list(UTENSILS)
    p = f.planner(items, motions=rates, utensils=utensils)
    goals = list(range(n))
    for cfg in SOUND_CONFIGS:
        trees = p.plan_many(goals, cfg.method, count=cfg.count, threads=1)  # type: ignore[arg-type]
        for goal, tree in zip(goals, trees, strict=True):
            compare(rf, f, tree, goal, kitchen, set(utensils), rates, cfg)
