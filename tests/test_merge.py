"""``foon.merge``: many FOONs into one at an identity level, with provenance and support.

Checked against ``merge_reference`` (a plain pure-Python merge of the same rules) on the
lab's subgraph sets and on generated sources, and against the lab's own merged universal
FOONs in ``lab_history/``, where the differences are explained.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections import Counter
from pathlib import Path

import foon
import foon_reference as ref
import merge_reference as mref
import pytest
from conftest import DATA, need_shared
from foon import _merge
from foon._cli_merge import add_merge_options, cmd_merge
from hypothesis import given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import course_parser

TEXT_SETS = ("subgraphs_sakib_TXT", "subgraphs_foon_api_FOON-111")
ALL_SETS = (*TEXT_SETS, "subgraphs_sakib_JSON")
#: The lab's universal FOON that the sakib subgraph sets were merged into (found by content:
#: it shares the most units with them, see test_which_lab_file).
LAB_UNIVERSAL = "lab_history/FOON_sakib_2021-10-18_3e2e427.txt"

Key = tuple[str, tuple[ref.Identity, ...], tuple[ref.Identity, ...]]


def files_of(folder: Path) -> list[Path]:
    return sorted(p for p in folder.iterdir() if p.suffix.lower() in (".txt", ".json"))


def ident(f: foon.Foon, o: int) -> ref.Identity:
    return f.object(o).identity()


def full_keys(f: foon.Foon) -> list[Key]:
    """Each unit as (motion, sorted input identities, sorted output identities)."""
    ids = [ident(f, o) for o in range(f.object_count)]
    out = []
    for i in range(f.fu_count):
        u = f.fu(i)
        ins = tuple(sorted((ids[o] for o in u.input_ids), key=repr))
        outs = tuple(sorted((ids[o] for o in u.output_ids), key=repr))
        out.append((u.motion, ins, outs))
    return out


def level1(k: Key) -> tuple[str, tuple[str, ...], tuple[str, ...]]:
    return (k[0], tuple(sorted(o[0] for o in k[1])), tuple(sorted(o[0] for o in k[2])))


def check_against_reference(f: foon.Foon, kept: list[mref.Kept]) -> None:
    """The core's merge and the reference's agree unit by unit: text, sources, support."""
    assert f.fu_count == len(kept)
    for i, k in enumerate(kept):
        assert f.fu_text(i) == mref.unit_text(k.unit)
        assert f.sources(i) == k.origins
        assert f.support(i) == k.support
    assert f.object_count == len(mref.objects(kept))
    assert f.stats()["motions"] == len(mref.motions(kept))


# --- the lab's subgraph sets ---------------------------------------------------------------


@pytest.mark.parametrize("level", [3, 2, 1])
@pytest.mark.parametrize("name", TEXT_SETS)
def test_real_text_sets_equal_reference(name: str, level: int) -> None:
    need_shared()
    folder = DATA / name
    f, report = _merge.merge_report(folder, level=level)
    sources = [(str(p), p.read_text(encoding="utf-8")) for p in files_of(folder)]
    kept = mref.merge(sources, level)
    check_against_reference(f, kept)
    read = sum(len(mref.read_units(t)) for _, t in sources)
    assert report.sources == len(sources) == 111
    assert report.units_read == read
    assert report.kept == len(kept)
    assert report.units_read - report.duplicates - report.same_at_level == report.kept
    assert (report.same_at_level == 0) == (level == 3)


@pytest.mark.parametrize("k", [2, 3])
def test_real_min_support(k: int) -> None:
    need_shared()
    folders = [DATA / n for n in TEXT_SETS]
    f, report = _merge.merge_report(*folders, level=1, min_support=k)
    sources = [(str(p), p.read_text(encoding="utf-8")) for d in folders for p in files_of(d)]
    kept = mref.merge(sources, 1, k)
    check_against_reference(f, kept)
    assert report.below_support == len(mref.merge(sources, 1)) - len(kept) > 0
    assert all(f.support(i) >= k for i in range(f.fu_count))


def test_json_set_equals_text_set_but_for_its_faults() -> None:
    """The sakib JSON and TXT subgraphs are the same recipes: their merges share all units but
    four of the JSON merge and three of the TXT merge, and the TXT files' faults explain each:
    - 0032 (cheeseburger): the TXT unit with two motion lines is dropped; JSON has it;
    - 0064 (goat cheese frittata), twice: the TXT line ``S<TAB>off<TAB>`` gives the stove the
      state ``off`` (an empty last field is ignored), which the JSON stove lacks;
    - 0083 (pastel): the TXT unit without a motion line is dropped and its objects are, in the
      JSON file, inputs of the next unit (a ``pour``).
    """
    need_shared()
    fj, rj = _merge.merge_report(DATA / "subgraphs_sakib_JSON")
    ft, rt = _merge.merge_report(DATA / "subgraphs_sakib_TXT")
    assert (rj.faulty, rt.faulty) == (0, 2)
    assert (rj.kept, rt.kept) == (2376, 2375)
    assert rj.units_read == rt.units_read + 1
    jk_list, tk_list = full_keys(fj), full_keys(ft)
    jk, tk = Counter(jk_list), Counter(tk_list)
    only_j, only_t = list((jk - tk).elements()), list((tk - jk).elements())
    assert (len(only_j), len(only_t)) == (4, 3)

    def file_of(f: foon.Foon, keys: list[Key], k: Key) -> str:
        return Path(f.sources(keys.index(k))[0][0]).stem[:4]

    by_file_j: dict[str, list[Key]] = {}
    for k in only_j:
        by_file_j.setdefault(file_of(fj, jk_list, k), []).append(k)
    assert sorted((n, len(v)) for n, v in by_file_j.items()) == [
        ("0032", 1),
        ("0064", 2),
        ("0083", 1),
    ]
    assert all(file_of(ft, tk_list, k) in ("0064", "0083") for k in only_t)
    two_motions = [w for w in ft.warnings if w[3] == "two-motions"]
    assert [Path(str(w[0])).stem[:4] for w in two_motions] == ["0032"]
    for k in only_t:
        if file_of(ft, tk_list, k) == "0064":
            (j,) = [j for j in by_file_j["0064"] if level1(j) == level1(k)]
            a, b = set(k[1] + k[2]) - set(j[1] + j[2]), set(j[1] + j[2]) - set(k[1] + k[2])
            assert {o[0] for o in a | b} == {"stove"}
            assert {(o[2], o[3]) for o in a} == {(o[2], o[3]) for o in b}
            assert all(o[1] == ("off",) for o in a) and all(o[1] == () for o in b)
        else:
            (j,) = by_file_j["0083"]
            assert j[0] == k[0] == "pour"
            extra = Counter(o[0] for o in j[1]) - Counter(o[0] for o in k[1])
            assert sorted(extra.elements()) == ["bowl", "egg", "egg white and yolk"]
    no_motion = [w for w in ft.warnings if w[3] == "no-motion"]
    assert [Path(str(w[0])).stem[:4] for w in no_motion] == ["0083"]


@pytest.mark.parametrize("name", ALL_SETS)
def test_counts_per_level_shrink(name: str) -> None:
    need_shared()
    rows = [_merge.merge_report(DATA / name, level=lv)[1] for lv in (3, 2, 1)]
    assert rows[0].kept >= rows[1].kept >= rows[2].kept > 0
    assert rows[0].objects >= rows[1].objects >= rows[2].objects
    for r in rows:
        assert r.kept == r.units_read - r.duplicates - r.same_at_level
        assert r.motions > 100


def test_which_lab_file() -> None:
    """By content: the sakib subgraph sets are the sources of the lab's universal FOON of
    2021-10-18 (it shares 99% of their units, more than any other lab_history FOON); the
    foon_api FOON-111 set is a later relabelled annotation that no lab_history FOON merges
    (none shares a third of its units)."""
    need_shared()
    labs = sorted((DATA / "lab_history").glob("*FOON*.txt"))
    lab_keys = {p.name: set(full_keys(foon.load(p))) for p in labs}
    for name in ("subgraphs_sakib_JSON", "subgraphs_sakib_TXT"):
        mk = set(full_keys(_merge.merge(DATA / name)))
        best = max(lab_keys, key=lambda n: len(mk & lab_keys[n]))
        assert best == Path(LAB_UNIVERSAL).name
        assert len(mk & lab_keys[best]) > 0.99 * len(mk)
    api = set(full_keys(_merge.merge(DATA / "subgraphs_foon_api_FOON-111")))
    assert max(len(api & k) for k in lab_keys.values()) < len(api) / 3


def test_lab_universal_differs_only_by_states() -> None:
    """The JSON subgraph merge and the lab's universal FOON have the same number of units
    and share all but 17; each of the 17 is the same unit at level 1 (same motion, same
    labels): in 16 the lab's file lacks a state the subgraph gives an object (``dried``
    peanut, ``powder`` cocoa, ``creamy`` cream, ``liquid`` tomato juice and coconut milk,
    ``ground`` pepper) and in one it writes the container ``in bowl`` for ``bowl``."""
    need_shared()
    merged = _merge.merge(DATA / "subgraphs_sakib_JSON")
    lab = foon.load(DATA / LAB_UNIVERSAL)
    assert merged.fu_count == lab.fu_count == 2376
    mk, lk = Counter(full_keys(merged)), Counter(full_keys(lab))
    only_m, only_l = list((mk - lk).elements()), list((lk - mk).elements())
    assert len(only_m) == len(only_l) == 17
    assert Counter(map(level1, only_m)) == Counter(map(level1, only_l))
    lacks_state = in_bowl = 0
    for m in only_m:
        (lab_unit,) = [u for u in only_l if level1(u) == level1(m)]
        a, b = set(m[1] + m[2]), set(lab_unit[1] + lab_unit[2])
        for x in a - b:
            same = [y for y in b - a if y[0] == x[0] and y[2] == x[2]]
            if [y for y in same if y[1] == x[1] and y[3] == f"in {x[3]}"]:
                assert x[3] == "bowl"
                in_bowl += 1
            else:
                (y,) = [y for y in same if y[3] == x[3]]
                assert set(y[1]) < set(x[1]), (x, y)
                lacks_state += 1
    assert in_bowl == 1
    assert lacks_state >= 16


# --- the text form: every reader reads it, provenance comes back ---------------------------


@pytest.mark.parametrize("level", [3, 1])
def test_merged_text_reads_back(tmp_path: Path, level: int) -> None:
    need_shared()
    out = tmp_path / "merged.txt"
    folders = [DATA / "subgraphs_sakib_TXT", DATA / "subgraphs_foon_api_FOON-111"]
    f = _merge.merge(*folders, level=level, min_support=1, out=out)
    text = out.read_text(encoding="utf-8")
    assert text.startswith("# foon merge:\t")
    back = _merge.load_merged(out)
    assert back.fu_count == f.fu_count
    for i in range(f.fu_count):
        assert back.fu_text(i) == f.fu_text(i)
        assert back.sources(i) == f.sources(i)
        assert back.support(i) == f.support(i)
    assert _merge.provenance_lines(back) == _merge.provenance_lines(f)
    # Written again, the text is the same bytes (the header line is the file's own).
    header = text.split("\n", 1)[0].removeprefix("# foon merge:\t")
    assert _merge.merged_text(back, header) == text
    # The same merge again writes the same bytes.
    again = tmp_path / "again.txt"
    _merge.merge(*folders, level=level, out=again)
    assert again.read_bytes() == out.read_bytes()
    # A plain load reads the same units (the provenance lines are comments).
    plain = foon.load(out)
    assert [plain.fu_text(i) for i in range(plain.fu_count)] == [
        f.fu_text(i) for i in range(f.fu_count)
    ]
    # The pure-Python reference parser reads the same units.
    r = ref.parse(text)
    assert [ref.fu_text(u) for u in r.fus] == [f.fu_text(i) for i in range(f.fu_count)]


def test_course_parser_reads_merged_text(tmp_path: Path) -> None:
    """The course parser reads the merged text (provenance lines included) as the same units
    and objects."""
    need_shared()
    out = tmp_path / "merged.txt"
    some = files_of(DATA / "subgraphs_foon_api_FOON-111")[:12]
    f = _merge.merge(*some, DATA / "subgraphs_misc", out=out)
    units, objects, _ = course_parser.parse(str(out))
    assert len(units) == f.fu_count > 50
    assert len(objects) == f.object_count


def test_course_parser_passes_over_provenance_silently(tmp_path: Path) -> None:
    """Every provenance line has a TAB after its marker: the course parser warns about a
    line without one, and passes over a line that starts with neither O, S nor M."""
    need_shared()
    text = _merge.merged_text(_merge.merge(DATA / "subgraphs_misc"), "x")
    for line in text.splitlines():
        if line.startswith("#"):
            assert "\t" in line and not line.startswith("# Source:")


def test_strange_paths_round_trip() -> None:
    names = ["a\tb.txt", "c\\d:7.txt", "new\nline.txt", "e.txt"]
    unit = "O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n"
    other = "O\tbread\nM\tslice\nO\tbread\nS\tsliced\n//\n"
    f, _ = _merge.merge_texts(
        [(names[0], unit), (names[1], other + unit), (names[2], unit), (names[3], other)]
    )
    back = _merge.parse_merged(_merge.merged_text(f))
    assert [back.sources(i) for i in range(back.fu_count)] == [
        f.sources(i) for i in range(f.fu_count)
    ]
    assert f.sources(0) == [(names[0], 1), (names[1], 6), (names[2], 1)]
    assert (f.support(0), f.support(1)) == (3, 2)


def test_strict_merge_fails_on_a_fault() -> None:
    need_shared()
    with pytest.raises(foon.ParseError, match="strict"):
        _merge.merge(DATA / "subgraphs_sakib_TXT", strict=True)


def test_sources_of_a_plain_load() -> None:
    need_shared()
    f = foon.load(DATA / "FOON.txt")
    assert f.sources(0) == [(str(DATA / "FOON.txt"), f.fu(0).line)]
    assert f.support(0) == 1
    with pytest.raises(IndexError):
        f.sources(f.fu_count)


def test_plain_text_has_no_provenance() -> None:
    text = "O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n"
    f = _merge.parse_merged(text, path="plain.txt")
    assert f.sources(0) == [("plain.txt", 1)]


def test_bad_provenance_is_an_error_naming_its_line() -> None:
    text = "# source:\ta.txt\nO\tegg\nM\tcrack\nO\tegg\nS\tcracked\n//\n"
    with pytest.raises(foon.ParseError) as e:
        _merge.parse_merged(text, path="m.txt")
    assert e.value.line == 1
    disorder = (
        "# input:\ta\n# input:\tb\n# source:\tb:1\nO\tx\nM\tm\nO\tx\nS\ts\n//\n"
        "# source:\ta:1\nO\ty\nM\tm\nO\ty\nS\ts\n//\n"
    )
    with pytest.raises(foon.ParseError, match="reading order") as e:
        _merge.parse_merged(disorder, path="m.txt")
    assert e.value.line == 10


# --- generated sources: the core equals the reference ---------------------------------------

LABELS = ("egg", "bowl", "salt", "pan")
STATES = ("whole", "cracked", "hot", "mixed")
MOTIONS = ("mix", "pour", "heat")


@st.composite
def objects_st(draw: st.DrawFn) -> str:
    label = draw(st.sampled_from(LABELS))
    states = draw(st.lists(st.sampled_from(STATES), max_size=2))
    lines = [f"O\t{label}"] + [f"S\t{s}" for s in states]
    ing = draw(st.lists(st.sampled_from(LABELS), max_size=2))
    if ing:
        lines.append("S\tcontains\t{" + ",".join(ing) + "}")
    if draw(st.booleans()):
        lines.append(f"S\tin\t[{draw(st.sampled_from(LABELS))}]")
    return "\n".join(lines) + "\n"


@st.composite
def unit_st(draw: st.DrawFn) -> str:
    ins = draw(st.lists(objects_st(), min_size=1, max_size=3))
    outs = draw(st.lists(objects_st(), min_size=1, max_size=2))
    return "".join(ins) + f"M\t{draw(st.sampled_from(MOTIONS))}\n" + "".join(outs) + "//\n"


@st.composite
def sources_st(draw: st.DrawFn) -> list[tuple[str, str]]:
    pool = draw(st.lists(unit_st(), min_size=1, max_size=6))
    n = draw(st.integers(1, 5))
    out = []
    for s in range(n):
        picks = draw(st.lists(st.sampled_from(pool), max_size=8))
        noise = "# a comment\n\n" if draw(st.booleans()) else ""
        out.append((f"s{s}.txt", noise + "".join(picks)))
    return out


@settings(max_examples=150, deadline=None)
@given(sources_st(), st.sampled_from([1, 2, 3]), st.integers(1, 4))
def test_generated_merge_equals_reference(
    sources: list[tuple[str, str]], level: int, k: int
) -> None:
    f, report = _merge.merge_texts(sources, level=level, min_support=k)
    kept = mref.merge(sources, level, k)
    check_against_reference(f, kept)
    assert report.kept == len(kept)
    assert report.units_read == sum(len(mref.read_units(t)) for _, t in sources)
    back = _merge.parse_merged(_merge.merged_text(f, report.header))
    assert [back.fu_text(i) for i in range(back.fu_count)] == [
        f.fu_text(i) for i in range(f.fu_count)
    ]
    assert [back.sources(i) for i in range(back.fu_count)] == [k.origins for k in kept]


@settings(max_examples=40, deadline=None)
@given(sources_st())
def test_generated_merge_is_deterministic_and_levels_nest(sources: list[tuple[str, str]]) -> None:
    texts = [_merge.merged_text(_merge.merge_texts(sources, level=lv)[0]) for lv in (3, 2, 1)]
    assert texts[0] == _merge.merged_text(_merge.merge_texts(sources)[0])
    counts = [_merge.merge_texts(sources, level=lv)[1].kept for lv in (3, 2, 1)]
    assert counts[0] >= counts[1] >= counts[2]


def test_reference_reader_equals_foon_reference_on_real_text() -> None:
    """merge_reference's reader reads the units foon_reference.parse reads (after dropping
    repeated units, which the merge records instead)."""
    need_shared()
    for name in TEXT_SETS:
        for p in files_of(DATA / name):
            text = p.read_text(encoding="utf-8")
            first: dict[object, mref.Unit] = {}
            for u in mref.read_units(text):
                first.setdefault(mref.unit_key(u, 3), u)
            assert [mref.unit_text(u) for u in first.values()] == [
                ref.fu_text(u) for u in ref.parse(text).fus
            ]


# --- errors and the command ------------------------------------------------------------------


def test_bad_options_and_inputs(tmp_path: Path) -> None:
    a = tmp_path / "a.txt"
    a.write_text("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    with pytest.raises(ValueError, match="level"):
        _merge.merge(a, level=4)
    with pytest.raises(ValueError, match="min_support"):
        _merge.merge(a, min_support=0)
    with pytest.raises(ValueError, match="given twice"):
        _merge.merge(a, tmp_path)
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValueError, match="no FOON files"):
        _merge.merge(empty)
    with pytest.raises(ValueError, match="one of the inputs"):
        _merge.merge(a, out=a)
    with pytest.raises(FileNotFoundError):
        _merge.merge(tmp_path / "missing.txt")
    bad = tmp_path / "b.txt"
    bad.write_text("O\tegg\nX\toops\n")
    out = tmp_path / "out.txt"
    out.write_text("before")
    with pytest.raises(foon.ParseError) as e:
        _merge.merge(a, bad, out=out)
    assert (e.value.path, e.value.line) == (str(bad), 2)
    assert out.read_text() == "before"  # nothing written on failure
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.txt", "empty", "out.txt"]


def run_cli(argv: list[str]) -> int:
    p = argparse.ArgumentParser()
    add_merge_options(p)
    return cmd_merge(p.parse_args(argv))


def test_cli_summary_and_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    a = tmp_path / "a.txt"
    b = tmp_path / "b.json"
    a.write_text("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n" * 2)
    b.write_text(
        json.dumps(
            [
                {
                    "input_nodes": [{"label": "egg", "states": ["whole"]}],
                    "motion_node": "crack",
                    "output_nodes": [{"label": "egg", "states": ["cracked"]}],
                }
            ]
        )
    )
    out = tmp_path / "m.txt"
    assert run_cli([str(a), str(b), "-o", str(out)]) == 0
    line = capsys.readouterr().out
    assert line.splitlines() == [
        (
            "merged 2 sources at level 3: 3 units read, 1 kept (2 objects, 1 motions); "
            "dropped: 0 faulty, 2 duplicates"
        )
    ]
    assert run_cli([str(a), str(b), "-o", str(out), "--json", "--min-support", "2"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert (d["kept"], d["below_support"], d["output"]) == (1, 0, str(out))
    back = _merge.load_merged(out)
    assert back.sources(0) == [(str(a), 1), (str(a), 7), (str(b), 1)]
    assert run_cli([str(a), "-o", "-"]) == 0
    cap = capsys.readouterr()
    assert cap.out.startswith("# foon merge:") and cap.err.startswith("merged 1 sources")
    if os.path.exists("/dev/null"):
        assert run_cli([str(a), "-o", "/dev/null"]) == 0
