"""The robot/human split (``Foon.split``, ``foon split``) against the brute force of
``split_reference.py`` on generated FOONs (cycles, duplicates, self-loops, the container rule),
and on the course data: the best success for every budget, the front, every front tree
(valid, its success and human steps as reported), budget 0 against ``optimal-success``, and
the lab's fixed-tree method against its reference."""

from __future__ import annotations

import json
import math
import random
from collections.abc import Callable

import foon
import foon_reference as ref
import pytest
import split_reference as sref
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_differential import RATES, Case, GenFoon, draw_case, gen_foons, load_course

SPLIT_SETTINGS = settings(max_examples=500, deadline=None, derandomize=True,
                          suppress_health_check=[HealthCheck.too_slow,
                                                 HealthCheck.data_too_large])  # fmt: skip


def rate_of(
    rates: dict[str, float] | None, overrides: dict[int, float], default: float | None
) -> Callable[[ref.RefFoon], Callable[[int], float]]:
    def bind(rf: ref.RefFoon) -> Callable[[int], float]:
        def rate(f: int) -> float:
            if f in overrides:
                return overrides[f]
            if rates is not None and rf.fus[f].motion in rates:
                return rates[rf.fus[f].motion]
            assert default is not None
            return default

        return rate

    return bind


def check_point(
    f: foon.Foon,
    planner: foon.Planner,
    goal: int,
    p: foon._split.SplitPoint,
    robot: Callable[[int], float],
    human: Callable[[int], float],
) -> None:
    """A front tree is valid, makes what it says, and has the success and human steps
    reported."""
    valid, _, _ = planner._native.check_tree(list(p.units), goal)
    assert valid or not p.units
    assert p.units == tuple(dict.fromkeys(s.unit for s in p.steps))
    assert sum(s.times for s in p.steps if s.actor == "human") == p.human
    for s in p.steps:
        assert s.unit in f.producers(s.object)
    if p.steps:
        assert p.steps[-1].object == goal and p.steps[-1].times == 1
    log_success = sum(
        s.times * math.log(human(s.unit) if s.actor == "human" else robot(s.unit)) for s in p.steps
    )
    assert math.isclose(math.exp(log_success), p.success, rel_tol=1e-9, abs_tol=1e-300)


def check_case(c: Case, data: st.DataObject, max_human: int) -> int:
    """Every goal of the case against brute force; returns how many were compared."""
    rates = c.rates
    # One drawn seed picks the human's table and the overrides: fewer draws, faster runs.
    rnd = random.Random(data.draw(st.integers(0, 2**32 - 1), label="profiles seed"))
    human_kind = rnd.choice(("certain", "table", "table-default"))
    human_rates = None
    if human_kind != "certain":
        motions = sorted({fu.motion for fu in c.rf.fus})
        human_rates = {m: rnd.choice(RATES) for m in motions
                       if human_kind == "table" or rnd.random() < 0.5}  # fmt: skip
    n_fu = len(c.rf.fus)
    overrides = {}
    if n_fu and rnd.random() < 0.5:
        for u in rnd.sample(range(n_fu), min(n_fu, rnd.randint(1, 3))):
            overrides[u] = rnd.choice(RATES)
    robot_profile = foon.Profile(foon.MotionRates(rates)).with_overrides(overrides)
    if human_kind == "certain":
        human_profile = foon.Profile.certain()
    else:
        human_profile = foon.Profile(foon.MotionRates(human_rates or {}), 1.0)
    profiles = foon.Profiles({"robot": robot_profile, "human": human_profile})
    robot = rate_of(rates, overrides, None)(c.rf)
    human = rate_of(human_rates, {}, 1.0)(c.rf)
    kitchen = ref.kitchen_ids(c.rf, c.kitchen)
    planner = c.f.planner(c.rkitchen, motions=foon.MotionRates(rates), utensils=c.utensils)
    compared = 0
    for goal in c.goals:
        r = planner.split(goal, profiles, max_human, fixed_tree=True)
        try:
            costs = sref.best_costs(c.rf, kitchen, c.utensils, robot, human, goal, max_human)
        except sref.TooBig:
            continue
        compared += 1
        assert [None if b is None else b for b in r.best] == [
            None if cost == math.inf else math.exp(-cost) for cost in costs
        ]
        solved = costs[-1] != math.inf
        assert r.solved == solved
        assert [p.human for p in r.front] == sref.front(costs)
        for p in r.front:
            assert p.success == math.exp(-costs[p.human])
            check_point(c.f, planner, goal, p, robot, human)
        # Budget 0 is optimal-success with the robot's table (without overrides).
        if not overrides:
            t = planner.plan(goal, "optimal-success")
            assert t.solved == (costs[0] != math.inf)
            if t.solved:
                assert t.cost == r.best[0]
                assert r.front[0].units == tuple(t.units)
        # The fixed-tree method: the best robot tree, its m lowest-rate units to the human.
        if costs[0] == math.inf:
            assert r.fixed is None or not solved
            continue
        assert r.fixed is not None
        base = r.front[0]
        assert base.human == 0
        made = [(st_.unit, st_.times) for st_ in base.steps]
        instances = sum(t for _, t in made)
        assert [p.human for p in r.fixed] == list(range(min(max_human, instances) + 1))
        for p in r.fixed:
            steps, success = sref.fixed_tree(made, robot, human, p.human)
            assert list(p.steps) == steps
            assert p.success == success
            assert p.success <= math.exp(-costs[p.human]) * (1 + 1e-9)
    return compared


