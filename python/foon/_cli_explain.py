"""``foon explain``: why a goal can or cannot be made from a kitchen (computed in the core,
see :meth:`foon.Foon.explain`), as text for people, ``--json`` for programs, or the
blocking part as a picture (``--format dot|svg|png|pdf|html``)."""

from __future__ import annotations

import json
import sys

import foon
from foon._cli_commands import as_goal, inputs, read_raw_goals
from foon.cli import CliError, UsageError, _common, _nodes_arg

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse

__all__ = ["add_explain_options", "cmd_explain", "write_document"]

#: The picture formats of ``foon explain``.
PICTURES = ("dot", "svg", "png", "pdf", "html")

_SOUND = ("ids", "greedy-success", "greedy-inputs", "optimal-success", "optimal-units",
          "optimal-inputs")  # fmt: skip


def add_explain_options(sp: argparse.ArgumentParser) -> None:
    _common(sp)
    sp.add_argument(
        "--method",
        choices=_SOUND,
        default=None,
        help="the objective of the best tree reported for a derivable goal (default: "
        "optimal-success with --motions or --default-rate, else optimal-units)",
    )
    sp.add_argument("--count", choices=["nodes", "ingredients"], default="nodes")
    sp.add_argument("--default-rate", type=float, default=None, metavar="R",
                    help="success rate of motions missing from --motions")  # fmt: skip
    sp.add_argument(
        "--level",
        type=int,
        choices=(1, 2, 3),
        default=3,
        help="identity level for matching the kitchen and the goal: 3 full identity "
        "(default), 2 ingredients ignored, 1 labels only",
    )
    sp.add_argument("--json", action="store_true", help="print the explanation as JSON")
    sp.add_argument(
        "--format",
        choices=PICTURES,
        default=None,
        help="draw the blocking part instead (a derivable goal: its best tree); svg, png, "
        "pdf and html run Graphviz",
    )
    sp.add_argument("-o", "--out", metavar="FILE", help="with --format: write to FILE")
    sp.add_argument("--title", metavar="TEXT", help="with --format: the picture's title")
    sp.add_argument(
        "--max-nodes",
        type=_nodes_arg,
        metavar="N",
        help=f"largest picture drawn, in nodes (default: {foon.MAX_PICTURE_NODES:,})",
    )


def write_document(path: str | None, data: bytes, fmt: str, inputs: list[str | None]) -> None:
    """Writes a whole document to ``path`` (stdout when None) as ``foon export -o`` does:
    into a stream, or by replacing the file only once everything is written."""
    import os

    from foon._cli_commands import _Stdout
    from foon._cli_out import OutDir, OutError, is_stream

    if path is None:
        _Stdout(fmt)(data)
        return
    folder, name = os.path.split(path)
    if not name:
        raise UsageError(f"--out: {path!r} names a folder, not a file")
    if is_stream(path):
        try:
            with open(path, "wb") as fh:
                fh.write(data)
        except OSError as e:
            raise CliError(f"{path}: cannot write: {e.strerror or e}") from None
        return
    try:
        out = OutDir(folder or ".", [name], inputs)
        try:
            out.write(0, data)
            out.commit()
        finally:
            out.abort()
    except OutError as e:
        raise CliError(str(e)) from None


def cmd_explain(args: argparse.Namespace) -> int:
    if args.format is None and (args.out or args.title or args.max_nodes is not None):
        raise UsageError("-o, --title and --max-nodes go with --format")
    if args.format is not None and args.json:
        raise UsageError("--json and --format are exclusive")
    f, kitchen, motions, utensils, ex = inputs(args)
    goals = read_raw_goals(args, ex)
    if len(goals) != 1:
        raise UsageError("foon explain takes exactly one goal")
    planner = f.planner(
        kitchen,
        motions=motions,
        utensils=utensils,
        default_rate=args.default_rate,
        level=args.level,
    )
    try:
        e = planner.explain(as_goal(goals[0]), args.method, count=args.count)
    except foon.GoalNotFoundError as err:
        raise CliError(str(err)) from None
    if args.format is not None:
        data = e.write(args.format, title=args.title, max_nodes=args.max_nodes)
        raw = data if isinstance(data, bytes) else data.encode("utf-8")
        write_document(args.out, raw, args.format,
                       [args.foon, args.kitchen, args.motions, args.utensils, args.goals])  # fmt: skip
    elif args.json:
        sys.stdout.write(json.dumps(e.to_dict(), indent=2) + "\n")
    else:
        sys.stdout.write(e.text)
    return 0 if e.derivable else 1
