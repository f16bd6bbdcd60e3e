"""``foon paths``: every valid tree of a goal up to the limits, streamed (never a prompt); and
the output of ``foon plan --k K [--diverse]`` (the k best trees). Each tree is printed with
its rank, cost and units; ``--json`` (``--format json`` for ``plan``) prints, for each goal,
its trees as a list."""

from __future__ import annotations

import json
import sys

import foon
from foon.cli import UsageError

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse
    from collections.abc import Iterable, Sequence

    from foon._kbest import RankedTree

__all__ = ["add_paths_options", "cmd_paths", "print_ranked"]


def _count(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise UsageError(f"expected a whole number, not {text!r}") from None
    if v < 0:
        raise UsageError(f"expected a number of at least 0, not {v}")
    return v


def add_paths_options(sp: argparse.ArgumentParser) -> None:
    from foon.cli import _common

    _common(sp, motions=False)
    sp.add_argument(
        "--max-trees", type=_count, metavar="N", help="stop after N trees (default: all)"
    )
    sp.add_argument("--max-height", type=_count, metavar="H", help="leave out trees higher than H")
    sp.add_argument("--json", action="store_true", help="machine-readable output")


def print_ranked(
    f: foon.Foon,
    goals: Sequence[foon.Object | str],
    trees: Iterable[Iterable[RankedTree]],
    as_json: bool,
) -> int:
    """Writes each goal's trees as they come; returns 1 when a goal has none."""
    out = sys.stdout
    failed = 0
    if as_json:
        out.write("[")
    for i, (g, ranked) in enumerate(zip(goals, trees, strict=True)):
        label = g if isinstance(g, str) else g.label
        if as_json:
            out.write(("," if i else "") + '\n  {"goal": ' + json.dumps(label) + ', "trees": [')
        else:
            out.write(f"# goal: {label}\n")
        n = 0
        for r in ranked:
            if as_json:
                out.write(("," if n else "") + "\n    " + json.dumps(r.to_dict()))
            else:
                t = r.tree
                units = " ".join(map(str, r.units))
                out.write(f"#{r.rank} cost {r.cost:g} ({len(r.units)} units, height "
                          f"{t.height}): {units}\n{t.to_text()}")  # fmt: skip
            n += 1
            out.flush()
        if as_json:
            out.write("\n  ]}" if n else "]}")
        elif not n:
            out.write("no tree\n")
        failed += n == 0
    if as_json:
        out.write("\n]\n")
    out.flush()
    return 1 if failed else 0


def _goals(args: argparse.Namespace, ex: foon.Example | None) -> list[foon.Object | str]:
    from foon._cli_commands import as_goal, read_raw_goals

    if args.goals is None and args.goal is None and args.label is None:
        if ex is None:
            raise UsageError("give the goals with --goals FILE, --goal JSON or --label TEXT")
        return list(ex.goals)
    return [as_goal(g) for g in read_raw_goals(args, ex)]


def cmd_paths(args: argparse.Namespace) -> int:
    from foon._cli_commands import inputs

    f, kitchen, _motions, utensils, ex = inputs(args)
    goals = _goals(args, ex)
    planner = f.planner(kitchen, utensils=utensils)
    trees = (planner.paths(g, max_trees=args.max_trees, max_height=args.max_height) for g in goals)
    return print_ranked(f, goals, trees, args.json)


def plan_k(args: argparse.Namespace) -> int:
    """``foon plan --k K [--diverse]``."""
    from foon._cli_commands import inputs

    if args.k < 1:
        raise UsageError(f"--k must be at least 1 (got {args.k})")
    if not args.method.startswith("optimal-"):
        raise UsageError(
            f"--k needs an optimal method (optimal-success, optimal-units or optimal-inputs), "
            f"not {args.method}"
        )
    if args.format not in ("text", "json") or args.out is not None:
        raise UsageError("--k prints text or --format json, to standard output")
    f, kitchen, motions, utensils, ex = inputs(args)
    goals = _goals(args, ex)
    planner = f.planner(kitchen, motions=motions, utensils=utensils, default_rate=args.default_rate)
    ids = [f.goal_id(g) for g in goals]  # every goal found before anything is written
    trees = (planner.plan_k(g, args.k, args.method, diverse=args.diverse) for g in ids)
    return print_ranked(f, goals, trees, args.format == "json")
