"""The commands of large merged FOONs, end to end through ``foon.cli.main``: ``merge``,
``stats --provenance``, ``synth``."""

from __future__ import annotations

import json
from pathlib import Path

import foon
import pytest
from foon.cli import main

Capture = pytest.CaptureFixture[str]

UNIT_A = "O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n"
UNIT_B = "O\tbread\nS\twhole\nM\tslice\nO\tbread\nS\tsliced\n//\n"


def run(argv: list[str], capsys: Capture) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_merge_then_stats_provenance(tmp_path: Path, capsys: Capture) -> None:
    (tmp_path / "a.txt").write_text(UNIT_A + UNIT_B)
    (tmp_path / "b.txt").write_text(UNIT_B)
    out = tmp_path / "merged.txt"
    code, _, err = run(
        ["merge", str(tmp_path / "a.txt"), str(tmp_path / "b.txt"), "-o", str(out)], capsys
    )
    assert code == 0, err
    merged = foon.load(out)
    assert merged.fu_count == 2
    code, text, err = run(["stats", "--provenance", str(out)], capsys)
    assert code == 0, err
    lines = [s for s in text.splitlines() if s.startswith("unit ")]
    assert lines[0] == f"unit 0: support 1: {tmp_path / 'a.txt'}:1"
    assert lines[1] == f"unit 1: support 2: {tmp_path / 'a.txt'}:7, {tmp_path / 'b.txt'}:1"
    code, text, err = run(["stats", "--provenance", "--json", str(out)], capsys)
    assert code == 0, err
    rows = json.loads(text)
    prov = rows[0]["provenance"]
    assert [p["support"] for p in prov] == [1, 2]
    assert prov[1]["sources"] == [[str(tmp_path / "a.txt"), 7], [str(tmp_path / "b.txt"), 1]]


def test_merge_refuses_to_write_over_an_input(tmp_path: Path, capsys: Capture) -> None:
    a = tmp_path / "a.txt"
    a.write_text(UNIT_A)
    code, _, err = run(["merge", str(a), "-o", str(a)], capsys)
    assert code != 0
    assert "foon: error:" in err and "Traceback" not in err
    assert a.read_text() == UNIT_A


def test_synth_writes_a_foon_of_the_size_asked(tmp_path: Path, capsys: Capture) -> None:
    out = tmp_path / "s.txt"
    code, _, err = run(["synth", "--units", "500", "--seed", "3", "-o", str(out), "-q"], capsys)
    assert code == 0, err
    assert foon.load(out).fu_count == 500


def test_merge_into_an_index_keeps_the_provenance(tmp_path: Path, capsys: Capture) -> None:
    (tmp_path / "a.txt").write_text(UNIT_A + UNIT_B)
    (tmp_path / "b.txt").write_text(UNIT_B)
    text, idx = tmp_path / "m.txt", tmp_path / "m.foonidx"
    inputs = [str(tmp_path / "a.txt"), str(tmp_path / "b.txt")]
    assert run(["merge", *inputs, "-o", str(text), "-q"], capsys)[0] == 0
    assert run(["merge", *inputs, "-o", str(idx), "-q"], capsys)[0] == 0
    from_text = run(["stats", "--provenance", str(text)], capsys)[1].splitlines()
    from_index = run(["stats", "--provenance", str(idx)], capsys)[1].splitlines()
    assert [s for s in from_text if s.startswith("unit ")] == [
        s for s in from_index if s.startswith("unit ")
    ]
    f = foon.load(idx)
    assert f.index_path is not None and f.support(1) == 2


def test_index_then_check_finds_a_corrupt_file(tmp_path: Path, capsys: Capture) -> None:
    src = tmp_path / "a.txt"
    src.write_text(UNIT_A + UNIT_B)
    idx = tmp_path / "a.foonidx"
    assert run(["index", str(src), "-o", str(idx), "-q"], capsys)[0] == 0
    assert run(["check", str(idx)], capsys)[0] == 0
    data = bytearray(idx.read_bytes())
    data[-1] ^= 0xFF  # the last data byte: the structure may hold, the checksum does not
    bad = tmp_path / "bad.foonidx"
    bad.write_bytes(bytes(data))
    code, out, err = run(["check", str(bad)], capsys)
    assert code == 1 and "bad.foonidx" in out and "Traceback" not in out + err
