"""Batches of queries from a file to a folder of Parquet partitions: :func:`batch`.

The queries are read as a stream (Parquet by record batches, CSV by
``pyarrow.csv.open_csv``, JSON lines in blocks of lines through ``pyarrow.json``) and cut
into chunks of ``chunk_size`` rows: partition ``k`` holds the answers to rows
``k * chunk_size`` to ``(k + 1) * chunk_size - 1``, in order, planned by
:func:`foon._arrow.plan_table` (locally, or on Dask workers, :mod:`foon._dask`). Each
partition is written atomically (a temporary file in the output folder, then a rename; by
the client, or by the Dask worker that planned it), and ``_manifest.json`` (written the same
way by the client alone, at most once a second while partitions come in, and at the end)
records the inputs' fingerprints and every finished partition with its row count and
SHA-256, so that a rerun with the same inputs plans only the partitions that are missing.
The layout, the manifest and the resume rules are in ``docs/BATCH.md`` ("Output and
resume").

The input file is read twice: once to check it (columns, types, every row parsed; a bad
file is an error before any output) and count its rows, once to plan. Memory holds a few
chunks at a time, whatever the number of queries."""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import re
import secrets
import sys
import time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, TypeGuard

if TYPE_CHECKING:
    import threading
    from concurrent.futures import Future

    import pyarrow as pa  # type: ignore[import-untyped]

    from foon import Foon, MotionsLike, UtensilsLike
    from foon._kitchens import KitchenSet

__all__ = [
    "DEFAULT_CHUNK_SIZE",
    "MANIFEST",
    "BatchSummary",
    "CacheInfo",
    "batch",
    "batch_cache_info",
    "clear_batch_cache",
    "read_queries",
]

#: Queries per chunk (per partition, and per Dask task) when ``chunk_size`` is not given:
#: large enough that a Dask task's fixed cost (scheduling, shipping the chunk, a few
#: milliseconds) is a small share of its planning, small enough that a few chunks in flight
#: stay in tens of megabytes.
DEFAULT_CHUNK_SIZE = 20_000

#: The manifest's file name in the output folder, and its format tag.
MANIFEST = "_manifest.json"
_FORMAT = "foon-batch/1"

#: Seconds between two rewrites of the manifest while partitions are being recorded (it is
#: always written at the end, and when the run fails or is interrupted): a client killed
#: outright leaves a manifest that lists the partitions of all but its last second, whose
#: files a rerun plans again.
MANIFEST_INTERVAL = 1.0

#: Rows per block when reading JSON lines.
_JSON_BLOCK = 16_384

#: Rows per record batch read from Parquet, at most (a chunk is put together from them).
_PARQUET_BATCH = 1 << 20

_SUFFIXES = {
    ".parquet": "parquet",
    ".pq": "parquet",
    ".csv": "csv",
    ".jsonl": "jsonl",
    ".ndjson": "jsonl",
    ".json": "jsonl",
}

_REQUIRED = ("query_id", "kitchen_id", "goal", "method")


@dataclass(frozen=True)
class CacheInfo:
    """The process's cache of prepared kitchens, which every batch in the process shares
    (a Dask worker's tasks included): at most 1,024 kitchens and 256 MiB of them, and 4
    bases. ``bytes`` is the kept kitchens' size as last measured; ``hits``, ``misses`` and
    ``evictions`` count since the process started."""

    entries: int
    bytes: int
    bases: int
    hits: int
    misses: int
    evictions: int


def batch_cache_info() -> CacheInfo:
    """The counters of the process's cache of prepared kitchens (:class:`CacheInfo`)."""
    from foon import _foon

    return CacheInfo(*_foon.batch_cache_stats())


def clear_batch_cache() -> None:
    """Drops every prepared kitchen and base the process's batches keep (the memory they
    hold is freed once no planner uses them); the counters stay."""
    from foon import _foon

    _foon.clear_batch_cache()


@dataclass(frozen=True)
class BatchSummary:
    """What a batch did: every query of the input (kept partitions included), how many
    were solved, the failures by code, and the time and throughput of this run (over the
    queries it planned)."""

    queries: int
    solved: int
    failures: dict[str, int]
    partitions: int
    planned_partitions: int
    planned_queries: int
    seconds: float
    engine: str
    out: str
    chunk_size: int
    kept_partitions: int = field(default=0)

    @property
    def throughput(self) -> float | None:
        """Queries planned per second in this run (None when nothing was planned)."""
        if self.planned_queries == 0 or self.seconds <= 0:
            return None
        return self.planned_queries / self.seconds

    def to_dict(self) -> dict[str, Any]:
        return {
            "queries": self.queries,
            "solved": self.solved,
            "failures": dict(sorted(self.failures.items())),
            "partitions": self.partitions,
            "planned_partitions": self.planned_partitions,
            "kept_partitions": self.kept_partitions,
            "planned_queries": self.planned_queries,
            "seconds": round(self.seconds, 6),
            "throughput": None if self.throughput is None else round(self.throughput, 3),
            "engine": self.engine,
            "chunk_size": self.chunk_size,
            "out": self.out,
        }


# --- reading queries ------------------------------------------------------------------------


def _format_of(path: str) -> str:
    ext = os.path.splitext(path)[1].lower()
    try:
        return _SUFFIXES[ext]
    except KeyError:
        raise ValueError(
            f"{path}: unknown query file type {ext or '(no extension)'!r} "
            "(.parquet, .csv or .jsonl)"
        ) from None


