"""``.foonidx`` index files from Python: ``foon.load`` opens them (told by their magic, not
their name), plans from a mapped index equal plans from the parsed text (every data file and
generated FOONs, every method), the bytes round-trip, the fingerprint is the content's,
pickling reopens the file (or carries the bytes), hostile files are clear errors, and
``foon index`` builds one index from many files."""

from __future__ import annotations

import argparse
import os
import pickle
import struct
import tempfile
import warnings
from pathlib import Path

import foon
import pytest
from conftest import DATA, Course, need_shared
from foon._cli_index import add_index_options, cmd_index
from hypothesis import HealthCheck, given, settings
from test_differential import GenFoon, gen_foons

FOLDERS = (
    "lab_history",
    "subgraphs_foon_api_FOON-111",
    "subgraphs_misc",
    "subgraphs_sakib_TXT",
    "subgraphs_sakib_JSON",
)


def quiet_load(path: str | Path) -> foon.Foon:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", foon.FoonWarning)
        return foon.load(path)


def data_files() -> list[Path]:
    files = [DATA / "FOON.txt"]
    for d in FOLDERS:
        files += sorted(p for p in (DATA / d).iterdir() if p.is_file())
    return files


def summary(t: foon.TaskTree) -> tuple[object, ...]:
    return (t.goal_id, t.units, t.solved, t.height, t.cost, t.missing, t.cycle, t.unresolved)


def all_plans(
    f: foon.Foon, goals: list[int], kitchen: foon.Kitchen, utensils: list[str]
) -> list[tuple[object, ...]]:
    out: list[tuple[object, ...]] = []
    for method in foon.METHODS:
        for compat in (None, "course") if not method.startswith("optimal") else (None,):
            trees = f.plan_many(
                goals, kitchen, method, compat=compat, utensils=utensils, default_rate=0.9
            )
            out += [(method, compat, *summary(t)) for t in trees]
    return out


