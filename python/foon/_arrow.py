"""Queries in, results out, as Arrow tables: :func:`plan_table`.

The query rows (:data:`QUERY_COLUMNS`) go to the core as columns; the answers come back as
Arrow-shaped buffers (validity bitmaps, little-endian values, offsets) wrapped here with
``pyarrow.Array.from_buffers``, never row by row. The schemas and failure codes are in
``docs/BATCH.md`` ("Formats"). Importing this module imports ``pyarrow``; ``import foon``
does not."""

from __future__ import annotations

from typing import TYPE_CHECKING

import pyarrow as pa  # type: ignore[import-untyped]

from foon import Foon, _as_rates, _as_utensils, _foon, _type
from foon._kitchens import KitchenSet

if TYPE_CHECKING:
    import threading

    from foon import MotionsLike, UtensilsLike

#: The columns of a query table, in order (``options`` may be absent).
QUERY_COLUMNS: tuple[str, ...] = ("query_id", "kitchen_id", "goal", "method", "options")

#: The columns of a result table.
RESULT_SCHEMA: pa.Schema = pa.schema(
    [
        ("query_id", pa.string()),
        ("solved", pa.bool_()),
        ("fu_count", pa.uint32()),
        ("height", pa.uint32()),
        ("success", pa.float64()),
        ("cost", pa.float64()),
        ("leaf_count", pa.uint32()),
        ("units", pa.list_(pa.uint32())),
        ("failure", pa.string()),
        ("missing", pa.list_(pa.string())),
        ("message", pa.string()),
    ]
)

#: Every failure code, in documentation order.
FAILURE_CODES: tuple[str, ...] = tuple(_foon.failure_codes())


#: A string column as the core reads it: the array's offset, its validity bitmap (``None``
#: when no value is null), its offsets, its data, and whether the offsets are 64-bit.
_Strings = tuple[int, bytes | None, bytes, bytes, bool]


def _text_column(
    queries: pa.Table | pa.RecordBatch, name: str, required: bool = True
) -> _Strings | None:
    """A string column as Arrow buffers (:data:`_Strings`); ``None`` when it is absent or
    all null and not required; ``ValueError`` naming it when it is absent (and required) or
    not strings."""
    if name not in queries.column_names:
        if not required:
            return None
        raise ValueError(
            f"the query table has no column '{name}' (columns: {', '.join(queries.column_names)})"
        )
    col = queries.column(name)
    t = col.type
    if pa.types.is_null(t) and not required:
        return None
    if pa.types.is_dictionary(t) and (
        pa.types.is_string(t.value_type) or pa.types.is_large_string(t.value_type)
    ):
        col = col.cast(pa.string())
    elif not (pa.types.is_string(t) or pa.types.is_large_string(t)):
        raise ValueError(f"query column '{name}' must be strings, not {t}")
    if isinstance(col, pa.ChunkedArray):
        col = col.combine_chunks()
    valid, offsets, data = col.buffers()
    return (
        col.offset,
        None if valid is None or col.null_count == 0 else valid.to_pybytes(),
        b"" if offsets is None else offsets.to_pybytes(),
        b"" if data is None else data.to_pybytes(),
        pa.types.is_large_string(col.type),
    )


def _query_ids(queries: pa.Table | pa.RecordBatch) -> pa.Array | pa.ChunkedArray:
    if "query_id" not in queries.column_names:
        raise ValueError(
            f"the query table has no column 'query_id' (columns: {', '.join(queries.column_names)})"
        )
    col = queries.column("query_id")
    t = col.type
    if pa.types.is_integer(t) or pa.types.is_large_string(t) or pa.types.is_dictionary(t):
        try:
            return col.cast(pa.string())
        except (pa.ArrowInvalid, pa.ArrowNotImplementedError):
            raise ValueError(
                f"query column 'query_id' must be strings or integers, not {t}"
            ) from None
    if not pa.types.is_string(t):
        raise ValueError(f"query column 'query_id' must be strings or integers, not {t}")
    return col


