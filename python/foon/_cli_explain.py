"""``foon explain``: why a goal can or cannot be made from a kitchen (computed in the core,
see :meth:`foon.Foon.explain`), as text for people or ``--json`` for programs."""

from __future__ import annotations

import json
import sys

import foon
from foon._cli_commands import as_goal, inputs, read_raw_goals
from foon.cli import CliError, UsageError, _common

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse

__all__ = ["add_explain_options", "cmd_explain"]

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


def cmd_explain(args: argparse.Namespace) -> int:
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
    if args.json:
        sys.stdout.write(json.dumps(e.to_dict(), indent=2) + "\n")
    else:
        sys.stdout.write(e.text)
    return 0 if e.derivable else 1