def spread(f: foon.Foon, n: int) -> list[int]:
    produced = [o for o in range(f.object_count) if f.producers(o)]
    step = max(1, -(-len(produced) // max(n, 1)))
    return produced[::step]


def index_of(f: foon.Foon, tmp: Path, name: str = "x.foonidx") -> foon.Foon:
    path = tmp / name
    f.write_index(path)
    return foon.load(path)


def test_every_data_file_plans_the_same_from_its_index(tmp_path: Path, course: Course) -> None:
    need_shared()
    checked = 0
    for k, path in enumerate(data_files()):
        try:
            text = quiet_load(path)
        except foon.FoonError:
            continue
        mapped = index_of(text, tmp_path, f"{k}.foonidx")
        assert mapped.index_path == str(tmp_path / f"{k}.foonidx")
        assert mapped.fingerprint == text.fingerprint
        assert mapped.warnings == []
        assert mapped.to_text() == text.to_text()
        goals = spread(text, 25 if k == 0 else 3)
        assert all_plans(mapped, goals, course.kitchen, course.utensils) == all_plans(
            text, goals, course.kitchen, course.utensils
        ), path
        checked += 1
    assert checked > 300


def test_index_bytes_round_trip(tmp_path: Path) -> None:
    need_shared()
    f = foon.load(DATA / "FOON.txt")
    a = tmp_path / "a.foonidx"
    b = tmp_path / "b.foonidx"
    f.write_index(a)
    g = foon.load(a)
    g.write_index(b)
    assert a.read_bytes() == b.read_bytes()
    assert g.fingerprint == f.fingerprint and len(g.fingerprint) == 32
    assert g.stats() == {**f.stats(), "duplicates_dropped": 0, "warnings": 0}
    g.verify_checksum()
    # The magic decides, not the name.
    c = tmp_path / "course.txt"
    c.write_bytes(a.read_bytes())
    assert foon.Foon.load(c).index_path == str(c)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(gen_foons())
def test_generated_foons_plan_the_same_from_their_index(g: GenFoon) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", foon.FoonWarning)
        text = foon.Foon.from_text(g.text, path="gen.foon")
    data = text._native.to_bytes()
    again = foon.Foon(foon._foon.Foon.from_bytes(data))
    assert again == text and again.fingerprint == text.fingerprint
    with tempfile.TemporaryDirectory() as d:
        mapped = index_of(text, Path(d))
        assert mapped.fingerprint == text.fingerprint
        raw = [o for o in range(text.object_count) if not text.producers(o)]
        kitchen = foon.Kitchen(text.object(o) for o in raw[::2])
        goals = list(range(text.object_count))
        assert all_plans(mapped, goals, kitchen, ["bowl"]) == all_plans(
            text, goals, kitchen, ["bowl"]
        )


AWKWARD = (
    "O\tonion\nS\twhole\nM\tpeel\nO\tonion\nS\tpeeled\n//\n"
    "O\tonion\nS\twhole\nM\tpeel\nO\tonion\nS\tpeeled\n//\n"
    "O\tbowl\nO\tonion\nS\tsmall\n//\n"
    "O\tonion\nS\tpeeled\nM\tchop\nO\tonion\nS\tchopped\n"
)


def test_pickles_carry_bytes_or_reopen_the_file(tmp_path: Path) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", foon.FoonWarning)
        text = foon.Foon.from_text(AWKWARD, path="awkward.foon")
    assert text.warnings  # a unit without a motion, an unterminated one
    back = pickle.loads(pickle.dumps(text))
    assert back == text and back.warnings == text.warnings
    assert back._native.duplicates() == text._native.duplicates()
    assert back._native.source == "awkward.foon" and back.index_path is None

    path = tmp_path / "awk.foonidx"
    text.write_index(path)
    mapped = foon.load(path)
    data = pickle.dumps(mapped)
    assert len(data) < 400  # the path and the fingerprint, not the index
    again = pickle.loads(data)
    assert again.index_path == str(path) and again.fingerprint == text.fingerprint
    assert again.to_text() == text.to_text()

    # The file changed: a clear error naming it.
    other = foon.Foon.from_text("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    other.write_index(path)
    with pytest.raises(foon.FoonError, match="changed since the FOON was pickled"):
        pickle.loads(data)
    # The file is gone.
    path.unlink()
    with pytest.raises(FileNotFoundError, match=r"awk\.foonidx"):
        pickle.loads(data)


def test_hostile_index_files_are_clear_errors(tmp_path: Path) -> None:
    f = foon.Foon.from_text("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    good = tmp_path / "good.foonidx"
    f.write_index(good)
    data = good.read_bytes()
    cases = {
        "short": data[:60],
        "cut": data[:-8],
        "future": data[:8] + struct.pack("<I", 9) + data[12:],
        "flipped": data[:300] + bytes([data[300] ^ 0xFF]) + data[301:],
    }
    for name, bad in cases.items():
        p = tmp_path / f"{name}.foonidx"
        p.write_bytes(bad)
        with pytest.raises(foon.FoonError) as e:
            foon.load(p)
        msg = str(e.value)
        assert msg.startswith(str(p) + ": ") and "\n" not in msg, msg
    with pytest.raises(foon.FoonError, match="newer than this foon reads"):
        foon.load(tmp_path / "future.foonidx")
    # A flipped byte of the data is caught by the checksum on request.
    start = struct.unpack_from("<Q", data, 56)[0]
    p = tmp_path / "data.foonidx"
    text_at = data.index(b"crack", start)
    p.write_bytes(data[:text_at] + b"Crack" + data[text_at + 5 :])
    g = foon.load(p)
    with pytest.raises(foon.FoonError, match="checksum mismatch"):
        g.verify_checksum()


def run_index(*argv: str) -> int:
    ap = argparse.ArgumentParser(prog="foon index")
    add_index_options(ap)
    return cmd_index(ap.parse_args(list(argv)))


def test_cli_index_builds_one_index_from_many_sources(tmp_path: Path) -> None:
    need_shared()
    folder = DATA / "subgraphs_sakib_TXT"
    out = tmp_path / "all.foonidx"
    assert run_index(str(folder), str(DATA / "FOON.txt"), "-o", str(out)) == 0
    f = foon.load(out)
    listed = sorted(str(folder / n) for n in os.listdir(folder) if n.endswith((".txt", ".json")))
    names = [*listed, str(DATA / "FOON.txt")]
    assert len(names) == 112
    # Units come in the order of their files: the folder's, sorted by name, then FOON.txt.
    kept_from = [names.index(f.sources(i)[0][0]) for i in range(f.fu_count)]
    assert kept_from == sorted(kept_from) and kept_from[-1] == len(names) - 1
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", foon.FoonWarning)
        want = foon.Foon.load_sources(names)
    assert f.fingerprint == want.fingerprint
    assert f._native.source == names[0]
    # The same FUs as loading every file and keeping first copies.
    assert f.fu_count >= quiet_load(DATA / "FOON.txt").fu_count
    # Never over an input; an empty folder is an error.
    src = tmp_path / "a.txt"
    src.write_text("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    from foon.cli import UsageError

    with pytest.raises(UsageError, match="over an input"):
        run_index(str(src), "-o", str(src))
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValueError, match="no FOON files"):
        run_index(str(empty), "-o", str(tmp_path / "e.foonidx"))
    leftovers = [n for n in os.listdir(tmp_path) if n.endswith(".tmp")]
    assert leftovers == []


def test_check_names_a_corrupt_index_file_without_a_fake_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from foon.cli import main

    f = foon.Foon.from_text("O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n")
    good = tmp_path / "good.foonidx"
    f.write_index(good)
    data = good.read_bytes()
    cut = tmp_path / "cut.foonidx"
    cut.write_bytes(data[:-8])
    # A flipped letter of the data: the index opens, the checksum check of `foon check` fails.
    start = struct.unpack_from("<Q", data, 56)[0]
    text_at = data.index(b"crack", start)
    sum_bad = tmp_path / "sum.foonidx"
    sum_bad.write_bytes(data[:text_at] + b"Crack" + data[text_at + 5 :])
    for p, why in ((cut, "truncated: the header says"), (sum_bad, "checksum mismatch")):
        (finding,) = foon.check(p)
        assert (finding.path, finding.line, finding.column) == (str(p), 0, 0)
        assert (finding.severity, finding.code) == ("error", "bad-index")
        assert finding.message.startswith(why), finding.message
        assert str(finding) == f"{p}: error: {finding.message} [bad-index]"
        assert main(["check", str(p)]) == 1
        out = capsys.readouterr().out
        assert out == f"{p}: error: {finding.message} [bad-index]\n", out
    # A good index has no findings; a text file's findings keep their line and column.
    assert foon.check(good) == []
    txt = tmp_path / "a.txt"
    txt.write_text("O\tegg\nS\twhole\nO\tegg\nS\tcracked\n//\n")
    assert all(str(x).startswith(f"{txt}:{x.line}:{x.column}: ") for x in foon.check(txt))
    assert all(x.line > 0 for x in foon.check(txt))
