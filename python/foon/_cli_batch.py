"""``foon batch QUERIES --foon FILE.foonidx --kitchens K -o OUT``: a file of queries planned
into Parquet partitions, locally or on a Dask cluster (see :func:`foon.batch`); a summary
at the end (``--json`` for programs)."""

from __future__ import annotations

import json
import sys

from foon.cli import CliError, SigtermStops, one_line

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse

    from foon._batch import BatchSummary

__all__ = ["add_batch_options", "cmd_batch", "summary_text"]


def _positive(text: str) -> int:
    import argparse

    if not (text.isascii() and text.isdigit()) or int(text) < 1:
        raise argparse.ArgumentTypeError(f"not a whole number of at least 1: {text!r}")
    return int(text)


def add_batch_options(sp: argparse.ArgumentParser) -> None:
    from foon.cli import _threads

    sp.add_argument(
        "queries",
        metavar="QUERIES",
        help="the queries: a .parquet, .csv or .jsonl table of query_id, kitchen_id, goal, "
        "method and optionally options",
    )
    sp.add_argument("--foon", required=True, metavar="FILE", help="the FOON (a .foonidx index)")
    sp.add_argument(
        "--kitchens",
        required=True,
        metavar="K",
        help="the kitchens: a JSON object of id to items, a base with per-id deltas, or a "
        "folder of kitchen files",
    )
    sp.add_argument(
        "-o", "--out", required=True, metavar="OUT", help="the results folder (Parquet parts)"
    )
    sp.add_argument("--engine", choices=("local", "dask"), default="local", help="default: local")
    sp.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="dask: the scheduler's address (default: a local cluster, one worker per core)",
    )
    sp.add_argument(
        "--chunk-size",
        type=_positive,
        metavar="N",
        help="queries per partition and per Dask task (default: 20,000)",
    )
    sp.add_argument(
        "--threads",
        type=_threads,
        metavar="N",
        help="local: threads (default: all cores); dask: core threads per task (default: 1)",
    )
    sp.add_argument("--motions", metavar="FILE", help="motion success rates")
    sp.add_argument("--utensils", metavar="FILE", help="utensil list (container rule)")
    sp.add_argument(
        "--default-rate",
        type=float,
        metavar="R",
        help="success rate for motions missing from the table",
    )
    sp.add_argument(
        "--overwrite",
        action="store_true",
        help="replace the results in OUT (by default a rerun of the same inputs resumes, and "
        "other inputs are an error)",
    )
    sp.add_argument("--json", action="store_true", help="print the summary as JSON")
    sp.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def _n(x: int) -> str:
    return f"{x:,}"


def summary_text(s: BatchSummary) -> str:
    """The summary: queries, solved, failures by code, partitions, time and throughput."""
    lines = [
        f"{_n(s.queries)} queries: {_n(s.solved)} solved, {_n(s.queries - s.solved)} failed",
    ]
    for code, n in sorted(s.failures.items(), key=lambda kv: (-kv[1], kv[0])):
        lines.append(f"  {code}: {_n(n)}")
    rate = "" if s.throughput is None else f", {s.throughput:,.0f} queries/s"
    kept = f", {_n(s.kept_partitions)} kept from an earlier run" if s.kept_partitions else ""
    lines.append(
        f"{_n(s.partitions)} partitions in {s.out} ({_n(s.planned_partitions)} planned{kept}); "
        f"{_n(s.planned_queries)} queries planned in {s.seconds:.2f} s{rate} ({s.engine})"
    )
    return "\n".join(lines) + "\n"


def cmd_batch(args: argparse.Namespace) -> int:
    from foon._progress import wanted

    try:
        import pyarrow  # type: ignore[import-untyped]  # noqa: F401
    except ImportError:
        raise CliError("foon batch needs pyarrow: pip install 'foon[batch]'") from None
    if args.engine == "dask":
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise CliError("--engine dask needs dask: pip install 'foon[dask]'") from None
    elif args.scheduler is not None:
        raise CliError("--scheduler is for --engine dask")
    from foon._batch import batch

    try:
        with SigtermStops():
            summary = batch(
                args.queries,
                foon=args.foon,
                kitchens=args.kitchens,
                out=args.out,
                engine=args.engine,
                scheduler=args.scheduler,
                chunk_size=args.chunk_size,
                threads=args.threads,
                resume=not args.overwrite,
                progress=wanted(args.quiet),
                motions=args.motions,
                utensils=args.utensils,
                default_rate=args.default_rate,
            )
    except (ValueError, RuntimeError, TypeError) as e:
        raise CliError(one_line(str(e))) from None
    if args.json:
        sys.stdout.write(json.dumps(summary.to_dict(), indent=2) + "\n")
    else:
        sys.stdout.write(summary_text(summary))
    return 0
