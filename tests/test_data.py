"""Every FOON text file of the real data set loads, with the same counts as the pure-Python
reference parser, and the course FOON has the published counts."""

from __future__ import annotations

import warnings

import foon
import foon_reference as ref
import pytest
from conftest import DATA, need_shared

NON_FOON = {
    "motion.txt",
    "motion_uniform_0.1.txt",
    "utensils.txt",
    "default_ingredients.txt",
    "dish_type.txt",
}


def foon_files() -> list[str]:
    if not DATA.is_dir():
        return []
    return sorted(str(p.relative_to(DATA)) for p in DATA.rglob("*.txt") if p.name not in NON_FOON)


def test_the_data_set_has_250_foon_files() -> None:
    need_shared()
    assert len(foon_files()) == 250


def test_course_foon_counts(course: object) -> None:
    need_shared()
    f = foon.load(DATA / "FOON.txt")
    s = f.stats()
    assert (s["functional_units"], s["objects"], s["produced_objects"], s["motions"]) == (
        2376,
        4305,
        3371,
        129,
    )
    assert s["duplicates_dropped"] == 0
    assert f.warnings == []


@pytest.mark.parametrize("name", foon_files() or ["(no data)"])
def test_every_file_loads_like_the_reference(name: str) -> None:
    need_shared()
    path = DATA / name
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        f = foon.load(path)
    r = ref.parse(path.read_text(encoding="utf-8"))
    assert [w.category for w in caught] == [foon.FoonWarning] * len(r.warnings)
    s = f.stats()
    assert s["functional_units"] == len(r.fus)
    assert s["objects"] == len(r.objects)
    assert s["produced_objects"] == sum(1 for o in range(len(r.objects)) if r.producers(o))
    assert s["motions"] == len({fu.motion for fu in r.fus})
    assert [(w[1], w[3]) for w in f.warnings] == r.warnings
    # Objects in the same id order with the same identities.
    for i in range(0, len(r.objects), max(1, len(r.objects) // 50)):
        assert f.object(i).identity() == r.objects[i]


def test_duplicate_units_are_dropped_in_the_lab_history() -> None:
    need_shared()
    [path] = DATA.glob("lab_history/FOON_sakib_2021-10-05_4640080.txt")
    f = foon.load(path)
    s = f.stats()
    assert s["duplicates_dropped"] == 77
    assert s["functional_units"] == 2350


def test_known_annotation_faults_are_warnings_with_lines() -> None:
    need_shared()
    [no_motion] = DATA.glob("subgraphs_sakib_TXT/0083-*.txt")
    with pytest.warns(foon.FoonWarning, match=r":500:1: .*no motion line.*\[no-motion\]"):
        foon.load(no_motion)
    [two] = DATA.glob("subgraphs_sakib_TXT/0032-*.txt")
    with pytest.warns(foon.FoonWarning, match=r":114:1: .*second motion line.*\[two-motions\]"):
        foon.load(two)
    with pytest.raises(foon.ParseError) as e:
        foon.load(two, strict=True)
    assert (e.value.line, e.value.column) == (114, 1)  # type: ignore[attr-defined]
