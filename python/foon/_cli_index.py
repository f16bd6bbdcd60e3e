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
from foon.cli import CliError, UsageError, one_line

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse

#: The file names a folder contributes: FOON text and the lab's JSON.
FOON_SUFFIXES = (".txt", ".foon", ".json")


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


def sources(paths: list[str]) -> list[str]:
    """The files to index: each file as given, each folder's FOON files in sorted order."""
    out: list[str] = []
    for p in paths:
        if os.path.isdir(p):
            names = sorted(
                n
                for n in os.listdir(p)
                if n.lower().endswith(FOON_SUFFIXES) and os.path.isfile(os.path.join(p, n))
            )
            if not names:
                raise CliError(f"{p}: the folder holds no FOON files ({', '.join(FOON_SUFFIXES)})")
            out.extend(os.path.join(p, n) for n in names)
        else:
            out.append(p)
    return out


def cmd_index(args: argparse.Namespace) -> int:
    files = sources(list(args.files))
    target = os.path.realpath(args.output)
    for p in files:
        if os.path.realpath(p) == target:
            raise UsageError(f"-o {args.output}: refusing to write the index over an input")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", foon.FoonWarning)
        f = foon.Foon.load_sources(files, strict=args.strict)
    for w in caught:
        print(f"foon: warning: {one_line(str(w.message))}", file=sys.stderr)
    f.write_index(args.output)
    return 0