def _check_schema(path: str, schema: pa.Schema) -> None:
    """The query columns are there and of usable types (``ValueError`` naming the column)."""
    import pyarrow as pa

    names = schema.names
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ValueError(f"{path}: the query table has the column '{twice[0]}' twice")
    for name in _REQUIRED:
        if name not in names:
            raise ValueError(
                f"{path}: the query table has no column '{name}' (columns: {', '.join(names)})"
            )
    for name in (*_REQUIRED, "options"):
        if name not in names:
            continue
        t = schema.field(name).type
        if pa.types.is_dictionary(t):
            t = t.value_type
        ok = pa.types.is_string(t) or pa.types.is_large_string(t) or pa.types.is_null(t)
        if name == "query_id":
            ok = (ok and not pa.types.is_null(t)) or pa.types.is_integer(t)
        if not ok:
            raise ValueError(f"{path}: query column '{name}' must be strings, not {t}")


def _select(batch: pa.RecordBatch) -> pa.RecordBatch:
    """Only the query columns, in order."""
    names = [c for c in ("query_id", "kitchen_id", "goal", "method", "options") if c in
             batch.schema.names]  # fmt: skip
    return batch.select(names)


def _null_ids(batch: pa.RecordBatch, first_row: int, place: Callable[[int], str]) -> None:
    """A row without a query id is an error naming its line (its row, in Parquet)."""
    import pyarrow.compute as pc  # type: ignore[import-untyped]

    missing = _missing_ids(batch.column("query_id"))
    if pc.any(missing).as_py():
        i = int(pc.index(missing, True).as_py())
        raise ValueError(f"{place(first_row + i)}: the query has no query_id")


def _missing_ids(col: Any) -> Any:
    """Per row of a ``query_id`` column: whether the id is missing (null, or empty text)."""
    import pyarrow as pa
    import pyarrow.compute as pc

    missing = col.is_null()
    if pa.types.is_dictionary(col.type):
        col = col.cast(col.type.value_type)
    if pa.types.is_string(col.type) or pa.types.is_large_string(col.type):
        missing = pc.or_(missing, pc.fill_null(pc.equal(pc.utf8_length(col), 0), False))
    return missing


def _parquet_batches(path: str, rows: int, use_threads: bool) -> Iterator[pa.RecordBatch]:
    import pyarrow.parquet as pq  # type: ignore[import-untyped]

    try:
        f = pq.ParquetFile(path)
    except Exception as e:  # noqa: BLE001 - pyarrow raises many kinds for a bad file
        raise ValueError(f"{path}: not a readable Parquet file: {e}") from None
    with f:
        _check_schema(path, f.schema_arrow)
        cols = [c for c in ("query_id", "kitchen_id", "goal", "method", "options")
                if c in f.schema_arrow.names]  # fmt: skip
        try:
            yield from f.iter_batches(batch_size=min(rows, _PARQUET_BATCH), columns=cols,
                                      use_threads=use_threads)  # fmt: skip
        except OSError as e:
            raise ValueError(f"{path}: {e}") from None


@contextlib.contextmanager
def _csv_fields_unbounded() -> Iterator[None]:
    """The ``csv`` module reads fields of any length (as pyarrow's reader does) while in."""
    import csv

    old = csv.field_size_limit(sys.maxsize)
    try:
        yield
    finally:
        csv.field_size_limit(old)


def _csv_row_line(path: str, row: int) -> int:
    """The line that data row ``row`` (0-based) of a CSV file starts on: blank lines are not
    rows (as for pyarrow's reader) and a quoted field may span lines."""
    import csv

    # (Bytes that are not UTF-8 further on, which the check reports, do not stop the count.)
    with _csv_fields_unbounded(), open(path, encoding="utf-8", errors="replace",
                                       newline="") as f:  # fmt: skip
        reader = csv.reader(f)
        next(reader, None)  # the header
        start = reader.line_num + 1
        i = 0
        for r in reader:
            if r:
                if i == row:
                    return start
                i += 1
            start = reader.line_num + 1
    return start


def _csv_line_error(path: str) -> str | None:
    """Where the CSV file goes wrong (a row with the wrong number of fields), found with
    the ``csv`` module when pyarrow's reader has refused it."""
    with _csv_fields_unbounded():
        return _csv_line_error_of(path)


def _csv_line_error_of(path: str) -> str | None:
    import csv

    with open(path, "rb") as raw:
        for line, text in enumerate(raw, 1):
            try:
                text.decode("utf-8")
            except UnicodeDecodeError as e:
                return f"{path}:{line}:{e.start + 1}: not UTF-8"
    with open(path, encoding="utf-8", newline="") as f:
        reader = csv.reader(f, strict=True)
        start = 1  # the line the row being read starts on
        try:
            header = next(reader)
            width = len(header)
            start = reader.line_num + 1
            for row in reader:
                # (Blank lines are skipped, as pyarrow's reader does.)
                if row and len(row) != width:
                    return f"{path}:{start}:1: expected {width} fields, got {len(row)}"
                start = reader.line_num + 1
        except StopIteration:
            return f"{path}:1:1: the CSV file is empty"
        except csv.Error as e:
            if "unexpected end of data" in str(e):
                return f"{path}:{start}:1: a quoted field is not closed"
            return f"{path}:{reader.line_num}:1: {e}"
    return None


#: The bytes pyarrow's CSV reader decodes at a time; a row longer than that (a goal of
#: megabytes) is read again from the start with blocks 16 times larger, up to
#: :data:`_CSV_BLOCK_MAX` (a row longer than that, or a quoted field never closed, is an
#: error).
_CSV_BLOCK = 1 << 20
_CSV_BLOCK_MAX = 256 << 20


def _csv_batches(path: str, use_threads: bool) -> Iterator[pa.RecordBatch]:
    import pyarrow as pa

    block = _CSV_BLOCK
    done = 0  # rows given already (skipped when read again with larger blocks)
    while True:
        skip = done
        try:
            for b in _csv_blocks(path, use_threads, block):
                if skip >= b.num_rows:
                    skip -= b.num_rows
                    continue
                b, skip = b.slice(skip), 0
                done += b.num_rows
                yield b
            return
        except pa.ArrowInvalid as e:
            if "straddl" in str(e) and block < _CSV_BLOCK_MAX:
                block = min(16 * block, _CSV_BLOCK_MAX)
                continue
            raise ValueError(_csv_line_error(path) or f"{path}: {e}") from None