def plan_table(
    foon: Foon,
    kitchens: KitchenSet,
    queries: pa.Table | pa.RecordBatch,
    *,
    threads: int | None = None,
    motions: MotionsLike = None,
    utensils: UtensilsLike = None,
    default_rate: float | None = None,
    deltas: str = "incremental",
    cancel: threading.Event | None = None,
) -> pa.Table:
    """Answers every query row (columns :data:`QUERY_COLUMNS`) over ``foon`` with the
    kitchens of ``kitchens``: one result row per query, in query order, in the schema
    :data:`RESULT_SCHEMA`. A row that cannot be planned (unknown kitchen or method, bad
    goal or options) is a result row with its failure code. ``threads`` as for
    :meth:`foon.Planner.plan_many`; ``motions``, ``utensils`` and ``default_rate`` as for
    :meth:`foon.Foon.plan` (a row's ``default_rate`` option replaces it). ``deltas`` is how
    the kitchens given as a base plus a delta are prepared: ``"incremental"`` (from the
    base kitchen's preparation, the default) or ``"from-scratch"`` (from their own items);
    the answers are the same either way. The interpreter is released while the core plans.
    ``cancel``: once this event is set, the call stops and raises ``KeyboardInterrupt``, as
    Ctrl-C does (how a call made off the main thread, which sees no signals, is stopped)."""
    if not isinstance(foon, Foon):
        raise TypeError(f"foon must be a Foon, not {_type(foon)}")
    if not isinstance(kitchens, KitchenSet):
        raise TypeError(f"kitchens must be a KitchenSet, not {_type(kitchens)}")
    if not isinstance(queries, pa.Table | pa.RecordBatch):
        raise TypeError(f"queries must be a pyarrow Table or RecordBatch, not {_type(queries)}")
    query_ids = _query_ids(queries)
    kitchen_ids = _text_column(queries, "kitchen_id")
    goals = _text_column(queries, "goal")
    methods = _text_column(queries, "method")
    options = _text_column(queries, "options", required=False)
    assert kitchen_ids is not None and goals is not None and methods is not None
    rates = _as_rates(motions)
    raw = _foon.plan_query_columns(
        foon._native,
        kitchens._native,
        queries.num_rows,
        kitchen_ids,
        goals,
        methods,
        options,
        threads,
        _as_utensils(utensils),
        None if rates is None else list(rates.items()),
        default_rate,
        deltas,
        cancel,
    )
    n = raw[0]
    b = pa.py_buffer

    def fixed(t: pa.DataType, valid: bytes, values: bytes) -> pa.Array:
        return pa.Array.from_buffers(t, n, [b(valid), b(values)])

    def strings(valid: bytes, offsets: bytes, data: bytes) -> pa.Array:
        return pa.Array.from_buffers(pa.string(), n, [b(valid), b(offsets), b(data)])

    def last_offset(offsets: bytes) -> int:
        return int.from_bytes(offsets[-4:], "little", signed=True)

    unit_values = pa.Array.from_buffers(pa.uint32(), last_offset(raw[12]), [None, b(raw[13])])
    units = pa.Array.from_buffers(
        RESULT_SCHEMA.field("units").type, n, [None, b(raw[12])], children=[unit_values]
    )
    missing_values = pa.Array.from_buffers(
        pa.string(), last_offset(raw[17]), [None, b(raw[18]), b(raw[19])]
    )
    missing = pa.Array.from_buffers(
        RESULT_SCHEMA.field("missing").type, n, [None, b(raw[17])], children=[missing_values]
    )
    arrays = [
        query_ids,
        pa.Array.from_buffers(pa.bool_(), n, [None, b(raw[1])]),
        fixed(pa.uint32(), raw[2], raw[3]),
        fixed(pa.uint32(), raw[4], raw[5]),
        fixed(pa.float64(), raw[6], raw[7]),
        fixed(pa.float64(), raw[8], raw[9]),
        fixed(pa.uint32(), raw[10], raw[11]),
        units,
        strings(raw[14], raw[15], raw[16]),
        missing,
        strings(raw[20], raw[21], raw[22]),
    ]
    return pa.Table.from_arrays(arrays, schema=RESULT_SCHEMA)
