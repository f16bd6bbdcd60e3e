"""Bad input never crashes: the malformed-input corpus (``tests/malformed/cases.json``), huge
lines, missing files, and a chain a million units deep.

Every case must raise :class:`foon.ParseError` naming the file, line and column (1-based,
columns in characters) with a reason, and the CLI must exit 1 with one
``foon: error: <path>:<line>:<col>: ...`` line on stderr and no traceback. The same cases are
checked against the Rust core by ``rust/foon-core/tests/malformed.rs``.
"""

from __future__ import annotations

import json
import re
import time
from pathlib import Path
from typing import Any

import foon
import foon.cli
import pytest
from foon import _foon
from workloads import can_measure_memory, chain_text, load_memory

HERE = Path(__file__).resolve().parent / "malformed"
CASES: list[dict[str, Any]] = json.loads((HERE / "cases.json").read_text(encoding="utf-8"))

TINY_FOON = "O\tonion\nS\twhole\nM\tchop\nO\tonion\nS\tchopped\n//\n"
MIB = 1 << 20  # the parser's line limit (foon_core::parse::MAX_LINE_BYTES)


def _load(kind: str, path: Path, strict: bool = False) -> Any:
    if kind == "foon":
        return foon.load(path, strict=strict)
    if kind == "kitchen":
        return foon.Kitchen.load(path)
    if kind == "goal":
        return _foon.load_objects(str(path), "goal")
    if kind == "motions":
        return foon.MotionRates.load(path)
    if kind == "utensils":
        return foon.load_utensils(path)
    raise AssertionError(f"unknown kind {kind}")


def _cli_args(kind: str, path: Path, tmp_path: Path, strict: bool = False) -> list[str]:
    if kind == "foon":
        return ["stats", *(["--strict"] if strict else []), str(path)]
    tiny = tmp_path / "tiny.foon"
    tiny.write_text(TINY_FOON)
    flag = {
        "kitchen": "--kitchen",
        "goal": "--goals",
        "motions": "--motions",
        "utensils": "--utensils",
    }[kind]
    return ["plan", "--foon", str(tiny), flag, str(path)]


def _one_error_line(err: str, path: Path | str, line: int, column: int) -> str:
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert re.fullmatch(rf"foon: error: {re.escape(str(path))}:{line}:{column}: .+", lines[0]), err
    return lines[0]


def test_the_corpus_covers_what_it_must() -> None:
    assert len(CASES) >= 40
    files = {c["file"] for c in CASES}
    assert len(files) == len(CASES)
    for c in CASES:
        assert (HERE / c["file"]).is_file(), c["file"]
    dialects = {c["dialect"] for c in CASES if c["kind"] == "foon"}
    assert dialects == {"A", "A'", "B", "B'"}
    # Every warning kind that strict mode turns into an error, in every dialect.
    for dialect in dialects:
        warned = {
            c.get("warning") for c in CASES if c["kind"] == "foon" and c["dialect"] == dialect
        }
        assert {"no-motion", "two-motions", "unterminated"} <= warned, dialect
    kinds = {c["kind"] for c in CASES}
    assert kinds == {"foon", "kitchen", "goal", "motions", "utensils"}
    # Dialect B files really are CRLF.
    for c in CASES:
        if c["dialect"] == "B":
            assert b"\r\n" in (HERE / c["file"]).read_bytes()


@pytest.mark.parametrize("case", CASES, ids=[c["file"] for c in CASES])
def test_python_raises_parse_error_with_location(case: dict[str, Any]) -> None:
    path = HERE / case["file"]
    with pytest.raises(foon.ParseError) as info:
        _load(case["kind"], path, strict=case.get("strict", False))
    e = info.value
    assert (e.line, e.column) == (case["line"], case["column"]), str(e)
    assert e.path == str(path)
    assert case["reason_contains"] in e.reason, e.reason
    assert str(e).startswith(f"{path}:{case['line']}:{case['column']}: ")


