"""``foon merge FILE|DIR... -o OUT``: many FOONs into one, with provenance and support (the
rules are the core's, see :func:`foon.merge`); and the text of ``foon stats --provenance``."""

from __future__ import annotations

import sys

from foon import _foon
from foon._merge import MergeReport, provenance_lines
from foon.cli import UsageError, one_line

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse

__all__ = ["add_merge_options", "cmd_merge", "provenance_lines"]


def add_merge_options(sp: argparse.ArgumentParser) -> None:
    sp.add_argument(
        "inputs",
        nargs="+",
        metavar="FILE|DIR",
        help="FOON files (text or the lab's JSON) and folders (their .txt and .json files, "
        "sorted by name), read in the order given",
    )
    sp.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="OUT",
        help="the merged FOON, as FOON text with its provenance as '#' lines "
        "(written atomically, never over an input; '-' for standard output)",
    )
    sp.add_argument(
        "--level",
        type=int,
        choices=(1, 2, 3),
        default=3,
        help="identity level for duplicates: 3 full identity (default), "
        "2 ingredients ignored, 1 labels only",
    )
    sp.add_argument(
        "--min-support",
        type=int,
        default=1,
        metavar="K",
        help="keep only the units found in at least K sources (default 1)",
    )
    sp.add_argument("--strict", action="store_true", help="turn load warnings into errors")
    sp.add_argument("--json", action="store_true", help="print the summary as JSON")
    sp.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def _warn(items: list[tuple[str | None, int, int, str, str]]) -> None:
    for path, line, col, kind, message in items:
        text = one_line(f"{path or '<string>'}:{line}:{col}: {message} [{kind}]")
        print(f"foon: warning: {text}", file=sys.stderr)


def cmd_merge(args: argparse.Namespace) -> int:
    from foon._progress import wanted

    if args.min_support < 1:
        raise UsageError(f"--min-support must be at least 1 (got {args.min_support})")
    to_stdout = args.output == "-"
    native, raw = _foon.merge_paths(
        list(args.inputs),
        level=args.level,
        min_support=args.min_support,
        strict=args.strict,
        out=None if to_stdout else args.output,
        progress=wanted(args.quiet),
    )
    report = MergeReport(raw)
    _warn(native.warnings())
    if to_stdout:
        sys.stdout.write(_foon.merged_text(native, report.header))
        sys.stdout.flush()
    summary = sys.stderr if to_stdout else sys.stdout
    if args.json:
        import json

        d = report.to_dict()
        d.pop("header")
        d["output"] = args.output
        print(json.dumps(d, sort_keys=True), file=summary)
    else:
        print(report.summary, file=summary)
    return 0
