"""``foon find TEXT``: objects ranked by the similarity of their label, states and
container to a free-text query (computed in the core, see :meth:`foon.Foon.find_similar`)."""

from __future__ import annotations

import json
import sys

from foon._cli_commands import load_foon
from foon.cli import UsageError

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse

__all__ = ["add_find_options", "cmd_find"]


def add_find_options(sp: argparse.ArgumentParser) -> None:
    sp.add_argument("text", metavar="TEXT", help='the query, e.g. "chopped onion in bowl"')
    sp.add_argument("--foon", metavar="FILE", help="FOON file (default: the example)")
    sp.add_argument("-k", type=int, default=10, metavar="K", help="how many objects (default 10)")
    sp.add_argument("--strict", action="store_true", help="turn load warnings into errors")
    sp.add_argument("--json", action="store_true", help="print the objects as JSON")


def cmd_find(args: argparse.Namespace) -> int:
    import foon

    if args.k < 0:
        raise UsageError("-k must be 0 or more")
    f = foon.example().foon if args.foon is None else load_foon(args.foon, args.strict)
    found = f.find_similar(args.text, args.k)
    if args.json:
        sys.stdout.write(json.dumps([s.to_dict() for s in found], indent=2) + "\n")
    else:
        for s in found:
            sys.stdout.write(f"{s.score:.3f}\t{s.object_id}\t{s.object}\n")
    return 0
