"""``foon.batch`` and ``foon batch`` with the local engine: the answers of every input format
equal the per-query reference and the whole-table ``plan_table``, whatever the chunking;
resume plans only what is missing; bad queries are rows, bad files are errors before any
output; an interrupted run leaves only whole partitions."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

import foon
from batch_files import Data, key_rows, read_parts, reference_row
from foon import _arrow, _batch
from foon.cli import main


@pytest.fixture(scope="module")
def data(tmp_path_factory: pytest.TempPathFactory) -> Data:
    return Data(tmp_path_factory.mktemp("batch"))


@pytest.fixture(scope="module")
def whole(data: Data) -> Any:
    """The whole query table answered in one ``plan_table`` call."""
    return _arrow.plan_table(data.foon, data.kitchens, data.table, motions=data.motions)


def run(data: Data, out: Path, kind: str = "parquet", **kw: Any) -> _batch.BatchSummary:
    kw.setdefault("chunk_size", 128)
    return foon.batch(
        data.path(kind), foon=data.index, kitchens=data.kitchens, out=out,
        motions=data.motions, **kw,
    )  # fmt: skip


def manifest(out: Path) -> dict[str, Any]:
    return json.loads((out / _batch.MANIFEST).read_text())  # type: ignore[no-any-return]


@pytest.mark.parametrize("kind", ["parquet", "csv", "jsonl"])
def test_formats_equal_reference(data: Data, whole: Any, tmp_path: Path, kind: str) -> None:
    s = run(data, tmp_path / "out", kind)
    got = read_parts(tmp_path / "out")
    assert got.schema == _arrow.RESULT_SCHEMA
    assert got.equals(whole)
    assert key_rows(got) == [reference_row(data, r) for r in data.rows]
    assert got.column("query_id").to_pylist() == [r["query_id"] for r in data.rows]
    assert s.queries == len(data.rows) and s.partitions == 5 and s.planned_partitions == 5
    assert s.solved == sum(got.column("solved").to_pylist())
    failures = [f for f in got.column("failure").to_pylist() if f is not None]
    assert s.failures == {c: failures.count(c) for c in set(failures)}
    m = manifest(tmp_path / "out")
    assert [e["rows"] for e in m["partitions"].values()] == [128, 128, 128, 128, 88]
    # The folder reads as one dataset (the manifest's name hides it from readers).
    assert pq.read_table(tmp_path / "out").equals(whole)


def test_bad_queries_are_rows(data: Data, whole: Any, tmp_path: Path) -> None:
    s = run(data, tmp_path / "out")
    rows = {r["query_id"]: r for r in read_parts(tmp_path / "out").to_pylist()}
    assert rows["q00005"]["failure"] == "unknown-kitchen"
    assert rows["q00011"]["failure"] == "goal-not-found"
    assert rows["q00017"]["failure"] == "unknown-method"
    assert rows["q00023"]["failure"] == "bad-option"
    for code in ("unknown-kitchen", "goal-not-found", "unknown-method", "bad-option"):
        assert s.failures[code] >= 1


@pytest.mark.parametrize("chunk", [1, 37, 600, 10_000])
def test_chunking_and_threads_change_nothing(
    data: Data, whole: Any, tmp_path: Path, chunk: int
) -> None:
    if chunk == 1:  # one query per partition: a slice of the file is enough
        sub = data.folder / "first40.parquet"
        if not sub.exists():
            pq.write_table(data.table.slice(0, 40), sub)
        s = foon.batch(sub, foon=data.index, kitchens=data.kitchens, out=tmp_path / "o",
                       motions=data.motions, chunk_size=1)  # fmt: skip
        assert s.partitions == 40
        assert read_parts(tmp_path / "o").equals(whole.slice(0, 40))
        return
    for threads in (1, 2):
        out = tmp_path / f"t{threads}"
        s = run(data, out, "csv", chunk_size=chunk, threads=threads)
        assert s.partitions == -(-len(data.rows) // chunk)
        assert read_parts(out).equals(whole)


def count_plans(monkeypatch: pytest.MonkeyPatch) -> list[list[str]]:
    """Every chunk ``plan_table`` is called with (its query ids), from now on (not the call
    on no rows that checks the settings)."""
    calls: list[list[str]] = []
    real = _arrow.plan_table

    def counting(f: Any, ks: Any, queries: Any, **kw: Any) -> Any:
        if queries.num_rows:
            calls.append(queries.column("query_id").to_pylist())
        return real(f, ks, queries, **kw)

    monkeypatch.setattr(_arrow, "plan_table", counting)
    return calls


def test_resume_plans_only_the_missing(
    data: Data, whole: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = tmp_path / "out"
    run(data, out)
    first = {p.name: p.read_bytes() for p in out.glob("part-*.parquet")}
    (out / "part-00002.parquet").unlink()
    calls = count_plans(monkeypatch)
    s = run(data, out)
    assert [c[0] for c in calls] == ["q00256"] and len(calls[0]) == 128
    assert (s.planned_partitions, s.kept_partitions, s.planned_queries) == (1, 4, 128)
    assert s.queries == len(data.rows)
    assert read_parts(out).equals(whole)
    assert {p.name: p.read_bytes() for p in out.glob("part-*.parquet")} == first
    # A partition whose bytes no longer match the manifest's checksum is planned again.
    p3 = out / "part-00003.parquet"
    p3.write_bytes(p3.read_bytes()[:-20] + b"\0" * 20)
    calls.clear()
    s = run(data, out)
    assert [c[0] for c in calls] == ["q00384"] and s.planned_partitions == 1
    assert read_parts(out).equals(whole)
    # Nothing missing: nothing planned.
    calls.clear()
    s = run(data, out)
    assert calls == [] and s.planned_partitions == 0 and s.throughput is None
    assert s.solved == sum(whole.column("solved").to_pylist())
    # resume=False plans everything again.
    s = run(data, out, resume=False)
    assert len(calls) == 5 and s.planned_partitions == 5


def test_other_inputs_are_an_error(data: Data, tmp_path: Path) -> None:
    out = tmp_path / "out"
    run(data, out)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    other = foon.KitchenSet({"full": data.kitchen_items["full"]})
    with pytest.raises(FileExistsError, match=r"other inputs.*kitchens"):
        foon.batch(data.parquet, foon=data.index, kitchens=other, out=out,
                   motions=data.motions, chunk_size=128)  # fmt: skip
    with pytest.raises(FileExistsError, match="chunk_size"):
        run(data, out, chunk_size=100)
    with pytest.raises(FileExistsError, match="settings"):
        foon.batch(data.parquet, foon=data.index, kitchens=data.kitchens, out=out,
                   chunk_size=128)  # fmt: skip
    with pytest.raises(FileExistsError, match="queries"):
        run(data, out, "csv")
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    s = run(data, out, "csv", resume=False)
    assert s.planned_partitions == 5


def test_a_folder_of_other_partitions_is_left_alone(data: Data, tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "part-00000.parquet").write_bytes(b"not ours")
    (out / "notes.txt").write_text("kept")
    with pytest.raises(FileExistsError, match=r"no _manifest\.json"):
        run(data, out)
    assert (out / "part-00000.parquet").read_bytes() == b"not ours"
    run(data, out, resume=False)
    assert (out / "notes.txt").read_text() == "kept"
    assert len(list(out.glob("part-*.parquet"))) == 5


def bad_files(folder: Path, data: Data) -> list[tuple[Path, str]]:
    """(file, the error it must give)."""
    cases: list[tuple[Path, str]] = []

    def add(name: str, content: str | bytes, message: str) -> None:
        p = folder / name
        if isinstance(content, bytes):
            p.write_bytes(content)
        else:
            p.write_text(content)
        cases.append((p, message))

    t = data.table
    p = folder / "no_goal.parquet"
    pq.write_table(t.drop_columns(["goal"]), p)
    cases.append((p, "no column 'goal'"))
    p = folder / "int_goal.parquet"
    pq.write_table(t.set_column(2, "goal", pa.array(range(t.num_rows))), p)
    cases.append((p, "'goal' must be strings"))
    p = folder / "null_id.parquet"
    ids = t.column("query_id").to_pylist()
    ids[300] = None
    pq.write_table(t.set_column(0, "query_id", pa.array(ids, pa.string())), p)
    cases.append((p, "null_id.parquet: row 301: the query has no query_id"))
    add("not.parquet", "query_id,kitchen_id\n", "not a readable Parquet file")
    lines = data.csv.read_text().splitlines(keepends=True)
    add(
        "short_row.csv",
        "".join([*lines[:400], '"q9","full"\n', *lines[400:]]),
        "short_row.csv:401:1: expected 5 fields, got 2",
    )
    add("no_method.csv", "query_id,kitchen_id,goal\nq1,full,x\n", "no column 'method'")
    jl = data.jsonl.read_text().splitlines(keepends=True)
    add(
        "bad.jsonl",
        "".join([*jl[:450], '{"query_id": "x", "kitchen_id": }\n', *jl[450:]]),
        "bad.jsonl:451:33: Expecting value",
    )
    add(
        "no_kitchen.jsonl",
        "".join([*jl[:20], '{"query_id": "x", "goal": "g", "method": "ids"}\n']),
        "no_kitchen.jsonl:21:1: the query has no 'kitchen_id'",
    )
    add(
        "list_goal.jsonl",
        '{"query_id": "x", "kitchen_id": "k", "goal": [1], "method": "ids"}\n',
        "list_goal.jsonl:1: 'goal' must be a string",
    )
    add("queries.txt", "", "unknown query file type '.txt'")
    # Bytes that are not UTF-8, late in a file (past the first chunk), in any column.
    raw = [x.encode() for x in jl]
    bad = b'{"query_id": "x", "kitchen_id": "full", "goal": "caf\xe9", "method": "ids"}\n'
    add("latin1_goal.jsonl", b"".join([*raw[:500], bad, *raw[500:]]),
        "latin1_goal.jsonl:501:53: not UTF-8")  # fmt: skip
    add(
        "latin1_id.jsonl",
        b'{"query_id": "a\xe9", "kitchen_id": "k", "goal": "g", "method": "ids"}\n',
        "latin1_id.jsonl:1:16: not UTF-8",
    )
    csv_raw = data.csv.read_bytes().splitlines(keepends=True)
    add("latin1.csv", b"".join([*csv_raw[:300], b"q,full,caf\xe9,ids,\n", *csv_raw[300:]]),
        "latin1.csv:301:11: not UTF-8")  # fmt: skip
    p = folder / "latin1.parquet"
    goals = pa.array([b"caf\xe9"] * t.num_rows, pa.binary()).cast(pa.string(), safe=False)
    pq.write_table(t.set_column(2, "goal", goals), p)
    cases.append((p, "latin1.parquet: rows 1-"))
    # A column given twice; a row without an id (null after blank lines, or empty).
    add(
        "twice.csv",
        "query_id,kitchen_id,goal,method,query_id\nq1,full,x,ids,q1\n",
        "the column 'query_id' twice",
    )
    add(
        "blank_null_id.jsonl",
        '\n\n{"query_id": "a", "kitchen_id": "k", "goal": "g", "method": "ids"}\n'
        '{"query_id": null, "kitchen_id": "k", "goal": "g", "method": "ids"}\n',
        "blank_null_id.jsonl:4:1: the query has no query_id",
    )
    p = folder / "empty_id.jsonl"
    empty = '{"query_id": "", "kitchen_id": "k", "goal": "g", "method": "ids"}\n'
    p.write_text("".join([*jl[:30], empty]))
    cases.append((p, "empty_id.jsonl:31:1: the query has no query_id"))
    add(
        "open_quote.csv",
        'query_id,kitchen_id,goal,method\n\nq0,full,"a\nb",ids\nq1,full,"x,ids\n',
        "open_quote.csv:5:1: a quoted field is not closed",
    )
    add(
        "empty_id.csv",
        "query_id,kitchen_id,goal,method\nq1,full,x,ids\n,full,x,ids\n",
        "empty_id.csv:3: the query has no query_id",
    )
    # The line of a row after blank lines and a field over several lines.
    add(
        "late_empty_id.csv",
        'query_id,kitchen_id,goal,method\nq1,full,x,ids\n\n\nq2,full,"a\nb\nc",ids\n'
        "\n,full,x,ids\n",
        "late_empty_id.csv:9: the query has no query_id",
    )
    # Two objects on one line, whether or not a blank line is in the same block.
    two = (
        '{"query_id": "a", "kitchen_id": "k", "goal": "g", "method": "ids"}'
        '{"query_id": "b", "kitchen_id": "k", "goal": "g", "method": "ids"}\n'
    )
    add("two.jsonl", two, "two.jsonl:1:67: Extra data")
    add("two_blank.jsonl", two + "\n", "two_blank.jsonl:1:67: Extra data")
    # A lone surrogate escape in a text field (a goal given as an object included).
    sur = '{"query_id": "\\ud800", "kitchen_id": "k", "goal": "g", "method": "ids"}\n'
    add(
        "surrogate.jsonl",
        "".join([*jl[:5], sur]),
        "surrogate.jsonl:6: 'query_id' holds a lone UTF-16 surrogate escape",
    )
    add(
        "surrogate_goal.jsonl",
        '{"query_id": "a", "kitchen_id": "k", "goal": {"label": "\\udc00"}, "method": "ids"}\n',
        "surrogate_goal.jsonl:1: 'goal' holds a lone UTF-16 surrogate escape",
    )
    return cases


def test_bad_files_are_errors_before_any_output(data: Data, tmp_path: Path) -> None:
    for i, (path, message) in enumerate(bad_files(tmp_path, data)):
        out = tmp_path / f"out{i}"
        with pytest.raises(ValueError) as err:
            foon.batch(path, foon=data.index, kitchens=data.kitchens, out=out)
        assert message in str(err.value), (path, str(err.value))
        assert len(str(err.value).splitlines()) == 1
        assert not out.exists(), path
    with pytest.raises(FileNotFoundError, match="no such file"):
        foon.batch(tmp_path / "none.csv", foon=data.index, kitchens=data.kitchens,
                   out=tmp_path / "o")  # fmt: skip
    assert not (tmp_path / "o").exists()


def test_a_lost_base_kitchen_is_an_error_of_the_set(data: Data, tmp_path: Path) -> None:
    """A kitchen set whose base file cannot be read: one line naming the set's file, line
    and column and the file it looked for, before any output."""
    sets = tmp_path / "sets"
    sets.mkdir()
    (sets / "kitchens.json").write_text('{"kitchens": {"a": {}},\n "base": "gone.json"}\n')
    out = tmp_path / "out"
    with pytest.raises(foon.ParseError) as err:
        foon.batch(data.parquet, foon=data.index, kitchens=sets / "kitchens.json", out=out)
    message = str(err.value)
    assert message.startswith(f"{sets / 'kitchens.json'}:2:10: "), message
    assert f"the base kitchen 'gone.json' cannot be read ({sets / 'gone.json'}: " in message
    assert len(message.splitlines()) == 1
    assert not out.exists()


def test_settings_are_checked_before_any_output(data: Data, tmp_path: Path) -> None:
    for rate in (2.0, -0.5, float("nan")):
        with pytest.raises(ValueError, match="default rate"):
            run(data, tmp_path / "o", default_rate=rate)
        assert not (tmp_path / "o").exists()


def test_arguments_are_checked(data: Data, tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="engine='dask'"):
        run(data, tmp_path / "o", scheduler="tcp://127.0.0.1:1")
    with pytest.raises(ValueError, match="engine='dask'"):
        run(data, tmp_path / "o", client=object())
    with pytest.raises(TypeError, match=r"client must be a distributed\.Client, not object"):
        run(data, tmp_path / "o", engine="dask", client=object())
    with pytest.raises(TypeError, match="resume"):
        run(data, tmp_path / "o", resume="no")
    with pytest.raises(TypeError, match="progress"):
        run(data, tmp_path / "o", progress="yes")
    with pytest.raises(ValueError, match="out must name a folder, not ''"):
        foon.batch(data.path("csv"), foon=data.index, kitchens=data.kitchens, out="")
    assert not (tmp_path / "o").exists()


def test_a_column_of_nulls_is_bad_rows(data: Data, tmp_path: Path) -> None:
    t = data.table.slice(0, 20)
    p = tmp_path / "null_goal.parquet"
    pq.write_table(t.set_column(2, "goal", pa.nulls(t.num_rows)), p)
    s = foon.batch(p, foon=data.index, kitchens=data.kitchens, out=tmp_path / "o")
    got = read_parts(tmp_path / "o")
    assert got.column("query_id").to_pylist() == t.column("query_id").to_pylist()
    # Every row is bad: its goal (unless its kitchen or method, checked first, is).
    assert s.solved == 0 and sum(s.failures.values()) == 20
    assert s.failures["bad-goal"] >= 15
    assert set(s.failures) <= {"bad-goal", "unknown-kitchen", "unknown-method"}


def test_a_large_csv_with_line_breaks_in_quoted_fields(data: Data, tmp_path: Path) -> None:
    import csv

    from batch_files import query_schema

    # Goals written as indented JSON, over several blocks of the CSV reader (1 MiB each).
    rows: list[dict[str, Any]] = []
    while sum(len(r["goal"]) for r in rows) < (3 << 20):
        for r in data.rows:
            g = r["goal"]
            if g.startswith("{"):
                g = json.dumps(json.loads(g), indent=1)
            rows.append(dict(r, query_id=f"{r['query_id']}-{len(rows)}", goal=g))
    p = tmp_path / "multiline.csv"
    with open(p, "w", encoding="utf-8", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    assert p.stat().st_size > (3 << 20)
    s = foon.batch(p, foon=data.index, kitchens=data.kitchens, out=tmp_path / "o",
                   motions=data.motions, chunk_size=4096)  # fmt: skip
    table = pa.Table.from_pylist(rows, schema=query_schema())
    want = _arrow.plan_table(data.foon, data.kitchens, table, motions=data.motions)
    assert s.queries == len(rows)
    assert read_parts(tmp_path / "o").equals(want)


def test_a_csv_row_longer_than_a_block(data: Data, tmp_path: Path) -> None:
    """A row longer than the CSV reader's blocks (a field of megabytes) is read, in its
    place: the file is read again with larger blocks."""
    import csv

    from batch_files import query_schema

    rows = [dict(r) for r in data.rows[:300]]
    rows[200]["kitchen_id"] = "x" * (3 << 20)
    p = tmp_path / "long.csv"
    with open(p, "w", encoding="utf-8", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    s = foon.batch(p, foon=data.index, kitchens=data.kitchens, out=tmp_path / "o",
                   motions=data.motions, chunk_size=64)  # fmt: skip
    table = pa.Table.from_pylist(rows, schema=query_schema())
    want = _arrow.plan_table(data.foon, data.kitchens, table, motions=data.motions)
    assert s.queries == 300
    got = read_parts(tmp_path / "o")
    assert got.equals(want)
    assert got.column("failure")[200].as_py() == "unknown-kitchen"


def test_overwrite_removes_only_the_batchs_files(data: Data, tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    theirs = {"part-mydata.parquet": b"theirs", ".part-notes.tmp": b"notes", "x.txt": b"x",
              "part-0001.parquet": b"four digits"}  # fmt: skip
    for name, content in theirs.items():
        (out / name).write_bytes(content)
    (out / "part-00007.parquet").write_bytes(b"a batch's name")
    (out / ".part-00003.parquet.k2_x9.tmp").write_bytes(b"a batch's temporary file")
    run(data, out, resume=False)
    names = set(os.listdir(out))
    assert names == {*theirs, _batch.MANIFEST, *(f"part-0000{k}.parquet" for k in range(5))}
    assert all((out / n).read_bytes() == c for n, c in theirs.items())
    # A query file that is one of the files a batch writes there is never replaced.
    q = out / "part-00000.parquet"
    pq.write_table(data.table, q)
    before = q.read_bytes()
    with pytest.raises(ValueError, match="one of the files a batch writes"):
        foon.batch(q, foon=data.index, kitchens=data.kitchens, out=out, resume=False)
    assert q.read_bytes() == before


def test_a_query_file_linked_into_the_output_is_never_removed(data: Data, tmp_path: Path
                                                              ) -> None:  # fmt: skip
    """A query file reached through a symbolic link, or a hard link, from one of the names
    a batch writes in its output folder is refused before anything is removed."""
    out = tmp_path / "out"
    out.mkdir()
    elsewhere = tmp_path / "queries.parquet"
    pq.write_table(data.table, elsewhere)
    before = elsewhere.read_bytes()
    inside = out / "part-00000.parquet"
    inside.symlink_to(elsewhere)
    outside = tmp_path / "link.parquet"
    outside.symlink_to(inside)
    for q in (inside, outside):
        with pytest.raises(ValueError, match="one of the files a batch writes"):
            foon.batch(q, foon=data.index, kitchens=data.kitchens, out=out, resume=False)
    inside.unlink()
    os.link(elsewhere, inside)
    with pytest.raises(ValueError, match="one of the files a batch writes"):
        foon.batch(elsewhere, foon=data.index, kitchens=data.kitchens, out=out, resume=False)
    assert elsewhere.read_bytes() == before and inside.read_bytes() == before
    assert sorted(os.listdir(out)) == ["part-00000.parquet"]


def test_results_are_ordinary_files(data: Data, tmp_path: Path) -> None:
    """Partitions and the manifest get the mode of any new file (0o666 less the umask),
    readable by the workers and readers the umask lets in; a folder with a batch's name
    in the output is left alone."""
    out = tmp_path / "out"
    out.mkdir()
    (out / ".part-00000.parquet.x.tmp").mkdir()
    old = os.umask(0o022)
    try:
        run(data, out)
    finally:
        os.umask(old)
    modes = {n: (out / n).stat().st_mode & 0o777 for n in os.listdir(out) if n.endswith(
        (".parquet", ".json"))}  # fmt: skip
    assert len(modes) == 6 and set(modes.values()) == {0o644}, modes
    assert (out / ".part-00000.parquet.x.tmp").is_dir()


def test_the_output_folder_is_not_the_kitchens_folder(data: Data, tmp_path: Path) -> None:
    folder = tmp_path / "kitchens"
    folder.mkdir()
    (folder / "full.json").write_text("[]")
    with pytest.raises(ValueError, match="the output folder is the folder of kitchens"):
        foon.batch(data.path("parquet"), foon=data.index, kitchens=folder, out=folder)
    assert sorted(os.listdir(folder)) == ["full.json"]


@pytest.mark.parametrize("edit", ["other file", "out of range", "long key"])
def test_a_manifest_entry_out_of_its_place_is_an_error(data: Data, tmp_path: Path, edit: str
                                                       ) -> None:  # fmt: skip
    """Resume keeps a partition only where its manifest entry is the one its key must be:
    an entry naming another partition's file or a key past the last partition is a
    manifest that is not a batch's."""
    out = tmp_path / "out"
    run(data, out)
    m = manifest(out)
    if edit == "other file":
        m["partitions"]["00002"] = m["partitions"]["00003"]
        (out / "part-00002.parquet").unlink()
        message = "partition '00002' names the file 'part-00003.parquet'"
    elif edit == "out of range":
        m["partitions"]["00099"] = dict(m["partitions"]["00001"], file="part-00099.parquet")
        message = "partition '00099' is not one of its 5"
    else:
        key = "9" * 5000
        m["partitions"][key] = dict(m["partitions"]["00001"], file=f"part-{key}.parquet")
        message = "is not one of its 5"
    (out / _batch.MANIFEST).write_text(json.dumps(m))
    with pytest.raises(FileExistsError, match=message):
        run(data, out)
    assert run(data, out, resume=False).planned_partitions == 5


