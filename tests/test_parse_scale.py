"""Large merged FOONs from text: the renamed-copies family of benchmarks/parse_scale.py
loads as the pure-Python reference reads it (the same object and FU tables, the same
warnings), its copies share the kitchen's items and the utensils, and the text loads the same
from a file, from bytes and with CRLF line ends and a byte-order mark."""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import foon
import foon_reference as ref
import pytest
from conftest import DATA, need_shared
from hypothesis import given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import parse_scale


def copies_text(k: int) -> str:
    text = (DATA / "FOON.txt").read_text(encoding="utf-8")
    keep = parse_scale.shared_labels(DATA)
    return "".join(parse_scale.renamed_copy(text, i, keep) for i in range(k))


def tables(f: foon.Foon) -> tuple[object, ...]:
    objects = [f.object(i).identity() for i in range(f.object_count)]
    fus = [(f.fu(i).motion, tuple(f.fu(i).input_ids), tuple(f.fu(i).output_ids))
           for i in range(f.fu_count)]  # fmt: skip
    return objects, fus, [w[1:] for w in f.warnings]


def test_renamed_copies_load_as_the_reference_reads_them(tmp_path: Path) -> None:
    need_shared()
    text = copies_text(2)
    path = tmp_path / "copies.txt"
    path.write_text(text, encoding="utf-8")
    f = foon.load(path)
    rf = ref.parse(text)
    assert f.fu_count == len(rf.fus)
    assert f.object_count == len(rf.objects)
    for i in range(0, len(rf.objects), 7):
        assert f.object(i).identity() == rf.objects[i], i
        assert f.producers(i) == rf.producers(i), i
    for i in range(0, len(rf.fus), 5):
        assert list(f.fu(i).input_ids) == rf.fu_inputs(i), i
        assert list(f.fu(i).output_ids) == rf.fu_outputs(i), i
    assert [w[1] for w in f.warnings] == [line for line, _ in rf.warnings]
    one = foon.Foon.from_text((DATA / "FOON.txt").read_bytes())
    # The copies share raw items and utensils: fewer objects than three course FOONs, and
    # the units made only of shared objects are found once.
    assert one.object_count < f.object_count < 2 * one.object_count
    assert one.fu_count < f.fu_count < 2 * one.fu_count
    kitchen = foon.Kitchen.load(DATA / "kitchen.json")
    assert sum(f.find(o) is not None for o in kitchen) == sum(
        one.find(o) is not None for o in kitchen
    )


@settings(max_examples=10, deadline=None)
@given(k=st.integers(1, 2), crlf=st.booleans(), bom=st.booleans(), cut=st.integers(0, 2000))
def test_copies_load_the_same_from_a_file_and_from_bytes(
    tmp_path_factory: pytest.TempPathFactory, k: int, crlf: bool, bom: bool, cut: int
) -> None:
    """Any line ends, a byte-order mark, and a text that stops inside a unit (no last
    `//`): the file, the bytes and the LF text give the same tables and warnings."""
    need_shared()
    text = copies_text(k)
    lines = text.splitlines()
    text = "\n".join(lines[: len(lines) - cut])
    data = text.replace("\n", "\r\n") if crlf else text
    raw = (b"\xef\xbb\xbf" if bom else b"") + data.encode("utf-8")
    path = tmp_path_factory.mktemp("scale") / "t.txt"
    path.write_bytes(raw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", foon.FoonWarning)
        plain = tables(foon.Foon.from_text(text))
        assert tables(foon.load(path)) == plain
        assert tables(foon.Foon.from_text(raw)) == plain