def _csv_blocks(path: str, use_threads: bool, block: int) -> Iterator[pa.RecordBatch]:
    import pyarrow as pa
    import pyarrow.csv as pcsv  # type: ignore[import-untyped]

    text = {name: pa.string() for name in ("query_id", "kitchen_id", "goal", "method",
                                           "options")}  # fmt: skip
    reader = pcsv.open_csv(
        path,
        read_options=pcsv.ReadOptions(block_size=block, use_threads=use_threads),
        # Quoted fields may hold line breaks (a goal written as indented JSON).
        parse_options=pcsv.ParseOptions(newlines_in_values=True),
        convert_options=pcsv.ConvertOptions(
            column_types=text, strings_can_be_null=False, quoted_strings_can_be_null=False
        ),
    )
    with reader:
        _check_schema(path, reader.schema)
        while True:
            try:
                b = reader.read_next_batch()
            except StopIteration:
                return
            yield _select(b)


def _json_value(path: str, line: int, obj: dict[str, Any], name: str) -> str | None:
    v = obj.get(name)
    if v is None:
        return v
    if isinstance(v, str):
        text = v
    elif name == "query_id" and isinstance(v, int) and not isinstance(v, bool):
        return str(v)
    elif name in ("goal", "options") and isinstance(v, dict):
        text = json.dumps(v, ensure_ascii=False)
    else:
        raise ValueError(f"{path}:{line}: '{name}' must be a string, not {type(v).__name__}")
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        # A lone surrogate (the escape ``\\ud800``): JSON can write it, no text holds it.
        raise ValueError(
            f"{path}:{line}: '{name}' holds a lone UTF-16 surrogate escape, not text"
        ) from None
    return text


def _json_block_slow(path: str, lines: list[bytes], first_line: int) -> pa.RecordBatch:
    """A block of JSON lines parsed line by line (integer ids, goals and options given as
    objects), naming the line and column of the first bad one."""
    import pyarrow as pa

    cols: dict[str, list[str | None]] = {c: [] for c in ("query_id", "kitchen_id", "goal",
                                                          "method", "options")}  # fmt: skip
    for i, raw in enumerate(lines):
        line = first_line + i
        if not raw.strip():
            continue
        try:
            obj = json.loads(raw)
        except UnicodeDecodeError as e:
            raise ValueError(f"{path}:{line}:{e.start + 1}: not UTF-8") from None
        except json.JSONDecodeError as e:
            raise ValueError(f"{path}:{line}:{e.colno}: {e.msg}") from None
        if not isinstance(obj, dict):
            raise ValueError(f"{path}:{line}:1: a query must be a JSON object")  # noqa: TRY004
        for name in _REQUIRED:
            if name not in obj:
                raise ValueError(f"{path}:{line}:1: the query has no '{name}'")
        if obj["query_id"] in (None, ""):
            raise ValueError(f"{path}:{line}:1: the query has no query_id")
        for name, values in cols.items():
            values.append(_json_value(path, line, obj, name))
    return pa.RecordBatch.from_pydict(cols, schema=_json_schema())


def _json_schema() -> pa.Schema:
    import pyarrow as pa

    return pa.schema([(c, pa.string()) for c in ("query_id", "kitchen_id", "goal", "method",
                                                 "options")])  # fmt: skip


def _json_batches(path: str, use_threads: bool) -> Iterator[pa.RecordBatch]:
    import pyarrow as pa
    import pyarrow.compute as pc
    import pyarrow.json as pjson  # type: ignore[import-untyped]

    opts = pjson.ParseOptions(explicit_schema=_json_schema(), unexpected_field_behavior="ignore")
    reads = pjson.ReadOptions(use_threads=use_threads)
    with open(path, "rb") as f:
        line = 1
        while True:
            lines = [raw for raw in (f.readline() for _ in range(_JSON_BLOCK)) if raw]
            if not lines:
                return
            block = b"".join(x if x.endswith(b"\n") else x + b"\n" for x in lines)
            try:
                # pyarrow's reader takes bytes that are not UTF-8 as they are: checked here.
                block.decode("utf-8")
                t = pjson.read_json(io.BytesIO(block), parse_options=opts, read_options=reads)
                # Missing keys, integer ids, goals as objects, blank lines, empty ids: line by
                # line.
                # (A blank line would let a line of two objects pass the count.)
                if (
                    t.num_rows != len(lines)
                    or any(not x.strip() for x in lines)
                    or any(t.column(c).null_count for c in _REQUIRED)
                    or pc.any(_missing_ids(t.column("query_id"))).as_py()
                ):
                    raise pa.ArrowInvalid("not plain")
                out = pa.RecordBatch.from_arrays(
                    [t.column(c).combine_chunks() for c in t.column_names], schema=t.schema
                )
            except (pa.ArrowInvalid, UnicodeDecodeError):
                out = _json_block_slow(path, lines, line)
            yield out
            line += len(lines)


def read_queries(
    path: str, rows: int = DEFAULT_CHUNK_SIZE, *, use_threads: bool = True
) -> Iterator[pa.RecordBatch]:
    """The query rows of a Parquet, CSV or JSON-lines file, as record batches of the query
    columns (at most ``rows`` rows each for Parquet; a block at a time for the others).
    A file that cannot be read as queries is a ``ValueError`` naming it (and the line, for
    text files); a missing file is ``FileNotFoundError``. ``use_threads=False``: pyarrow
    decodes on the calling thread alone."""
    path = os.fspath(path)
    kind = _format_of(path)
    if not os.path.isfile(path):
        if os.path.exists(path):
            raise ValueError(f"{path}: not a file")
        raise FileNotFoundError(f"{path}: no such file")
    if kind == "parquet":
        return _parquet_batches(path, rows, use_threads)
    if kind == "csv":
        return _csv_batches(path, use_threads)
    return _json_batches(path, use_threads)