def test_a_partition_short_of_its_chunk_is_planned_again(data: Data, whole: Any,
                                                         tmp_path: Path) -> None:  # fmt: skip
    """A partition of fewer rows than its chunk (written while the query file shrank, by a
    run that then failed) is planned again by the rerun on the whole file; the others are
    kept."""
    out = tmp_path / "out"
    run(data, out)
    m = manifest(out)
    last = out / "part-00004.parquet"
    pq.write_table(pq.read_table(last).slice(0, 10), last)
    m["partitions"]["00004"].update(rows=10, sha256=_batch._sha256(str(last)))
    (out / _batch.MANIFEST).write_text(json.dumps(m))
    s = run(data, out)
    assert (s.kept_partitions, s.planned_partitions) == (4, 1)
    assert read_parts(out).equals(whole)


@pytest.mark.parametrize("edit", ["list", "no inputs", "entry", "file"])
def test_a_manifest_of_another_shape_is_an_error(data: Data, tmp_path: Path, edit: str
                                                 ) -> None:  # fmt: skip
    out = tmp_path / "out"
    run(data, out)
    m = manifest(out)
    if edit == "list":
        m["partitions"] = []
    elif edit == "no inputs":
        m["inputs"] = []
    elif edit == "entry":
        m["partitions"]["00001"] = "part-00001.parquet"
    else:
        m["partitions"]["00001"]["file"] = "../elsewhere.parquet"
    (out / _batch.MANIFEST).write_text(json.dumps(m))
    with pytest.raises(FileExistsError, match="not a batch's"):
        run(data, out)
    assert run(data, out, resume=False).planned_partitions == 5


