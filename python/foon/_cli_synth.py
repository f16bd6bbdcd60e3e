"""``foon synth``: writes a synthetic merged FOON, and optionally its kitchen, goals and
motion table (the generator is in the core; see :mod:`foon._synth`)."""

from __future__ import annotations

import os
import sys

from foon import _foon, _synth
from foon._cli_out import is_stream
from foon.cli import UsageError

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse


def _nonnegative(text: str) -> int:
    import argparse

    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if n < 0:
        raise argparse.ArgumentTypeError(f"must be at least 0, not {n}")
    return n


def add_synth_options(sp: argparse.ArgumentParser) -> None:
    """The options of ``foon synth``."""
    sp.add_argument(
        "--units",
        type=int,
        required=True,
        metavar="N",
        help=f"functional units, exactly (1 to {_synth.MAX_SYNTH_UNITS:,})",
    )
    sp.add_argument("--seed", type=_nonnegative, default=0, metavar="S", help="seed (default: 0)")
    sp.add_argument(
        "-o", "--out", required=True, metavar="FILE", help="the FOON file ('-' for stdout)"
    )
    sp.add_argument("--kitchen", metavar="FILE", help="also write the matching kitchen (JSON)")
    sp.add_argument("--goals", metavar="FILE", help="also write a goal file (JSON)")
    sp.add_argument(
        "--goal-count",
        type=_nonnegative,
        default=25,
        metavar="N",
        help="goals in --goals, spread over the FOON (default: 25)",
    )
    sp.add_argument("--motions", metavar="FILE", help="also write the motion rate table")
    sp.add_argument(
        "--threads", type=_nonnegative, metavar="N", help="threads (default: all cores)"
    )
    sp.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def cmd_synth(args: argparse.Namespace) -> int:
    """Writes the FOON (atomically, or to stdout), then the side files asked for."""
    from foon._progress import wanted

    names = [p for p in (args.kitchen, args.goals, args.motions) if p is not None]
    if any(p == "-" for p in names):
        raise UsageError("--kitchen, --goals and --motions need file names, not '-'")
    files = [p for p in (args.out, *names) if p != "-" and not is_stream(p)]
    if len({os.path.realpath(p) for p in files}) < len(files):
        raise UsageError("the output files must differ")
    threads = None if args.threads in (None, 0) else args.threads
    if args.out == "-":
        sys.stdout.flush()
    # Written atomically; a device or a FIFO is written into, never replaced.
    path = None if args.out == "-" else args.out
    _foon.synth_write(args.units, args.seed, path, threads, None, wanted(args.quiet))
    for what, path in (("kitchen", args.kitchen), ("goals", args.goals), ("motions", args.motions)):
        if path is not None:
            _foon.synth_side(args.units, args.seed, what, args.goal_count, path)
    return 0