def _row_place(path: str, kind: str) -> Callable[[int], str]:
    """Where row ``i`` (0-based) of a query file is, for messages: ``path:line`` for the
    text files (for JSON lines, of a block without blank lines: others are read line by
    line), ``path: row n`` for Parquet, which has rows, not lines."""
    if kind == "csv":
        return lambda i: f"{path}:{_csv_row_line(path, i)}"
    if kind == "jsonl":
        return lambda i: f"{path}:{i + 1}"
    return lambda i: f"{path}: row {i + 1}"


def scan_queries(path: str, *, use_threads: bool = True) -> int:
    """Reads the whole query file once, checking it; returns its row count."""
    import pyarrow as pa

    path = os.fspath(path)
    kind = _format_of(path)
    n = 0
    for b in read_queries(path, use_threads=use_threads):
        _check_schema(path, b.schema)
        if kind == "parquet":
            # Strings that are not UTF-8 (the text readers check their bytes themselves).
            try:
                b.validate(full=True)
            except pa.ArrowInvalid as e:
                raise ValueError(f"{path}: rows {n + 1}-{n + b.num_rows}: {e}") from None
        _null_ids(b, n, _row_place(path, kind))
        n += b.num_rows
    return n


def chunks(
    path: str, size: int, *, use_threads: bool = True, rows: int | None = None
) -> Iterator[tuple[int, pa.Table]]:
    """``(k, table)``: the query rows of partition ``k``, ``size`` rows each but the last
    (of the first ``rows`` rows of the file, when given); one empty partition when there
    are no rows."""
    import pyarrow as pa

    pending: list[pa.RecordBatch] = []
    have = 0
    k = 0
    left = rows
    for b in read_queries(path, size, use_threads=use_threads):
        if left is not None:
            b = b.slice(0, left)
            left -= b.num_rows
        while b.num_rows:
            take = min(size - have, b.num_rows)
            pending.append(b.slice(0, take))
            have += take
            b = b.slice(take)
            if have == size:
                yield k, _normalise(pa.Table.from_batches(pending))
                pending, have, k = [], 0, k + 1
    if have:
        yield k, _normalise(pa.Table.from_batches(pending))
    elif k == 0:
        # No rows: one empty partition, so that the output reads as a table of the result
        # schema (a folder of no partitions reads as a table of no columns).
        yield 0, _empty_queries()