def test_a_query_file_that_grows_during_the_run(data: Data, tmp_path: Path) -> None:
    p = tmp_path / "q.jsonl"
    original = data.jsonl.read_bytes()
    p.write_bytes(original)

    def grow(done: int, total: int) -> None:
        if done == 128:
            with open(p, "ab") as f:
                f.write(original[: original.index(b"\n") + 1] * 300)

    out = tmp_path / "out"
    with pytest.raises(ValueError, match="changed while the batch ran"):
        foon.batch(p, foon=data.index, kitchens=data.kitchens, out=out, chunk_size=128,
                   threads=1, progress=grow, motions=data.motions)  # fmt: skip
    m = manifest(out)
    assert m["inputs"]["rows"] == len(data.rows)
    assert sum(e["rows"] for e in m["partitions"].values()) == len(data.rows)
    # Back to the file that was checked: every partition is kept.
    p.write_bytes(original)
    s = foon.batch(p, foon=data.index, kitchens=data.kitchens, out=out, chunk_size=128,
                   motions=data.motions)  # fmt: skip
    assert (s.planned_partitions, s.kept_partitions) == (0, 5)


def test_partition_names_sort_as_their_numbers() -> None:
    ks = [0, 7, 99_999, 100_000, 100_001, 999_999, 1_000_000, 12_345_678, 10**12]
    names = [_batch.part_name(k) for k in ks]
    assert names[:4] == ["part-00000.parquet", "part-00007.parquet", "part-99999.parquet",
                         "part-z100000.parquet"]  # fmt: skip
    assert sorted(names) == names and len(set(names)) == len(names)
    assert sorted(_batch.part_key(k) for k in reversed(ks)) == [_batch.part_key(k) for k in ks]