@SPLIT_SETTINGS
@given(g=gen_foons(), data=st.data(), max_human=st.integers(0, 3))
def test_generated_foons(g: GenFoon, data: st.DataObject, max_human: int) -> None:
    c = draw_case(data, g)
    check_case(c, data, max_human)


def test_course_goals() -> None:
    """The 25 course goals, M = 0..3 with every human rate 1: budget 0 is optimal-success,
    the front only improves, and the split is never worse than the fixed tree."""
    c = load_course()
    profiles = foon.Profiles({"robot": c.rmotions})
    planner = c.foon.planner(c.rkitchen, motions=c.rmotions, utensils=c.rutensils)
    for goal in c.rgoals:
        r = c.foon.split(goal, c.rkitchen, profiles, 3, utensils=c.rutensils, fixed_tree=True)
        t = planner.plan(goal, "optimal-success")
        assert r.solved == t.solved
        if not t.solved:
            continue
        assert r.best[0] == t.cost
        assert r.front[0].units == tuple(t.units)
        successes = [p.success for p in r.front]
        assert successes == sorted(successes)  # (tiny successes underflow to 0)
        assert r.fixed is not None
        for p in r.fixed:
            best = r.best[p.human]
            assert best is not None and best >= p.success * (1 - 1e-12)


def test_kitchen_goal_and_unknown_profile() -> None:
    ex = foon.example()
    item = next(iter(ex.kitchen))
    r = ex.foon.split(item, ex.kitchen, {"robot": ex.motions}, 2) if ex.foon.find(item) else None
    if r is not None:
        assert r.solved and r.best == (1.0, 1.0, 1.0) and r.front[0].steps == ()
    with pytest.raises(ValueError, match="no profile named 'robot'"):
        ex.foon.split(ex.goals[0], ex.kitchen, {}, 1)
    with pytest.raises(foon.MissingRateError):
        ex.foon.split(ex.goals[0], ex.kitchen, {"robot": {"pour": 0.5}}, 1)


def test_override_file_errors(tmp_path: object) -> None:
    from pathlib import Path

    assert isinstance(tmp_path, Path)
    bad = tmp_path / "over.txt"
    bad.write_text("# units\n0\t0.5\n1\tx\n", encoding="utf-8")
    with pytest.raises(foon.ParseError, match=r"over\.txt:3:3: .*rate 'x' is not a number"):
        foon.Profile().with_overrides(bad)
    bad.write_text("0\t0.5\n  zz\t0.5\n", encoding="utf-8")
    with pytest.raises(foon.ParseError, match=r"over\.txt:2:3: .*unit 'zz'"):
        foon.Profile().with_overrides(bad)
    bad.write_text("0\t0.5\n0\t0.7\n", encoding="utf-8")
    with pytest.raises(foon.ParseError, match=r"over\.txt:2:1: .*unit 0 has two rates"):
        foon.Profile().with_overrides(bad)
    bad.write_text("0\t1.5\n", encoding="utf-8")
    with pytest.raises(foon.ParseError, match=r"over\.txt:1:3: .*not between 0 and 1"):
        foon.Profile().with_overrides(bad)
    bad.write_text("0\t0.5\n999\t0.5\n", encoding="utf-8")
    ex = foon.example()
    p = foon.Profile(ex.motions).with_overrides(bad)
    with pytest.raises(foon.ParseError, match=r"over\.txt:2:1: .*unit 999 is out of range"):
        ex.foon.split(ex.goals[0], ex.kitchen, {"robot": p}, 1)