def partition_count(rows: int, size: int) -> int:
    """The number of partitions of ``rows`` queries in chunks of ``size``: at least one."""
    return max(1, (rows + size - 1) // size)


def _normalise(t: pa.Table) -> pa.Table:
    """The chunk in one record batch per column, ids as strings (the same bytes whatever
    the input's batching, so that results do not depend on it)."""
    import pyarrow as pa

    if not pa.types.is_string(t.schema.field("query_id").type):
        t = t.set_column(0, "query_id", t.column("query_id").cast(pa.string()))
    # A column of nulls alone (Arrow type null): every row lacks it (a bad row each).
    for i, col in enumerate(t.schema):
        if pa.types.is_null(col.type):
            t = t.set_column(i, col.name, t.column(i).cast(pa.string()))
    return t.combine_chunks()


# --- fingerprints and the manifest ----------------------------------------------------------


def file_fingerprint(path: str) -> dict[str, Any]:
    """The query file's size and the BLAKE2b-128 of its whole content (its modification
    time is left out: a copy or a touch of the same bytes is the same input)."""
    h = hashlib.blake2b(digest_size=16)
    size = 0
    with open(path, "rb") as f:
        while block := f.read(1 << 22):
            h.update(block)
            size += len(block)
    return {"size": size, "blake2b": h.hexdigest()}


def _sha256(path: str) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        while block := f.read(1 << 22):
            h.update(block)
    return h.hexdigest()


def _settings_fingerprint(motions: Any, utensils: Any, default_rate: float | None) -> str:
    from foon import _as_rates, _as_utensils

    rates = _as_rates(motions)
    text = json.dumps(
        {
            "motions": None if rates is None else sorted(rates.items()),
            "utensils": sorted(_as_utensils(utensils)),
            "default_rate": default_rate,
        },
        sort_keys=True,
    )
    return hashlib.blake2b(text.encode(), digest_size=16).hexdigest()


def _write_atomic(folder: str, name: str, write: Callable[[str], None], *, hash: bool = False
                  ) -> str | None:  # fmt: skip
    """Writes ``folder/name`` through a temporary file in ``folder`` and a rename: a reader
    sees the old file or the whole new one, never a part. With ``hash``, returns the SHA-256
    of the bytes written (read back from the temporary file before the rename: this write's
    bytes, whatever another writer of the same name does)."""
    tmp = None
    try:
        # Created as an ordinary file is (mode 0o666 less the umask), not private as
        # mkstemp's.
        while tmp is None:
            tmp = os.path.join(folder, f".{name}.{secrets.token_hex(6)}.tmp")
            try:
                os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            except FileExistsError:
                tmp = None
        write(tmp)
        with open(tmp, "rb") as f:
            os.fsync(f.fileno())
        digest = _sha256(tmp) if hash else None
        os.replace(tmp, os.path.join(folder, name))
    except BaseException:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        raise
    return digest


def _write_json(folder: str, name: str, data: dict[str, Any]) -> None:
    def write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8") as f:
            json.dump(data, f, indent=1, sort_keys=False)
            f.write("\n")

    _write_atomic(folder, name, write)


def part_key(k: int) -> str:
    """Partition ``k``'s key in the manifest (and in its file's name): five digits, and from
    100,000 on the digits after one ``z`` per digit beyond five, so that the keys (and the
    file names) sort as the numbers do: ``99999`` < ``z100000`` < ``zz1000000``."""
    digits = str(k)
    return digits.zfill(5) if len(digits) <= 5 else "z" * (len(digits) - 5) + digits


def part_name(k: int) -> str:
    return f"part-{part_key(k)}.parquet"


def write_partition(folder: str, k: int, table: pa.Table) -> dict[str, Any]:
    """Writes the results of chunk ``k`` atomically as ``folder/part-k.parquet`` and returns
    its manifest entry (file, rows, SHA-256 of the bytes written, solved rows, failures by
    code). Called by the client, or by a Dask worker that sees the output folder; the
    results of a chunk are the same bytes whoever writes them, so a task run twice (after
    a worker died) replaces the file with itself."""
    import pyarrow.parquet as pq

    name = part_name(k)
    digest = _write_atomic(folder, name, lambda tmp: pq.write_table(table, tmp), hash=True)
    solved, failures = _count(table)
    return {
        "file": name,
        "rows": table.num_rows,
        "sha256": digest,
        "solved": solved,
        "failures": failures,
    }


#: The names of the files a batch writes in its output folder (the manifest, partitions,
#: and the temporary files of both while they are written): the only files it removes.
_OURS = re.compile(
    r"_manifest\.json|part-z*[0-9]{5,}\.parquet"
    r"|\.(?:_manifest\.json|part-z*[0-9]{5,}\.parquet)\.[A-Za-z0-9_-]+\.tmp"
)


def _is_ours(name: str) -> bool:
    return _OURS.fullmatch(name) is not None


def _clean(folder: str, everything: bool) -> None:
    """Removes the temporary files of an interrupted run (and, with ``everything``, the
    partitions and the manifest too); other files are left alone."""
    for name in os.listdir(folder):
        p = os.path.join(folder, name)
        if _is_ours(name) and (everything or name.endswith(".tmp")) and not os.path.isdir(p):
            with contextlib.suppress(FileNotFoundError):
                os.unlink(p)


def _prepare_output(out: str, inputs: dict[str, Any], resume: bool) -> dict[str, Any]:
    """The partitions of an earlier run with the same inputs that can be kept (each file
    there, its SHA-256 as recorded); a folder holding another batch's results (or other
    files) is an error unless ``resume`` is false."""
    if os.path.exists(out) and not os.path.isdir(out):
        raise FileExistsError(f"{out}: exists and is not a folder")
    os.makedirs(out, exist_ok=True)
    manifest_path = os.path.join(out, MANIFEST)
    if not resume:
        _clean(out, everything=True)
        return {}
    old: dict[str, Any] | None = None
    if os.path.exists(manifest_path):
        try:
            with open(manifest_path, encoding="utf-8") as f:
                old = json.load(f)
        except (OSError, ValueError):
            old = None
        if not _is_manifest(old):
            raise FileExistsError(
                f"{out}: holds a _manifest.json that is not a batch's (use --overwrite to "
                "replace it)"
            )
        if old.get("inputs") != inputs:
            diff = [k for k in inputs if old.get("inputs", {}).get(k) != inputs[k]]
            raise FileExistsError(
                f"{out}: holds the results of a batch with other inputs (differ: "
                f"{', '.join(diff) or 'format'}); use --overwrite to replace them"
            )
        bad = _misplaced_entry(old, inputs)
        if bad is not None:
            raise FileExistsError(
                f"{out}: its _manifest.json is not a batch's ({bad}); use --overwrite to replace it"
            )
    elif any(_is_ours(n) and n.endswith(".parquet") for n in os.listdir(out)):
        raise FileExistsError(
            f"{out}: holds partitions but no _manifest.json; use --overwrite to replace them"
        )
    _clean(out, everything=False)
    kept: dict[str, Any] = {}
    for key, entry in (old or {}).get("partitions", {}).items():
        p = os.path.join(out, entry.get("file", ""))
        # A partition of fewer rows than its chunk (written while the query file shrank,
        # a run that then failed) is planned again.
        if (
            entry["rows"] == _chunk_rows(inputs, key)
            and os.path.isfile(p)
            and _sha256(p) == entry.get("sha256")
        ):
            kept[key] = entry
    return kept


def _misplaced_entry(m: dict[str, Any], inputs: dict[str, Any]) -> str | None:
    """An entry of manifest ``m`` (of a run with these ``inputs``) that is not partition
    ``k``'s (its key and file name are fixed by ``k``), described; ``None`` when every
    entry is in its place."""
    n = partition_count(int(inputs["rows"]), int(inputs["chunk_size"]))
    for key, e in m["partitions"].items():
        k = _part_number(key)
        if k < 0 or k >= n:
            return f"partition '{key}' is not one of its {n}"
        if e["file"] != part_name(k):
            return f"partition '{key}' names the file '{e['file']}'"
    return None


def _chunk_rows(inputs: dict[str, Any], key: str) -> int:
    """The rows partition ``key`` (a key in its place) holds when whole, for a run with
    these ``inputs``."""
    rows, size = int(inputs["rows"]), int(inputs["chunk_size"])
    return min(size, rows - _part_number(key) * size)


#: A partition's key (:func:`part_key`), of a bounded length.
_PART_KEY = re.compile(r"z{0,15}[0-9]{5,20}")


def _part_number(key: str) -> int:
    """The partition number ``key`` is the key of (:func:`part_key`'s inverse), -1 for a
    string that is no partition's key."""
    if not _PART_KEY.fullmatch(key):
        return -1
    k = int(key.lstrip("z"))
    return k if part_key(k) == key else -1


def _is_manifest(m: Any) -> TypeGuard[dict[str, Any]]:
    """Whether ``m`` (a manifest file's JSON) has a batch manifest's shape."""
    if not (isinstance(m, dict) and m.get("format") == _FORMAT):
        return False
    parts = m.get("partitions")
    return (
        isinstance(m.get("inputs"), dict)
        and isinstance(parts, dict)
        and all(
            isinstance(e, dict)
            and isinstance(e.get("file"), str)
            and _is_ours(e["file"])
            and isinstance(e.get("sha256"), str)
            and isinstance(e.get("rows"), int)
            and isinstance(e.get("solved"), int)
            and isinstance(e.get("failures"), dict)
            for e in parts.values()
        )
    )


def _listed(out: str, key: str) -> bool:
    """Whether a manifest in ``out`` lists partition ``key`` (read only, never checked)."""
    try:
        with open(os.path.join(out, MANIFEST), encoding="utf-8") as f:
            old = json.load(f)
    except (OSError, ValueError):
        return False
    return (
        isinstance(old, dict)
        and isinstance(old.get("partitions"), dict)
        and (key in old["partitions"])
    )


# --- the batch --------------------------------------------------------------------------------


class _Progress:
    """A one-line bar on stderr: queries done of the total, and the rate."""

    def __init__(self, total: int, done: int) -> None:
        self.total = total
        self.start_done = done
        self.t0 = time.perf_counter()
        self.last = 0.0
        self.shown = -1

    def __call__(self, done: int, total: int, final: bool = False) -> None:
        now = time.perf_counter()
        if final and self.shown == done:
            sys.stderr.write("\n")
            sys.stderr.flush()
            return
        if not final and now - self.last < 0.1 and done < total:
            return
        self.last = now
        self.shown = done
        width = 30
        frac = done / total if total else 1.0
        bar = "#" * int(frac * width)
        rate = (done - self.start_done) / max(now - self.t0, 1e-9)
        line = f"\r[{bar:<{width}}] {done:,}/{total:,} queries  {rate:,.0f}/s"
        sys.stderr.write(line + ("\n" if final else ""))
        sys.stderr.flush()


def _count(t: pa.Table) -> tuple[int, dict[str, int]]:
    import pyarrow.compute as pc

    solved = int(pc.sum(t.column("solved")).as_py() or 0)
    failures: dict[str, int] = {}
    vc = pc.value_counts(t.column("failure").drop_null())
    for item in vc.to_pylist():
        failures[str(item["values"])] = int(item["counts"])
    return solved, dict(sorted(failures.items()))


def _empty_queries() -> pa.Table:
    import pyarrow as pa

    return pa.table({c: pa.array([], pa.string()) for c in _REQUIRED})


def _native_foon(foon: Any) -> Foon:
    from foon import Foon

    if isinstance(foon, Foon):
        return foon
    if isinstance(foon, str | os.PathLike):
        return Foon.load(foon)
    raise TypeError(f"foon must be a Foon or the path of a .foonidx, not {type(foon).__name__}")


def _kitchen_set(kitchens: Any) -> KitchenSet:
    from foon._kitchens import KitchenSet

    if isinstance(kitchens, KitchenSet):
        return kitchens
    if isinstance(kitchens, str | os.PathLike):
        return KitchenSet.load(kitchens)
    from collections.abc import Mapping

    if isinstance(kitchens, Mapping):
        return KitchenSet(kitchens)
    raise TypeError(
        f"kitchens must be a KitchenSet, a mapping or a path, not {type(kitchens).__name__}"
    )


class _Early:
    """Chunk 0 of a query file planned on a thread of its own (``plan(chunk, cancel)``)
    while the file is checked; its answers are only held."""

    def __init__(self, answers: Future[pa.Table], cancel: threading.Event) -> None:
        self.answers = answers
        self.cancel = cancel

    @classmethod
    def start(
        cls, path: str, size: int, plan: Callable[[pa.Table, threading.Event], pa.Table]
    ) -> _Early | None:
        """None when the first chunk cannot be read (the check says why; a file without
        rows has one, empty)."""
        import threading
        from concurrent.futures import ThreadPoolExecutor

        try:
            first = next(chunks(path, size))
        except Exception:  # noqa: BLE001 - reported by the file's check
            return None
        cancel = threading.Event()
        ex = ThreadPoolExecutor(max_workers=1, thread_name_prefix="foon-plan")
        answers = ex.submit(plan, first[1], cancel)
        ex.shutdown(wait=False)
        return cls(answers, cancel)

    def stop(self) -> None:
        """Stops the planning (if it still runs) and waits for its thread."""
        from concurrent.futures import wait

        self.cancel.set()
        wait([self.answers])


#: Chunks the local engine plans at once on more than one thread.
LOCAL_AHEAD = 2


def _plan_locally(
    todo: Iterable[tuple[int, pa.Table]],
    plan: Callable[[pa.Table, threading.Event], pa.Table],
    record: Callable[[int, dict[str, Any]], None],
    out: str,
    ahead: int,
    first: _Early | None = None,
    overlap: bool = True,
) -> None:
    """The local engine: ``plan(chunk, cancel)`` answers each chunk of ``todo``, ``ahead``
    chunks at once (each call on the core's pool, whose threads take a later chunk's rows
    while the last rows of another run, so that no thread waits at a chunk's end, nor for a
    chunk slower than the others). The partitions are written (and hashed) in order by a
    writer thread while later chunks are planned (with ``overlap``; without, each is written
    before the next chunk is planned, so that one thread works at a time: a batch asked to
    run on one thread), and recorded in order, each once it is whole: at most 2 * ``ahead``
    chunks' answers wait to be written, and one is written. An interrupted or failed run
    stops the chunks being planned and still records the partition being written.
    ``first``: chunk 0 being planned already (its answers are used when ``todo`` starts with
    chunk 0)."""
    import threading
    from collections import deque
    from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait

    cancel = threading.Event()
    chunks = iter(todo)
    order: deque[int] = deque()  # the chunks submitted and not yet written, in order
    running: dict[Future[pa.Table], int] = {}
    answered: dict[int, pa.Table] = {}
    writing: tuple[int, Future[dict[str, Any]]] | None = None
    with (
        ThreadPoolExecutor(max_workers=1, thread_name_prefix="foon-writer") as w,
        ThreadPoolExecutor(max_workers=ahead, thread_name_prefix="foon-plan") as p,
    ):
        try:
            more = True
            while True:
                # Without overlap, a chunk answered is written before the next is planned.
                while (more and len(running) < ahead and len(order) < 2 * ahead
                       and (overlap or not answered)):  # fmt: skip
                    nxt = next(chunks, None)
                    if nxt is None:
                        more = False
                        break
                    order.append(nxt[0])
                    if first is not None and nxt[0] == 0:
                        running[first.answers] = 0
                    else:
                        running[p.submit(plan, nxt[1], cancel)] = nxt[0]
                if order and order[0] in answered:
                    k = order.popleft()
                    if writing is not None:
                        done_k, entry = writing[0], writing[1].result()
                        writing = None
                        record(done_k, entry)
                    writing = (k, w.submit(write_partition, out, k, answered.pop(k)))
                    if not overlap:
                        done_k, entry = writing[0], writing[1].result()
                        writing = None
                        record(done_k, entry)
                    continue
                if not running:
                    break
                finished, _ = wait(running, return_when=FIRST_COMPLETED)
                for fut in finished:
                    answered[running.pop(fut)] = fut.result()
        finally:
            # Chunks still being planned (an interrupted or failed run) stop at once.
            cancel.set()
            if first is not None:
                first.stop()
            if writing is not None:
                record(writing[0], writing[1].result())


def _is_output_file(qpath: str, opath: str) -> bool:
    """Whether the query file is (by its name, the file it links to, or another link to the
    same file) one of the files a batch writes, and may remove, in ``opath``."""
    for p in (os.path.abspath(qpath), os.path.realpath(qpath)):
        if _is_ours(os.path.basename(p)) and os.path.realpath(
            os.path.dirname(p)
        ) == os.path.realpath(opath):
            return True
    if os.path.isdir(opath) and os.path.isfile(qpath):
        for name in os.listdir(opath):
            with contextlib.suppress(OSError):
                if _is_ours(name) and os.path.samefile(qpath, os.path.join(opath, name)):
                    return True
    return False


def _check_client(client: Any) -> None:
    """A ``client`` is a ``distributed.Client`` (``TypeError`` otherwise)."""
    try:
        from distributed import Client
    except ImportError:
        ok = False  # no Client can be given without the package
    else:
        ok = isinstance(client, Client)
    if not ok:
        raise TypeError(f"client must be a distributed.Client, not {type(client).__name__}")


def batch(
    queries: str | os.PathLike[str],
    *,
    foon: Foon | str | os.PathLike[str],
    kitchens: KitchenSet | str | os.PathLike[str],
    out: str | os.PathLike[str],
    engine: str = "local",
    client: Any = None,
    scheduler: str | None = None,
    chunk_size: int | None = None,
    threads: int | None = None,
    resume: bool = True,
    progress: bool | Callable[[int, int], None] | None = None,
    motions: MotionsLike = None,
    utensils: UtensilsLike = None,
    default_rate: float | None = None,
) -> BatchSummary:
    """Answers every query of the file ``queries`` (Parquet, CSV or JSON lines; columns
    ``query_id``, ``kitchen_id``, ``goal``, ``method`` and optionally ``options``) over
    ``foon`` with ``kitchens``, into Parquet partitions in the folder ``out`` (schema
    :data:`foon._arrow.RESULT_SCHEMA`, one row per query, in query order across
    ``part-00000.parquet``, ``part-00001.parquet``, ...).

    ``engine``: ``"local"`` (the core's thread pool, ``threads`` threads) or ``"dask"``
    (``client``, a ``distributed.Client``, or ``scheduler``, its address; with neither, a
    local cluster of one single-threaded worker process per core; ``threads`` is then the
    core threads of each task, 1 by default). ``chunk_size``: queries per partition and per
    task (default :data:`DEFAULT_CHUNK_SIZE`). With ``resume`` (default), an ``out`` that
    holds an earlier run of the same inputs keeps its confirmed partitions and plans only
    the missing ones; ``resume=False`` replaces what is there. ``progress``: ``True`` draws
    a bar on stderr, a callable is called as ``progress(done_queries, total_queries)``
    after each partition. A bad query is a result row with its failure code; a bad input
    file is an error before any output is written: ``ValueError`` for the query file or the
    settings (``FileNotFoundError`` when it is missing), :class:`foon.ParseError` for the
    kitchen set file, ``FileExistsError`` for an output folder that holds another batch's
    results (see docs/BATCH.md)."""
    import threading

    import foon as _pkg
    from foon import _arrow

    if engine not in ("local", "dask"):
        raise ValueError(f"unknown engine {engine!r} (local or dask)")
    if engine == "local" and (client is not None or scheduler is not None):
        raise ValueError("client and scheduler are for engine='dask'")
    if not isinstance(resume, bool):
        raise TypeError(f"resume must be True or False, not {resume!r}")
    if not (progress is None or isinstance(progress, bool) or callable(progress)):
        raise TypeError(f"progress must be True, False, None or a callable, not {progress!r}")
    if chunk_size is None:
        chunk_size = DEFAULT_CHUNK_SIZE
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, int) or chunk_size < 1:
        raise ValueError(f"chunk_size must be a whole number of at least 1, not {chunk_size!r}")
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, int)
                                or threads < 1):  # fmt: skip
        raise ValueError(f"threads must be a whole number of at least 1, not {threads!r}")
    qpath = os.fspath(queries)
    opath = os.fspath(out)
    if isinstance(qpath, bytes) or isinstance(opath, bytes):
        raise TypeError("paths must be str")
    if not opath:
        raise ValueError("out must name a folder, not ''")
    if _is_output_file(qpath, opath):
        raise ValueError(f"{qpath}: the query file is one of the files a batch writes in {opath}")
    if (
        isinstance(kitchens, (str, os.PathLike))
        and os.path.isdir(kitchens)
        and os.path.realpath(kitchens) == os.path.realpath(opath)
    ):
        raise ValueError(f"{opath}: the output folder is the folder of kitchens")
    if client is not None:
        _check_client(client)
    f = _native_foon(foon)
    ks = _kitchen_set(kitchens)
    rates = _pkg._as_rates(motions)
    tools = _pkg._as_utensils(utensils)

    def plan(t: pa.Table, cancel: threading.Event) -> pa.Table:
        return _arrow.plan_table(f, ks, t, threads=threads, motions=rates, utensils=tools,
                                 default_rate=default_rate, cancel=cancel)  # fmt: skip

    # The settings (a default rate out of range, ...): the core's check, on no rows.
    plan(_empty_queries(), threading.Event())
    # Everything that can be wrong with the inputs is found before the output is touched.
    # Meanwhile (the local engine on more than one thread) the first chunk is planned, its
    # answers held: its kitchens' preparation need not wait for the whole file's check.
    # (Not when an earlier run's manifest lists that chunk: a resumed run plans only what is
    # missing.)
    # One thread asked for: one thread works at a time (pyarrow's readers included).
    alone = engine == "local" and threads == 1
    ahead = 1 if threads == 1 else LOCAL_AHEAD
    early = engine == "local" and ahead > 1 and not (resume and _listed(opath, part_key(0)))
    # The Dask client (and the local cluster it may start) is closed once the batch ends.
    with contextlib.ExitStack() as stack:
        first = _Early.start(qpath, chunk_size, plan) if early else None
        try:
            total = scan_queries(qpath, use_threads=not alone)
            if engine == "dask" and f.index_path is None:
                raise ValueError(
                    "the dask engine needs a FOON opened from a .foonidx file (see 'foon index')"
                )
            inputs: dict[str, Any] = {
                "index": f.fingerprint,
                "kitchens": ks.fingerprint,
                "queries": file_fingerprint(qpath),
                "settings": _settings_fingerprint(rates, tools, default_rate),
                "chunk_size": chunk_size,
                "rows": total,
            }
            if engine == "dask":
                # Connected before the output is touched: a scheduler that cannot be reached
                # leaves no folder behind.
                from foon import _dask

                client = stack.enter_context(_dask.connected(client, scheduler))
            kept = _prepare_output(opath, inputs, resume)
        except BaseException:
            if first is not None:
                first.stop()
            raise
        if first is not None and part_key(0) in kept:
            first.stop()
            first = None
        n_parts = partition_count(total, chunk_size)
        manifest: dict[str, Any] = {
            "format": _FORMAT,
            "inputs": inputs,
            "partitions": dict(sorted(kept.items())),
        }
        _write_json(opath, MANIFEST, manifest)

        done = sum(int(e["rows"]) for e in kept.values())
        bar = _Progress(total, done) if progress is True else None
        report: Callable[[int, int], None] | None = progress if callable(progress) else bar
        if bar is not None:
            bar(done, total)

        planned = [0, 0]
        saved = [time.monotonic(), False]  # when the manifest was last written; entries since

        def save(force: bool) -> None:
            now = time.monotonic()
            if saved[1] and (force or now - saved[0] >= MANIFEST_INTERVAL):
                _write_json(opath, MANIFEST, manifest)
                saved[0], saved[1] = now, False

        def record(k: int, entry: dict[str, Any]) -> None:
            """Partition ``k`` is written (``entry``, its manifest entry): counted once."""
            nonlocal done
            key = part_key(k)
            if key in manifest["partitions"]:
                return  # recorded already (a task run twice after a worker died)
            manifest["partitions"][key] = entry
            manifest["partitions"] = dict(sorted(manifest["partitions"].items()))
            saved[1] = True
            save(False)
            done += int(entry["rows"])
            planned[0] += 1
            planned[1] += int(entry["rows"])
            if report is not None:
                report(done, total)

        todo = (
            (k, t)
            for k, t in chunks(qpath, chunk_size, use_threads=not alone, rows=total)
            if part_key(k) not in kept
        )
        t0 = time.perf_counter()
        try:
            if engine == "local":
                _plan_locally(todo, plan, record, opath, ahead, first, overlap=not alone)
                first = None
            else:
                _dask.run(
                    todo,
                    record,
                    out=opath,
                    foon=f,
                    kitchens=ks,
                    client=client,
                    threads=threads,
                    motions=rates,
                    utensils=tools,
                    default_rate=default_rate,
                    token=hashlib.blake2b(
                        json.dumps(inputs, sort_keys=True).encode(), digest_size=8
                    ).hexdigest(),
                )
        except BaseException:
            if first is not None:
                first.stop()
            # An interrupted or failed run: the manifest lists every partition recorded so far.
            with contextlib.suppress(Exception):
                save(True)
            raise
        save(True)
        # Temporary files of writers that died (a killed worker) are removed; the partitions
        # are all whole and recorded.
        _clean(opath, everything=False)
        seconds = time.perf_counter() - t0
        if bar is not None:
            bar(done, total, True)
        if os.stat(qpath).st_size != inputs["queries"]["size"]:
            # Its rows were planned as they were when it was checked; its fingerprint is of that
            # content, which a rerun will not find.
            raise ValueError(f"{qpath}: the query file changed while the batch ran")
        if len(manifest["partitions"]) != n_parts:
            raise RuntimeError(
                f"{opath}: {n_parts - len(manifest['partitions'])} partitions were not written"
            )
        solved = 0
        failures: dict[str, int] = {}
        for e in manifest["partitions"].values():
            solved += int(e["solved"])
            for code, c in e["failures"].items():
                failures[code] = failures.get(code, 0) + int(c)
        return BatchSummary(
            queries=total,
            solved=solved,
            failures=failures,
            partitions=n_parts,
            planned_partitions=planned[0],
            planned_queries=planned[1],
            seconds=seconds,
            engine=engine,
            out=opath,
            chunk_size=chunk_size,
            kept_partitions=len(kept),
        )
