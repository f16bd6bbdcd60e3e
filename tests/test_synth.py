"""``foon.synth``: synthetic merged FOONs.

What is shown here: the same (units, seed) gives the same bytes on 1 and 2 threads and
different seeds differ; every generated file loads (foon.load and the pure-Python course
parser of ``foon_reference``) without a warning and with exactly the units asked for; at
the course's size its statistics match the course FOON's within the tolerances stated in
``TOLERANCES`` (the same measuring code, :func:`measure`, runs on both); its goals are
derivable with its kitchen at the course's rate; and the command writes whole files or
nothing.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from collections import Counter
from pathlib import Path
from typing import Any

import foon
import foon_reference as ref
import pytest
from conftest import DATA, need_shared
from foon import _synth
from foon._cli_synth import add_synth_options, cmd_synth
from foon.cli import UsageError
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

COURSE_UNITS = 2376


# --- measuring (the same code for the course FOON and generated ones) -----------------------


def _bare(o: foon.Object) -> bool:
    return not (o.states or o.ingredients or o.container)


def _largest_scc(n: int, succ: list[set[int]]) -> int:
    """Objects in the largest strongly connected component (iterative Tarjan)."""
    index = [-1] * n
    low = [0] * n
    on = [False] * n
    stack: list[int] = []
    best = 0
    counter = 0
    for root in range(n):
        if index[root] >= 0:
            continue
        work = [(root, iter(succ[root]))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on[root] = True
        while work:
            v, it = work[-1]
            for w in it:
                if index[w] < 0:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on[w] = True
                    work.append((w, iter(succ[w])))
                    break
                if on[w]:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    u = work[-1][0]
                    low[u] = min(low[u], low[v])
                if low[v] == index[v]:
                    size = 0
                    while True:
                        w = stack.pop()
                        on[w] = False
                        size += 1
                        if w == v:
                            break
                    best = max(best, size)
    return best


def measure(f: foon.Foon) -> dict[str, Any]:
    """The statistics the generator is calibrated on."""
    n, no = f.fu_count, f.object_count
    units = [f.fu(i) for i in range(n)]
    objs = [f.object(i) for i in range(no)]
    prod = [len(f.producers(i)) for i in range(no)]
    produced = sum(p > 0 for p in prod)
    labels = Counter(o.label for o in objs)
    motions = Counter(u.motion for u in units)
    # Connected components of the unit-object graph (undirected), by union-find.
    parent = list(range(no))

    def find(x: int) -> int:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for u in units:
        ids = [*u.input_ids, *u.output_ids]
        for j in ids[1:]:
            a, b = find(ids[0]), find(j)
            if a != b:
                parent[a] = b
    comp = Counter(find([*u.input_ids, *u.output_ids][0]) for u in units)
    succ: list[set[int]] = [set() for _ in range(no)]
    for u in units:
        made = [o for o in u.output_ids if not _bare(objs[o])]
        for a in u.input_ids:
            succ[a].update(b for b in made if b != a)
    self_loops = sum(
        any(o in set(u.input_ids) and not _bare(objs[o]) for o in u.output_ids) for u in units
    )
    return {
        "inputs_per_unit": sum(len(u.input_ids) for u in units) / n,
        "outputs_per_unit": sum(len(u.output_ids) for u in units) / n,
        "objects_per_label": no / len(labels),
        "multi_producer_share": sum(p > 1 for p in prod) / produced,
        "states_per_object": sum(len(o.states) for o in objs) / no,
        "stateless_share": sum(not o.states for o in objs) / no,
        "ingredient_object_share": sum(bool(o.ingredients) for o in objs) / no,
        "container_object_share": sum(o.container is not None for o in objs) / no,
        "units_with_ingredients": sum(
            any(o.ingredients for o in (*u.inputs, *u.outputs)) for u in units
        )
        / n,
        "units_with_containers": sum(
            any(o.container for o in (*u.inputs, *u.outputs)) for u in units
        )
        / n,
        "self_loop_share": self_loops / n,
        "largest_component_share": max(comp.values()) / n,
        "largest_cycle_share": _largest_scc(no, succ) / no,
        "top_motions": [m for m, _ in motions.most_common(10)],
    }


#: Allowed difference between a generated FOON of 2,376 units and the course FOON, for each
#: statistic: ("rel", r) is a relative difference of at most r, ("abs", d) an absolute one.
TOLERANCES: dict[str, tuple[str, float]] = {
    "inputs_per_unit": ("rel", 0.20),
    "outputs_per_unit": ("rel", 0.15),
    "objects_per_label": ("rel", 0.25),
    "multi_producer_share": ("abs", 0.06),
    "states_per_object": ("rel", 0.20),
    "stateless_share": ("abs", 0.12),
    "ingredient_object_share": ("abs", 0.15),
    "container_object_share": ("abs", 0.20),
    "units_with_ingredients": ("abs", 0.08),
    "units_with_containers": ("abs", 0.10),
    "self_loop_share": ("abs", 0.03),
}


# --- determinism ----------------------------------------------------------------------------


def test_same_seed_same_bytes_on_any_thread_count() -> None:
    a = _synth.synth(9000, 7, threads=1)
    assert a == _synth.synth(9000, 7, threads=2)
    assert a == _synth.synth(9000, 7)
    assert a != _synth.synth(9000, 8)


def test_file_equals_text_and_report(tmp_path: Path) -> None:
    out = tmp_path / "s.txt"
    seen: list[tuple[int, int]] = []
    r = _synth.synth(4000, 3, path=out, threads=2, progress=lambda d, t: seen.append((d, t)))
    data = out.read_bytes()
    assert data.decode() == _synth.synth(4000, 3)
    assert (r.units, r.bytes, r.path) == (4000, len(data), str(out))
    assert r.recipes > 0
    assert seen and seen[-1] == (4000, 4000)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)
    assert [p.name for p in tmp_path.iterdir()] == ["s.txt"]  # no temporary file left


def test_side_files_are_deterministic() -> None:
    assert _synth.synth_kitchen(5000, 2) == _synth.synth_kitchen(5000, 2)
    assert _synth.synth_goals(5000, 2, 10) == _synth.synth_goals(5000, 2, 10)
    assert _synth.synth_goals(5000, 2, 10) != _synth.synth_goals(5000, 3, 10)


# --- loading, counts, no warnings -----------------------------------------------------------


def _check_file(text: str, units: int) -> foon.Foon:
    f = foon.Foon.from_text(text, strict=True)
    assert f.fu_count == units
    assert f.warnings == []
    r = ref.parse(text, strict=True)
    assert len(r.fus) == units
    assert r.warnings == []
    assert len(set(r.objects)) == f.object_count
    return f


@pytest.mark.parametrize("units", [1, 2, 3, 4, 17, 300, 2376, 20000])
def test_loads_with_exact_count(units: int) -> None:
    _check_file(_synth.synth(units, 0), units)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(units=st.integers(1, 3000), seed=st.integers(0, 2**64 - 1))
def test_any_size_and_seed_loads_exactly(units: int, seed: int) -> None:
    f = _check_file(_synth.synth(units, seed), units)
    kitchen = _synth.synth_kitchen(units, seed)
    goals = _synth.synth_goals(units, seed, 5)
    assert len(set(kitchen)) == len(kitchen)
    for g in goals:
        assert f.find(g) is not None  # every goal is an object of the FOON


def test_motion_table_covers_every_motion() -> None:
    rates = _synth.synth_motions()
    f = foon.Foon.from_text(_synth.synth(20000, 5))
    used = {f.fu(i).motion for i in range(f.fu_count)}
    assert used <= set(rates)
    assert all(0 < r <= 1 for r in rates.values())


def test_bad_sizes_are_clear_errors(tmp_path: Path) -> None:
    for units, match in [(0, "at least 1"), (-5, "at least 1"), (2**32, "at most 4294967295")]:
        with pytest.raises(ValueError, match=match):
            _synth.synth(units, 0)
        with pytest.raises(ValueError, match=match):
            _synth.synth(units, 0, path=tmp_path / "x.txt")
    assert not list(tmp_path.iterdir())
    with pytest.raises(ValueError, match="give path="):
        _synth.synth(_synth.SYNTH_TEXT_LIMIT + 1, 0)
    with pytest.raises(ValueError, match="seed"):
        _synth.synth(10, -1)
    with pytest.raises(TypeError, match="units must be an int"):
        _synth.synth("10", 0)  # type: ignore[call-overload]
    with pytest.raises(FileNotFoundError):
        _synth.synth(10, 0, path=tmp_path / "no" / "x.txt")


# --- calibration on the course FOON ---------------------------------------------------------


@pytest.fixture(scope="module")
def course_stats() -> dict[str, Any]:
    need_shared()
    return measure(foon.load(DATA / "FOON.txt"))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_statistics_match_the_course(course_stats: dict[str, Any], seed: int) -> None:
    got = measure(foon.Foon.from_text(_synth.synth(COURSE_UNITS, seed)))
    for key, (kind, tol) in TOLERANCES.items():
        want, have = course_stats[key], got[key]
        diff = abs(have - want) / want if kind == "rel" else abs(have - want)
        assert diff <= tol, f"{key}: generated {have:.3f}, course {want:.3f}"
    # One large connected component, as in a merged FOON (the course: 99.9% of the units).
    assert got["largest_component_share"] >= 0.9
    # A giant cycle through the shared vessels (the course's holds 41% of its objects).
    assert course_stats["largest_cycle_share"] >= 0.25
    assert got["largest_cycle_share"] >= 0.25
    # The motion mix: at least 7 of the course's 10 most used motions are in the top 10.
    top = set(got["top_motions"])
    assert len(top & set(course_stats["top_motions"])) >= 7


def test_lab_universal_foons_agree_with_the_course(course_stats: dict[str, Any]) -> None:
    """The lab's universal FOONs, which the model is also calibrated on, are within the same
    tolerances of the course FOON (so calibrating on either gives the same model)."""
    lab = measure(foon.load(DATA / "lab_history" / "FOON_sakib_2021-09-21_4172ca1.txt"))
    for key, (kind, tol) in TOLERANCES.items():
        want, have = course_stats[key], lab[key]
        diff = abs(have - want) / want if kind == "rel" else abs(have - want)
        assert diff <= tol, key


def _derivable_share(
    f: foon.Foon, kitchen: foon.Kitchen, goals: list[int], utensils: list[str] | None = None
) -> float:
    ranks = f.planner(kitchen, utensils=utensils).ranks()
    return sum(ranks[g] is not None for g in goals) / len(goals)


def test_goals_are_derivable_at_the_course_rate() -> None:
    """The course: 95.3% of its final products (produced, never consumed) are derivable
    with the course kitchen (23 of its 25 published goals). Generated dishes with the
    generated kitchen: within 6 points of that rate, on every seed tried."""
    need_shared()
    course = foon.load(DATA / "FOON.txt")
    n = course.object_count
    finals = [o for o in range(n) if course.producers(o) and not course.consumers(o)]
    kitchen = foon.Kitchen.load(DATA / "kitchen.json")
    utensils = foon.load_utensils(DATA / "utensils.txt")
    want = _derivable_share(course, kitchen, finals, utensils)
    assert abs(want - 0.953) < 0.005
    for seed in range(3):
        f = foon.Foon.from_text(_synth.synth(COURSE_UNITS, seed))
        goals = _synth.synth_goals(COURSE_UNITS, seed, 100)
        assert len(goals) >= 80
        ids = [f.find(g) for g in goals]
        assert None not in ids
        got = _derivable_share(f, _synth.synth_kitchen(COURSE_UNITS, seed), ids)  # type: ignore[arg-type]
        assert abs(got - want) <= 0.06, f"seed {seed}: {got:.3f} of the dishes derivable"


def test_goals_plan_with_every_method() -> None:
    f = foon.Foon.from_text(_synth.synth(6000, 4))
    kitchen = _synth.synth_kitchen(6000, 4)
    goals = _synth.synth_goals(6000, 4, 8)
    planner = f.planner(kitchen, motions=_synth.synth_motions())
    solved = 0
    for method in ("ids", "greedy-success", "optimal-success", "optimal-units"):
        for t in planner.plan_many(goals, method):
            if t.solved:
                solved += 1
                assert t.is_valid(kitchen)
    assert solved >= 0.8 * 4 * len(goals)


# --- the command ----------------------------------------------------------------------------


def _run(argv: list[str]) -> int:
    p = argparse.ArgumentParser()
    add_synth_options(p)
    return cmd_synth(p.parse_args(argv))


def test_command_writes_every_file(tmp_path: Path) -> None:
    out, k, g, m = (tmp_path / n for n in ("f.txt", "k.json", "g.json", "m.txt"))
    argv = ["--units", "3000", "--seed", "9", "-o", str(out), "--kitchen", str(k)]
    argv += ["--goals", str(g), "--goal-count", "7", "--motions", str(m), "-q"]
    assert _run(argv) == 0
    assert out.read_text() == _synth.synth(3000, 9)
    assert foon.Kitchen.load(k) == _synth.synth_kitchen(3000, 9)
    assert foon.load_goals(g) == _synth.synth_goals(3000, 9, 7)
    assert len(json.loads(g.read_text())) == 7
    assert dict(foon.MotionRates.load(m)) == dict(_synth.synth_motions())
    f = foon.load(out)
    plans = f.plan_many(foon.load_goals(g), foon.Kitchen.load(k), motions=m)
    assert any(t.solved for t in plans)


def test_command_errors_leave_no_file(tmp_path: Path) -> None:
    out = tmp_path / "f.txt"
    for units in ("0", str(2**32)):
        with pytest.raises(ValueError, match="units must be"):
            _run(["--units", units, "-o", str(out)])
    assert not list(tmp_path.iterdir())
    with pytest.raises(UsageError, match="differ"):
        _run(["--units", "5", "-o", str(out), "--kitchen", str(out)])
    with pytest.raises(UsageError, match="file names"):
        _run(["--units", "5", "-o", str(out), "--goals", "-"])


def test_command_to_stdout_and_devices(tmp_path: Path) -> None:
    code = (
        "import argparse, sys\n"
        "from foon._cli_synth import add_synth_options, cmd_synth\n"
        "p = argparse.ArgumentParser(); add_synth_options(p)\n"
        "sys.exit(cmd_synth(p.parse_args(sys.argv[1:])))\n"
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    r = subprocess.run(
        [sys.executable, "-c", code, "--units", "500", "--seed", "1", "-o", "-"],
        capture_output=True,
        check=True,
        env=env,
    )
    assert r.stdout.decode() == _synth.synth(500, 1)
    assert r.stderr == b""
    assert _run(["--units", "500", "-o", os.devnull]) == 0
    assert os.path.exists(os.devnull)