def test_a_huge_chunk_size_is_one_partition(data: Data, whole: Any, tmp_path: Path) -> None:
    s = run(data, tmp_path / "o", chunk_size=2**63)
    assert s.partitions == 1
    assert read_parts(tmp_path / "o").equals(whole)


def test_integer_ids_and_goal_objects_in_json_lines(data: Data, whole: Any, tmp_path: Path
                                                     ) -> None:  # fmt: skip
    p = tmp_path / "objects.jsonl"
    with open(p, "w", encoding="utf-8") as f:
        for i, r in enumerate(data.rows[:50]):
            d = dict(r)
            d["query_id"] = i
            if d["goal"].startswith("{"):
                d["goal"] = json.loads(d["goal"])
            if d["options"]:
                d["options"] = json.loads(d["options"])
            f.write(json.dumps(d) + "\n")
    foon.batch(p, foon=data.index, kitchens=data.kitchens, out=tmp_path / "o",
               motions=data.motions)  # fmt: skip
    got = read_parts(tmp_path / "o")
    assert got.column("query_id").to_pylist() == [str(i) for i in range(50)]
    assert got.drop_columns(["query_id"]).equals(whole.slice(0, 50).drop_columns(["query_id"]))


def test_an_empty_file_is_an_empty_batch(data: Data, tmp_path: Path) -> None:
    p = tmp_path / "empty.csv"
    p.write_text("query_id,kitchen_id,goal,method\n")
    s = foon.batch(p, foon=data.index, kitchens=data.kitchens, out=tmp_path / "o")
    assert (s.queries, s.partitions, s.solved, s.failures) == (0, 1, 0, {})
    assert list(manifest(tmp_path / "o")["partitions"]) == ["00000"]
    # One empty partition: the folder reads as a table of the result schema, with no rows.
    t = pq.read_table(tmp_path / "o")
    assert t.num_rows == 0 and t.schema == _arrow.RESULT_SCHEMA
    assert foon.batch(p, foon=data.index, kitchens=data.kitchens, out=tmp_path / "o"
                      ).kept_partitions == 1  # fmt: skip


