"""``foon split``: the robot/human split of each goal (the front of success against human
steps, each point's tree and who does which step; see :meth:`foon.Foon.split`)."""

from __future__ import annotations

import json
import math
import sys

import foon
from foon._cli_commands import NotFound, inputs, read_goals, resolve
from foon.cli import UsageError, error

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse
    from typing import Any


def _budget(text: str) -> int:
    import argparse

    if not (text.isascii() and text.isdigit()):
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}")
    n = int(text)
    if n > 2**32 - 2:
        raise argparse.ArgumentTypeError(f"too large: {text}")
    return n


def add_split_options(sp: argparse.ArgumentParser) -> None:
    """The options of ``foon split``."""
    sp.add_argument("--foon", metavar="FILE", help="FOON file (default: the example)")
    sp.add_argument("--kitchen", metavar="FILE", help="kitchen: JSON list or object blocks")
    sp.add_argument("--utensils", metavar="FILE", help="utensil list (container rule)")
    g = sp.add_mutually_exclusive_group()
    g.add_argument("--goals", metavar="FILE", help="goal file")
    g.add_argument("--goal", metavar="JSON", help="one goal (or a list of goals) as JSON")
    g.add_argument("--label", metavar="TEXT", help="a goal label that one object has")
    sp.add_argument("--strict", action="store_true", help="turn load warnings into errors")
    sp.add_argument(
        "--profile",
        action="append",
        default=[],
        metavar="NAME=FILE",
        help="a success profile: a motion table under a name (repeatable)",
    )
    sp.add_argument(
        "--override",
        action="append",
        default=[],
        metavar="NAME=FILE",
        help="per-unit rate overrides (unit<TAB>rate lines) for a profile (repeatable)",
    )
    sp.add_argument(
        "--motions",
        metavar="FILE",
        help="the robot's motion table when no --profile names it (default: the example's)",
    )
    sp.add_argument("--robot", default="robot", metavar="NAME", help="the robot's profile")
    sp.add_argument(
        "--human", default="human", metavar="NAME", help="the human's profile (default: rate 1)"
    )
    sp.add_argument(
        "--default-rate",
        type=float,
        metavar="R",
        help="the robot's rate for motions missing from its table",
    )
    sp.add_argument(
        "--max-human",
        type=_budget,
        default=1,
        metavar="M",
        help="the most steps the human may do (default: 1)",
    )
    sp.add_argument(
        "--fixed-tree",
        action="store_true",
        help="also the lab's method: the best robot tree, its lowest-rate steps to the human",
    )
    sp.add_argument("--json", action="store_true", help="machine-readable output")
    sp.add_argument(
        "--format",
        choices=("html",),
        default=None,
        help="html: one goal's split as a page (the front as a chart, each point's steps)",
    )
    sp.add_argument("-o", "--out", metavar="FILE", help="with --format: write to FILE")
    sp.add_argument("--title", metavar="TEXT", help="with --format: the page's title")


def _profiles(args: argparse.Namespace, motions: foon.MotionRates | None) -> foon.Profiles:
    try:
        p = foon.Profiles.parse(args.profile, args.override)
    except ValueError as e:
        raise UsageError(str(e)) from None
    names = dict(p)
    r = names.get(args.robot)
    if r is None or r.rates is None:
        # Overrides alone: over the --motions table (or the example's).
        if motions is None:
            raise UsageError(f"give the robot's rates: --profile {args.robot}=FILE or --motions")
        r = r or foon.Profile()
        names[args.robot] = foon.Profile(motions, r.default_rate, r.overrides,
                                         r.overrides_path, r._lines)  # fmt: skip
    if args.default_rate is not None:
        r = names[args.robot]
        names[args.robot] = foon.Profile(
            r.rates, args.default_rate, r.overrides, r.overrides_path, r._lines
        )
    return foon.Profiles(names)