@pytest.mark.parametrize("case", CASES, ids=[c["file"] for c in CASES])
def test_cli_exits_1_with_one_error_line(
    case: dict[str, Any], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = HERE / case["file"]
    rc = foon.cli.main(_cli_args(case["kind"], path, tmp_path, case.get("strict", False)))
    out, err = capsys.readouterr()
    assert rc == 1
    assert out == ""
    line = _one_error_line(err, path, case["line"], case["column"])
    assert case["reason_contains"] in line


STRICT_ONLY = [c for c in CASES if c.get("warning")]


@pytest.mark.parametrize("case", STRICT_ONLY, ids=[c["file"] for c in STRICT_ONLY])
def test_strict_only_faults_are_warnings_otherwise(
    case: dict[str, Any], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = HERE / case["file"]
    with pytest.warns(foon.FoonWarning, match=re.escape(f"[{case['warning']}]")) as rec:
        f = foon.load(path)
    assert any(f"{path}:{case['line']}:1: " in str(w.message) for w in rec)
    assert [(w[1], w[3]) for w in f.warnings] == [(case["line"], case["warning"])]
    rc = foon.cli.main(["stats", str(path)])
    out, err = capsys.readouterr()
    assert rc == 0 and "functional units" in out
    assert err.startswith(f"foon: warning: {path}:{case['line']}:1: ")
    assert "Traceback" not in err


NOTED = [c for c in CASES if c.get("note")]


@pytest.mark.parametrize("case", NOTED, ids=[c["file"] for c in NOTED])
def test_strict_only_annotation_faults_are_check_findings_otherwise(
    case: dict[str, Any], capsys: pytest.CaptureFixture[str]
) -> None:
    # A second container or ingredient list, an empty ingredient: loaded as the course does
    # (no load warning), reported by `foon check` with a code at the line and column.
    path = HERE / case["file"]
    f = foon.load(path)
    assert f.warnings == []
    found = [x for x in foon.check(path) if x.code == case["note"]]
    assert [(x.line, x.column, x.severity) for x in found] == [
        (case["line"], case["column"], "warning")
    ]
    rc = foon.cli.main(["check", str(path)])
    out, err = capsys.readouterr()
    assert rc == 1 and "Traceback" not in err
    assert f"{path}:{case['line']}:{case['column']}: warning: " in out
    assert f"[{case['note']}]" in out


def test_truncated_file_keeps_its_last_unit() -> None:
    # Ends mid-line ("S<TAB>sli", no newline, no "//"): the line is read as it is and the
    # unit is kept, with an "unterminated" warning.
    with pytest.warns(foon.FoonWarning, match="unterminated"):
        f = foon.load(HERE / "a_truncated_strict.foon")
    assert f.fu_count == 1
    assert f.fu(0).outputs == (foon.Object("apple", ("sli",)),)
    # Cut inside a UTF-8 sequence or an ingredient list, it is an error even without strict.
    for name, col in (("b_truncated_mid_utf8.foon", 8), ("bp_truncated_mid_list.foon", 12)):
        with pytest.raises(foon.ParseError) as info:
            foon.load(HERE / name)
        assert info.value.column == col


# --- huge lines ------------------------------------------------------------------------------

# (dialect, text before the huge line, line prefix, line suffix, newline, huge line number)
HUGE = [
    ("A", "O\tonion\nM\tchop\n//\n", "O\t", "", "\n", 4),
    ("A'", "O1\tonion\nM1\tchop\n//\n", "S1\t", "", "\n", 4),
    ("B", "# Source:\tx\n//\nO12\tonion\t1\n", "O13\t", "\t0", "\r\n", 4),
    ("B'", "O\tonion\t1\n", "M\t", "\t<1:10,1:11>", "\n", 2),
]


@pytest.mark.parametrize(
    ("dialect", "head", "pre", "post", "nl", "line"), HUGE, ids=[h[0] for h in HUGE]
)
def test_huge_line_is_an_error(
    dialect: str,
    head: str,
    pre: str,
    post: str,
    nl: str,
    line: int,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    huge = pre + "a" * (MIB + 1 - len(pre) - len(post)) + post
    assert len(huge) == MIB + 1
    path = tmp_path / f"huge_{dialect}.foon"
    path.write_bytes((head + huge + nl + "O\tx\n//\n").replace("\n", nl).encode())
    with pytest.raises(foon.ParseError) as info:
        foon.load(path)
    e = info.value
    assert (e.line, e.column, e.path) == (line, 1, str(path))
    assert "line is" in e.reason and str(MIB) in e.reason
    assert foon.cli.main(["stats", str(path)]) == 1
    _one_error_line(capsys.readouterr().err, path, line, 1)


def test_line_at_the_limit_is_accepted() -> None:
    # Exactly MAX_LINE_BYTES bytes before the CRLF: accepted (the \r does not count).
    pre, post = "O12\t", "\t1"
    line = pre + "a" * (MIB - len(pre) - len(post)) + post
    assert len(line) == MIB
    text = f"{line}\r\nM4\tchop\t1:10\t1:11\r\nO12\tb\t1\r\nS1\tcut\r\n//\r\n"
    f = foon.Foon.from_text(text.encode())
    assert f.fu_count == 1 and len(f.object(0).label) == MIB - 6


def test_hundred_megabyte_line_fails_fast() -> None:
    data = b"O\t" + b"x" * 100_000_000
    start = time.perf_counter()
    with pytest.raises(foon.ParseError) as info:
        foon.Foon.from_text(data)
    elapsed = time.perf_counter() - start
    e = info.value
    assert (e.line, e.column, e.path) == (1, 1, None)
    assert "100000002 bytes" in e.reason
    assert str(e).startswith("<string>:1:1: ")
    assert elapsed < 5.0, f"took {elapsed:.2f} s"


def test_hundred_megabyte_line_from_the_cli(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "huge.foon"
    with path.open("wb") as fh:
        fh.write(b"O\tonion\nM\tchop\n//\nO\t")
        fh.write(b"x" * 100_000_000)
        fh.write(b"\nM\tchop\n//\n")
    start = time.perf_counter()
    assert foon.cli.main(["stats", str(path)]) == 1
    elapsed = time.perf_counter() - start
    out, err = capsys.readouterr()
    assert out == ""
    assert "100000002 bytes" in _one_error_line(err, path, 4, 1)
    assert elapsed < 10.0, f"took {elapsed:.2f} s"


# --- missing files ---------------------------------------------------------------------------


@pytest.mark.parametrize("kind", ["foon", "kitchen", "goal", "motions", "utensils"])
def test_missing_file(kind: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    missing = tmp_path / "does-not-exist.txt"
    with pytest.raises(FileNotFoundError) as info:
        _load(kind, missing)
    assert str(missing) in str(info.value)
    rc = foon.cli.main(_cli_args(kind, missing, tmp_path))
    err = capsys.readouterr().err
    assert rc == 1
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"foon: error: {missing}"), err


# --- a chain a million units deep ------------------------------------------------------------

DEPTH = 1_000_000


@pytest.fixture(scope="module")
def chain() -> foon.Foon:
    # o0 -> o1 -> ... -> o1000000, one unit each; parsed and planned without recursion.
    f = foon.Foon.from_text(chain_text(DEPTH))
    assert f.fu_count == DEPTH and f.object_count == DEPTH + 1
    return f


@pytest.mark.parametrize(
    ("method", "options"),
    [
        ("ids", {}),
        ("greedy-success", {"default_rate": 0.5}),
        ("greedy-inputs", {}),
        ("bfs", {"compat": "course"}),
        ("optimal-units", {}),
    ],
)
def test_deep_chain_plans_without_crashing(
    chain: foon.Foon, method: str, options: dict[str, Any]
) -> None:
    kitchen = foon.Kitchen([foon.Object("item", ("s0",))])
    goal = foon.Object("item", (f"s{DEPTH}",))
    t = chain.plan(goal, kitchen, method, **options)
    assert t.solved
    assert t.fu_count == DEPTH
    if method != "bfs":
        # Sound methods list the units in execution order.
        assert t.units[:3] == [0, 1, 2] and t.units[-1] == DEPTH - 1
        assert t.height == DEPTH
    else:
        assert t.units[0] == 0 and t.units[-1] == DEPTH - 1
    if method == "optimal-units":
        assert t.cost == DEPTH


# --- memory ----------------------------------------------------------------------------------


@pytest.mark.skipif(not can_measure_memory(), reason="needs /proc (Linux)")
def test_memory_is_proportional_to_the_input(tmp_path: Path) -> None:
    """Loading a chain (every object distinct: the most index per byte of text) takes memory
    in proportion to the file. From 40,000 to 400,000 units, each added byte of input adds at
    most 4 bytes of index (every column counted: objects, units, provenance, identity hashes
    and their tables, which are kept at most half full) and at most 6 bytes of peak memory
    (the index and the builder's tables; the file is read as it is parsed), and the larger
    load stays within those bounds as a whole."""
    measured = []
    for n in (40_000, 400_000):
        path = tmp_path / f"chain{n}.foon"
        path.write_text(chain_text(n))
        index_bytes, peak = load_memory("foon", path)
        measured.append((path.stat().st_size, index_bytes, peak))
    (size0, index0, peak0), (size1, index1, peak1) = measured
    assert index1 - index0 <= 4 * (size1 - size0), measured
    assert peak1 - peak0 <= 6 * (size1 - size0), measured
    assert index1 <= 4 * size1 and peak1 <= 6 * size1, measured