def run_cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    from foon.cli import main

    code = main(["split", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_text_and_json(capsys: pytest.CaptureFixture[str], tmp_path: object) -> None:
    from pathlib import Path

    assert isinstance(tmp_path, Path)
    code, out, _ = run_cli(capsys, "--max-human", "2", "--fixed-tree")
    assert code == 0
    assert "front: 1 human step(s), success 0.9" in out
    assert "human unit 7 (pound)" in out and "fixed tree (the lab's method):" in out
    code, out, _ = run_cli(capsys, "--max-human", "2", "--fixed-tree", "--json")
    assert code == 0
    (d,) = json.loads(out)
    assert d["best"] == [0.495, 0.9, 1.0]
    assert [p["human"] for p in d["front"]] == [0, 1, 2]
    assert d["front"][1]["steps"][0] == {
        "unit": 7, "motion": "pound", "object": 17, "actor": "human", "budget": 1, "times": 1,
    }  # fmt: skip
    assert [round(p["success"], 12) for p in d["fixed_tree"]] == [0.495, 0.9, 1.0]
    # A human who pounds no better than the robot: one human step, the scoop; with two, a
    # different tree (freeze and crush by hand) beats every split of the robot's best tree.
    human = tmp_path / "human.txt"
    human.write_text("pound\t0.5\nscoop\t1.0\n", encoding="utf-8")
    ex = foon.example()
    robot = tmp_path / "robot.txt"
    robot.write_text("".join(f"{m}\t{r}\n" for m, r in ex.motions.items()), encoding="utf-8")
    code, out, _ = run_cli(capsys, "--profile", f"robot={robot}", "--profile",
                           f"human={human}", "--max-human", "2", "--json")  # fmt: skip
    (d,) = json.loads(out)
    assert code == 0 and [p["human"] for p in d["front"]] == [0, 1, 2]
    assert [s["actor"] for s in d["front"][1]["steps"]] == ["robot", "human"]
    assert d["front"][2]["units"] == [5, 3, 9, 8]
    assert [s["actor"] for s in d["front"][2]["steps"]] == ["robot", "human", "robot", "human"]
    assert math.isclose(d["best"][2], 0.85 * 0.85, rel_tol=1e-12)
    # Overrides: the robot never fails unit 6.
    over = tmp_path / "over.txt"
    over.write_text("# unit\trate\n6\t1\n", encoding="utf-8")
    code, out, _ = run_cli(capsys, "--override", f"robot={over}", "--max-human", "0", "--json")
    (d,) = json.loads(out)
    assert d["best"] == [ex.motions["pound"]]


def test_cli_errors(capsys: pytest.CaptureFixture[str], tmp_path: object) -> None:
    from pathlib import Path

    assert isinstance(tmp_path, Path)
    bad = tmp_path / "human.txt"
    bad.write_text("pound\t0.5\nscoop 1.0\n", encoding="utf-8")
    code, _, err = run_cli(capsys, "--profile", f"human={bad}")
    assert code == 1
    assert f"{bad}:2:10" in err and "expected 'motion<TAB>rate'" in err
    assert err.count("\n") == 1 and "Traceback" not in err
    over = tmp_path / "over.txt"
    over.write_text("6\t0.5\n7\tmaybe\n", encoding="utf-8")
    code, _, err = run_cli(capsys, "--override", f"human={over}")
    assert code == 1 and f"{over}:2:3" in err and "rate 'maybe' is not a number" in err
    over.write_text("6\t0.5\n70000\t0.5\n", encoding="utf-8")
    code, _, err = run_cli(capsys, "--override", f"human={over}")
    assert code == 1 and f"{over}:2:1" in err and "unit 70000 is out of range" in err
    code, _, err = run_cli(capsys, "--profile", "robot")
    assert code == 2 and "expected NAME=FILE" in err
    code, _, err = run_cli(capsys, "--label", "no such thing")
    assert code == 1 and "no such thing" in err


def test_compare_split_rows(capsys: pytest.CaptureFixture[str]) -> None:
    """``foon compare --split M``: a split and a fixed-tree row per goal; the split is never
    worse than the fixed tree, and at M = 0 both are optimal-success's cost."""
    from foon.cli import main

    assert main(["compare", "--split", "2", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    split = {r["goal"]: r for r in rows if r["method"] == "split M=2"}
    fixed = {r["goal"]: r for r in rows if r["method"] == "fixed-tree M=2"}
    assert split and split.keys() == fixed.keys()
    for goal, r in split.items():
        if r["solved"]:
            assert r["success"] >= fixed[goal]["success"] * (1 - 1e-12)
    ex = foon.example()
    r = ex.foon.split(ex.goals[0], ex.kitchen, {"robot": ex.motions}, 2)
    assert split[str(ex.foon.object(r.goal))]["success"] == r.best[2]