def _text(f: foon.Foon, r: foon.SplitResult) -> str:
    lines = [f"goal: {f.object(r.goal)}"]
    if not r.solved:
        if r.missing:
            items = "; ".join(str(f.object(o)) for o in r.missing)
            lines.append(f"  cannot be made: missing {items}")
        elif r.cycle:
            chain = " -> ".join(str(f.object(o)) for o in r.cycle)
            lines.append(f"  cannot be made: blocked by the cycle {chain}")
        else:
            lines.append("  cannot be made: every tree needs a step of rate 0")
        return "\n".join(lines) + "\n"
    lines.append("  budget  success")
    for m, b in enumerate(r.best):
        lines.append(f"  {m:>6}  {'-' if b is None else f'{b:.6g}'}")
    for p in r.front:
        lines.append(f"  front: {p.human} human step(s), success {p.success:.6g}")
        for i, s in enumerate(p.steps, 1):
            times = f" x{s.times}" if s.times != 1 else ""
            motion = f.fu(s.unit).motion
            lines.append(
                f"    {i}. {s.actor:<5} unit {s.unit} ({motion}) -> {f.object(s.object)}{times}"
            )
    if r.fixed is not None:
        lines.append("  fixed tree (the lab's method):")
        for q in r.fixed:
            who = ", ".join(f"{u}" + (f" x{t}" if t != 1 else "") for u, a, t in q.steps
                            if a == "human")  # fmt: skip
            lines.append(f"  {q.human:>6}  {q.success:.6g}  human: {who or '-'}")
    return "\n".join(lines) + "\n"


def _json_safe(d: Any) -> Any:
    if isinstance(d, float) and not math.isfinite(d):
        return None
    if isinstance(d, dict):
        return {k: _json_safe(v) for k, v in d.items()}
    if isinstance(d, list):
        return [_json_safe(v) for v in d]
    return d


def compare_rows(
    planner: foon.Planner,
    resolved: list[int | NotFound],
    max_human: int,
    motions: foon.MotionRates | None,
    default_rate: float | None,
) -> list[Any]:
    """``foon compare --split M``: rows ``split M=..`` and ``fixed-tree M=..`` for each goal
    (the robot's rates are the comparison's table, the human's are 1); success as tree cost
    counts it, the best with at most M human steps."""
    import time

    if motions is None and default_rate is None:
        raise UsageError("--split needs the robot's rates: give --motions FILE")
    profiles = foon.Profiles({"robot": foon.Profile(motions, default_rate)})
    names = (f"split M={max_human}", f"fixed-tree M={max_human}")
    split_rows: list[Any] = []
    fixed_rows: list[Any] = []
    for r in resolved:
        if isinstance(r, NotFound):
            for name, rows in zip(names, (split_rows, fixed_rows), strict=True):
                rows.append((name, str(r.goal), r.message))
            continue
        t0 = time.perf_counter()
        s = planner.split(r, profiles, max_human, fixed_tree=True)
        seconds = time.perf_counter() - t0
        p = s.front[-1] if s.front else None
        units = None if p is None else len(p.units)
        split_rows.append(
            (names[0], r, s.solved, units, s.best[-1], s.expanded, seconds)
        )  # fmt: skip
        q = s.fixed[-1] if s.fixed else None
        fixed_units = None if q is None else len({u for u, _, _ in q.steps})
        fixed_rows.append(
            (names[1], r, q is not None, fixed_units, None if q is None else q.success,
             s.expanded, seconds)
        )  # fmt: skip
    return split_rows + fixed_rows


def cmd_split(args: argparse.Namespace) -> int:
    """Splits each goal; exit code 1 when a goal cannot be made or is not found."""
    if args.format is None and (args.out or args.title):
        raise UsageError("-o and --title go with --format")
    if args.format is not None and args.json:
        raise UsageError("--json and --format are exclusive")
    f, kitchen, motions, utensils, ex = inputs(args)
    goals = read_goals(args, ex)
    if args.format is not None and len(goals) != 1:
        raise UsageError(f"--format {args.format} takes exactly one goal")
    profiles = _profiles(args, motions)
    planner = f.planner(kitchen, utensils=utensils)
    failed = 0
    out: list[dict[str, Any]] = []
    for gid in resolve(f, goals):
        if isinstance(gid, NotFound):
            failed += 1
            error(gid.message)
            if args.json:
                out.append({"goal": gid.goal_dict(), "solved": False, "error": gid.message})
            continue
        r = planner.split(
            gid, profiles, args.max_human, robot=args.robot, human=args.human,
            fixed_tree=args.fixed_tree,
        )  # fmt: skip
        failed += not r.solved
        if args.format is not None:
            from foon._cli_explain import write_document

            page = r.write(args.format, title=args.title).encode("utf-8")
            write_document(args.out, page, args.format,
                           [args.foon, args.kitchen, args.motions, args.utensils, args.goals,
                            *[p.partition("=")[2] for p in args.profile + args.override]])  # fmt: skip
        elif args.json:
            d = r.to_dict(f)
            d["goal"] = f.object(gid).to_dict()
            out.append(d)
        else:
            sys.stdout.write(_text(f, r))
    if args.json:
        sys.stdout.write(json.dumps(_json_safe(out), indent=2) + "\n")
    return 1 if failed else 0
