"""``foon index FILE|DIR... -o OUT.foonidx [--strict]``: one ``.foonidx`` index file built
from FOON files of any dialect, in the order given (a folder stands for its FOON files, in
sorted order), with the source and line of every unit kept. The file is written atomically
and never over one of its inputs; ``foon.load`` and every command open it.
"""

from __future__ import annotations

import os
import sys
import warnings

import foon
from foon.cli import UsageError, one_line

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse


def add_index_options(sp: argparse.ArgumentParser) -> None:
    sp.add_argument(
        "files",
        nargs="+",
        metavar="FILE|DIR",
        help="FOON files (text or JSON), in order; a folder gives its FOON files, sorted",
    )
    sp.add_argument("-o", "--output", required=True, metavar="OUT", help="the index file to write")
    sp.add_argument(
        "--strict", action="store_true", help="treat every annotation warning as an error"
    )
    sp.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def cmd_index(args: argparse.Namespace) -> int:
    from foon._progress import wanted

    target = os.path.realpath(args.output)
    for p in args.files:
        if os.path.realpath(p) == target:
            raise UsageError(f"-o {args.output}: refusing to write the index over an input")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", foon.FoonWarning)
        f = foon.Foon.load_sources(args.files, strict=args.strict, progress=wanted(args.quiet))
    for w in caught:
        print(f"foon: warning: {one_line(str(w.message))}", file=sys.stderr)
    f.write_index(args.output)
    return 0