def test_an_interrupted_run_leaves_whole_partitions(
    data: Data, whole: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = tmp_path / "out"

    def stop(done: int, total: int) -> None:
        if done >= 256:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run(data, out, progress=stop)
    assert sorted(os.listdir(out)) == [_batch.MANIFEST, "part-00000.parquet",
                                       "part-00001.parquet"]  # fmt: skip
    assert list(manifest(out)["partitions"]) == ["00000", "00001"]
    # A write that fails half way: no partition, no temporary file, the manifest as it was.
    real = pq.write_table
    writes = [0]

    def failing(table: Any, where: Any, **kw: Any) -> None:
        writes[0] += 1
        if writes[0] == 2:
            with open(where, "wb") as f:
                f.write(b"PAR1 half a file")
            raise OSError("disk full")
        real(table, where, **kw)

    monkeypatch.setattr(pq, "write_table", failing)
    with pytest.raises(OSError, match="disk full"):
        run(data, out)
    assert sorted(os.listdir(out)) == [_batch.MANIFEST, "part-00000.parquet",
                                       "part-00001.parquet", "part-00002.parquet"]  # fmt: skip
    assert list(manifest(out)["partitions"]) == ["00000", "00001", "00002"]
    monkeypatch.setattr(pq, "write_table", real)
    s = run(data, out)
    assert (s.planned_partitions, s.kept_partitions) == (2, 3)
    assert read_parts(out).equals(whole)


# --- the command ------------------------------------------------------------------------------


def cli(data: Data, out: Path, *extra: str, kind: str = "csv") -> list[str]:
    return [
        "batch", str(data.path(kind)), "--foon", str(data.index), "--kitchens",
        str(data.kitchens_path), "-o", str(out), "--motions", str(data.motions_path),
        "--chunk-size", "200", *extra,
    ]  # fmt: skip


def test_cli_summary_and_json(data: Data, whole: Any, tmp_path: Path,
                              capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    out = tmp_path / "out"
    assert main(cli(data, out, "--threads", "2")) == 0
    text, err = capsys.readouterr()
    solved = sum(whole.column("solved").to_pylist())
    assert text.splitlines()[0] == (f"600 queries: {solved} solved, {600 - solved} failed")
    assert "  unknown-kitchen: 1" in text.splitlines()
    assert "3 partitions in" in text and "(3 planned)" in text and "queries/s (local)" in text
    assert err == ""  # no bar: stderr is not a terminal
    assert read_parts(out).equals(whole)
    (out / "part-00001.parquet").unlink()
    assert main(cli(data, out, "--json")) == 0
    s = json.loads(capsys.readouterr().out)
    assert (s["queries"], s["solved"], s["planned_partitions"], s["kept_partitions"]) == (
        600, solved, 1, 2,
    )  # fmt: skip
    assert s["failures"]["unknown-method"] == 1 and s["engine"] == "local"


def test_sigterm_stops_the_cli_as_ctrl_c_does(data: Data, tmp_path: Path) -> None:
    """``kill`` (SIGTERM) of ``foon batch``: exit status 143, one line, no traceback, only
    whole partitions, each listed by the manifest; the rerun resumes."""
    import signal
    import subprocess
    import sys
    import time

    q = data.path("parquet")
    out = tmp_path / "out"
    argv = [sys.executable, "-m", "foon", "batch", str(q), "--foon", str(data.index),
            "--kitchens", str(data.kitchens_path), "-o", str(out), "--motions",
            str(data.motions_path), "--chunk-size", "1", "--threads", "1"]  # fmt: skip
    p = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not (out / "part-00002.parquet").exists() and time.monotonic() < deadline:
        time.sleep(0.01)
    p.send_signal(signal.SIGTERM)
    _, stderr = p.communicate(timeout=60)
    assert p.returncode == 143, (p.returncode, stderr)
    assert stderr.splitlines() == ["foon: terminated"], stderr
    names = set(os.listdir(out))
    listed = {e["file"] for e in manifest(out)["partitions"].values()}
    assert names == {_batch.MANIFEST, *listed}
    assert 3 <= len(listed) < len(data.rows)
    r = subprocess.run(argv, capture_output=True, text=True, timeout=600, check=True)
    assert "planned" in r.stdout
    assert len(manifest(out)["partitions"]) == len(data.rows)
    assert read_parts(out).equals(_arrow.plan_table(data.foon, data.kitchens, data.table,
                                                    motions=data.motions))  # fmt: skip


def test_cli_errors_are_one_line(data: Data, tmp_path: Path,
                                 capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    for i, (path, message) in enumerate(bad_files(tmp_path, data)):
        args = cli(data, tmp_path / f"o{i}")
        args[1] = str(path)
        assert main(args) == 1
        out, err = capsys.readouterr()
        assert out == ""
        assert err.startswith("foon: error: ") and err.count("\n") == 1, err
        assert message in err and "Traceback" not in err
        assert not (tmp_path / f"o{i}").exists()
    out = tmp_path / "out"
    assert main(cli(data, out)) == 0
    capsys.readouterr()
    assert main(cli(data, out, kind="jsonl")) == 1
    err = capsys.readouterr().err
    assert "other inputs" in err and "--overwrite" in err and err.count("\n") == 1
    assert main(cli(data, out, "--overwrite", kind="jsonl")) == 0
    assert main(cli(data, out, "--scheduler", "tcp://127.0.0.1:1")) == 1
    assert "--scheduler is for --engine dask" in capsys.readouterr().err


def test_cli_start_does_not_import_pyarrow() -> None:
    import subprocess
    import sys

    code = (
        "import sys, foon.cli; foon.cli.build_parser('batch'); "
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('pyarrow', 'dask', "
        "'distributed')))"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert r.stdout.strip() == "[]"


def test_the_process_cache_can_be_read_and_cleared(data: Data, whole: Any, tmp_path: Path
                                                   ) -> None:  # fmt: skip
    run(data, tmp_path / "a")
    info = foon.batch_cache_info()
    assert isinstance(info, foon.CacheInfo)
    assert info.entries > 0 and info.bases > 0 and info.bytes > 0
    foon.clear_batch_cache()
    after = foon.batch_cache_info()
    assert (after.entries, after.bytes, after.bases) == (0, 0, 0)
    assert (after.hits, after.misses) == (info.hits, info.misses)
    # The next batch prepares its kitchens again, with the same answers.
    run(data, tmp_path / "b")
    again = foon.batch_cache_info()
    assert again.misses > after.misses and again.entries > 0
    assert read_parts(tmp_path / "b").equals(whole)
