"""The ``foon`` command line: ``foon plan``, ``foon stats``.

Exit codes: 0 ok, 1 a domain error or a goal that could not be planned (one clear line on
stderr, no traceback), 2 a usage error, 130 interrupted.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Literal

import foon
from foon import _foon


class UsageError(Exception):
    """A command-line mistake (exit code 2)."""


# --- loading --------------------------------------------------------------------------------


def _load_foon(path: str | None, strict: bool) -> foon.Foon:
    """Loads a FOON and prints its warnings on stderr."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", foon.FoonWarning)
        f = foon.example().foon if path is None else foon.load(path, strict=strict)
    for w in caught:
        print(f"foon: warning: {w.message}", file=sys.stderr)
    return f


def _read_goals(args: argparse.Namespace, ex: foon.Example | None) -> list[foon.Object | str]:
    if args.goals:
        return [foon.Object(t[0], tuple(t[1]), tuple(t[2]), t[3])
                for t in _foon.load_objects(args.goals, "goal")]
    if args.goal:
        try:
            data = json.loads(args.goal)
        except json.JSONDecodeError as e:
            raise UsageError(f"--goal is not valid JSON: {e}") from None
        items = data if isinstance(data, list) else [data]
        if not all(isinstance(d, dict) for d in items):
            raise UsageError('--goal takes a JSON object {"label", "states", ...} or a list of them')
        try:
            return [foon.Object.from_dict(d) for d in items]
        except ValueError as e:
            raise UsageError(f"--goal: {e}") from None
    if args.label:
        return [args.label]
    if ex is not None:
        return [ex.goals[0]]
    raise UsageError("give the goal with --goals FILE, --goal JSON or --label TEXT")


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


#: Characters that may not stand in a file name made from a label (path separators, and
#: what common file systems reject); each becomes ``_``, as spaces do.
_UNSAFE_IN_NAME = str.maketrans({c: "_" for c in ' /\\:*?"<>|'})


def file_stem(label: str) -> str:
    """The file name (without extension) for a goal: its label with spaces as ``_`` (the
    course's naming), and path separators and other unsafe characters as ``_`` too, so that a
    label can never name a file outside the output folder."""
    stem = "".join("_" if ord(c) < 32 else c for c in label.translate(_UNSAFE_IN_NAME))
    return "_" + stem if stem in ("", ".", "..") else stem


def refuse_input(path: Path, inputs: Sequence[str | None]) -> None:
    """Raises FoonError when ``path`` is one of the input files."""
    for i in inputs:
        if i is not None and _same_file(path, Path(i)):
            raise foon.FoonError(f"{path}: refusing to overwrite an input file")


def write_atomic(path: Path, text: str, inputs: Sequence[str | None] = ()) -> None:
    """Writes ``text`` to ``path`` through a temporary file in the same folder and a rename,
    so a failed or interrupted run never leaves a partial file; refuses to replace an input."""
    refuse_input(path, inputs)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _summary(t: foon.TaskTree) -> str:
    head = f"{t.goal}: "
    if not t.solved:
        return head + f"FAILED ({t.method}): {t.explanation()}"
    parts = [f"{t.fu_count} unit{'s' if t.fu_count != 1 else ''}"]
    parts.append(f"height {t.height}" if t.height is not None else "not executable as listed")
    if t.success is not None:
        parts.append(f"success {100 * t.success:.2f}%")
    compat = ", course" if t.compat == "course" else ""
    return head + ", ".join(parts) + f" ({t.method}{compat}, {1000 * t.seconds:.2f} ms)"


# --- commands -------------------------------------------------------------------------------


def cmd_plan(args: argparse.Namespace) -> int:
    f, kitchen, motions, utensils, ex = _inputs(args)
    goals = _read_goals(args, ex)
    trees = f.plan_many(goals, kitchen, args.method, compat=args.compat, count=args.count,
                        motions=motions, utensils=utensils, default_rate=args.default_rate,
                        threads=args.threads)
    inputs = [args.foon, args.kitchen, args.motions, args.utensils, args.goals]
    if args.out is not None:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        ext = ".json" if args.format == "json" else ".txt"
        used: dict[str, int] = {}
        files: list[tuple[Path, foon.TaskTree]] = []
        for t in trees:
            stem = file_stem(t.goal.label)
            used[stem] = used.get(stem, 0) + 1
            if used[stem] > 1:
                # Two goals with one label: keep both files rather than replace the first.
                print(f"foon: note: a second goal labelled '{t.goal.label}' is written to "
                      f"{stem}_{used[stem]}{ext}", file=sys.stderr)
                stem = f"{stem}_{used[stem]}"
            files.append((out / (stem + ext), t))
        # Every destination is checked before the first is written: nothing is written when
        # one of them would replace an input.
        for path, _ in files:
            refuse_input(path, inputs)
        for path, t in files:
            text = t.to_json() + "\n" if args.format == "json" else t.to_text()
            write_atomic(path, text, inputs)
    elif args.format == "json":
        sys.stdout.write(json.dumps([t.to_dict() for t in trees], indent=2) + "\n")
    else:
        for t in trees:
            if len(trees) > 1:
                sys.stdout.write(f"# goal: {t.goal}\n")
            if t.units or t.solved:
                sys.stdout.write(t.to_text())
    if not args.quiet:
        for t in trees:
            print(_summary(t), file=sys.stderr)
    return 0 if all(t.solved for t in trees) else 1


def _inputs(args: argparse.Namespace) -> tuple[foon.Foon, foon.Kitchen, foon.MotionRates | None,
                                                list[str], foon.Example | None]:
    """The FOON, kitchen, rates and utensils of a command (the example's by default)."""
    ex = foon.example() if args.foon is None else None
    f = ex.foon if ex is not None else _load_foon(args.foon, args.strict)
    kitchen = (foon.Kitchen.load(args.kitchen) if args.kitchen
               else ex.kitchen if ex else foon.Kitchen())
    motions = (foon.MotionRates.load(args.motions) if getattr(args, "motions", None)
               else ex.motions if ex else None)
    utensils = (foon.load_utensils(args.utensils) if args.utensils
                else ex.utensils if ex else [])
    return f, kitchen, motions, utensils, ex


COMPARE_METHODS = ("ids", "greedy-success", "greedy-inputs", "optimal-success", "optimal-units",
                   "optimal-inputs", "bfs")


def cmd_compare(args: argparse.Namespace) -> int:
    f, kitchen, motions, utensils, ex = _inputs(args)
    goals = _read_goals(args, ex) if (args.goals or args.goal or args.label or ex is None) \
        else list(ex.goals)
    if args.goals is None and args.goal is None and args.label is None and ex is None:
        raise UsageError("give the goals with --goals FILE")
    methods = args.methods.split(",") if args.methods else list(COMPARE_METHODS)
    for m in methods:
        if m not in foon.METHODS:
            raise UsageError(f"unknown method '{m}' (choose from {', '.join(foon.METHODS)})")
    rows: list[dict[str, Any]] = []
    for m in methods:
        course = (m == "bfs" or args.compat == "course") and not m.startswith("optimal")
        compat: Literal["course"] | None = "course" if course else None
        for t in f.plan_many(goals, kitchen, m, compat=compat, count=args.count,
                             motions=motions, utensils=utensils,
                             default_rate=args.default_rate, threads=args.threads):
            rows.append({
                "goal": str(t.goal), "method": m + (" (course)" if compat else ""),
                "solved": t.solved, "fu_count": t.fu_count if t.solved else None,
                "height": t.height, "success": t.success if t.solved else None,
                "leaf_inputs": t.leaf_inputs if t.solved else None, "expanded": t.expanded,
                "peak_frontier": t.peak_frontier, "seconds": t.seconds,
            })
    summary = _compare_summary(rows)
    if args.json:
        sys.stdout.write(json.dumps({"rows": rows, "summary": summary}, indent=2) + "\n")
    elif args.csv:
        import csv

        w = csv.DictWriter(sys.stdout, fieldnames=list(rows[0]) if rows else ["goal"],
                           extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
        for srow in summary:
            w.writerow({"goal": "(all)", **srow})
    else:
        _print_compare_table(rows, summary)
    return 0


def _compare_summary(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    out = []
    for m in dict.fromkeys(r["method"] for r in rows):
        rs = [r for r in rows if r["method"] == m]
        ok = [r for r in rs if r["solved"]]

        def mean(key: str, rows_: list[dict[str, Any]] = ok) -> float | None:
            vals = [r[key] for r in rows_ if r[key] is not None]
            return sum(vals) / len(vals) if vals else None

        out.append({
            "method": m, "solved": len(ok), "goals": len(rs), "fu_count": mean("fu_count"),
            "height": mean("height"), "success": mean("success"),
            "leaf_inputs": mean("leaf_inputs"), "expanded": mean("expanded", rs),
            "peak_frontier": mean("peak_frontier", rs),
            "seconds": sum(r["seconds"] for r in rs),
        })
    return out


def _cell(v: Any, kind: str = "") -> str:
    if v is None:
        return "-"
    if kind == "pct":
        return f"{100 * v:.2f}%"
    if kind == "ms":
        return f"{1000 * v:.3f}"
    if isinstance(v, float):
        return f"{v:.1f}"
    return str(v)


def _print_compare_table(rows: list[dict[str, Any]], summary: list[dict[str, Any]]) -> None:
    head = ["goal", "method", "units", "height", "success", "leaves", "expanded", "peak", "ms"]
    body = [[r["goal"][:48], r["method"], _cell(r["fu_count"]), _cell(r["height"]),
             _cell(r["success"], "pct"), _cell(r["leaf_inputs"]), _cell(r["expanded"]),
             _cell(r["peak_frontier"]), _cell(r["seconds"], "ms")] for r in rows]
    for srow in summary:
        body.append([f"(all: {srow['solved']}/{srow['goals']} solved)", srow["method"],
                     _cell(srow["fu_count"]), _cell(srow["height"]),
                     _cell(srow["success"], "pct"), _cell(srow["leaf_inputs"]),
                     _cell(srow["expanded"]), _cell(srow["peak_frontier"]),
                     _cell(srow["seconds"], "ms")])
    widths = [max(len(x[i]) for x in [head, *body]) for i in range(len(head))]
    line = "  ".join(h.ljust(w) if i < 2 else h.rjust(w) for i, (h, w) in enumerate(zip(head, widths)))
    print(line)
    print("-" * len(line))
    for i, row in enumerate(body):
        if i == len(rows):
            print("-" * len(line))
        print("  ".join(c.ljust(w) if j < 2 else c.rjust(w)
                        for j, (c, w) in enumerate(zip(row, widths))))


def cmd_verify(args: argparse.Namespace) -> int:
    f, kitchen, _, utensils, ex = _inputs(args)
    goals = _read_goals(args, ex)
    if len(goals) != 1 or isinstance(goals[0], str):
        if goals and isinstance(goals[0], str):
            goals = [f.object(f.goal_id(goals[0]))]
        else:
            raise UsageError("verify takes exactly one goal")
    goal = goals[0]
    assert isinstance(goal, foon.Object)
    r = f.verify(args.tree, goal, kitchen, utensils)
    if args.json:
        out = {"valid": r.valid, "units": r.units, "goal_made": r.goal_made,
               "blocked": None if r.blocked is None else {
                   "position": r.blocked.position, "line": r.blocked.line,
                   "missing": [o.to_dict() for o in r.blocked.missing]},
               "foreign_units": [{"position": p, "line": ln} for p, ln in r.foreign_units]}
        sys.stdout.write(json.dumps(out, indent=2) + "\n")
    else:
        if r.blocked is not None:
            b = r.blocked
            print(f"{args.tree}:{b.line}: unit {b.position + 1} cannot run: needs "
                  + "; ".join(str(o) for o in b.missing)
                  + " (neither in the kitchen nor made by an earlier unit)")
        if not r.goal_made:
            what = "is not an object of the tree" if r.goal_absent else "is never made"
            print(f"{args.tree}: the goal {goal} {what}")
        for pos, line in r.foreign_units:
            print(f"{args.tree}:{line}: note: unit {pos + 1} is not a unit of the FOON")
        if r.valid:
            print(f"{args.tree}: valid: {r.units} units make {goal}")
    return 0 if r.valid else 1


def _looks_like_foon(path: Path) -> bool:
    """A text file whose first meaningful line is an O, S or M line or `//`."""
    try:
        with path.open("rb") as fh:
            for raw in fh:
                line = raw.strip()
                if not line or line.startswith(b"#"):
                    continue
                return line[:1] in (b"O", b"S", b"M") or line.startswith(b"//")
    except OSError:
        return True  # let the checker report it
    return False


def cmd_check(args: argparse.Namespace) -> int:
    files: list[Path] = []
    skipped = 0
    for name in args.paths:
        p = Path(name)
        if p.is_dir():
            for q in sorted(p.rglob("*.txt")):
                if _looks_like_foon(q):
                    files.append(q)
                else:
                    skipped += 1
        else:
            files.append(p)
    kitchen = foon.Kitchen.load(args.kitchen) if args.kitchen else None
    motions = foon.MotionRates.load(args.motions) if args.motions else None
    utensils = foon.load_utensils(args.utensils) if args.utensils else None
    findings = foon.check(files, kitchen=kitchen, motions=motions, utensils=utensils)
    if args.json:
        sys.stdout.write(json.dumps([f.__dict__ for f in findings], indent=2) + "\n")
    else:
        for f in findings:
            print(f)
        counts = {s: sum(f.severity == s for f in findings) for s in ("error", "warning", "note")}
        note = f" ({skipped} non-FOON .txt files skipped)" if skipped else ""
        print(f"{len(files)} files checked{note}: {counts['error']} errors, "
              f"{counts['warning']} warnings, {counts['note']} notes", file=sys.stderr)
    return 1 if findings else 0


def cmd_stats(args: argparse.Namespace) -> int:
    rows = []
    for path in args.files:
        f = _load_foon(path, args.strict)
        s = f.stats()
        rows.append({"file": path, **s})
    if args.json:
        sys.stdout.write(json.dumps(rows if len(rows) > 1 else rows[0], indent=2) + "\n")
        return 0
    for r in rows:
        print(r["file"])
        for k, v in r.items():
            if k != "file":
                print(f"  {k.replace('_', ' '):<20} {v:>10,}")
    return 0


# --- parser ---------------------------------------------------------------------------------


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="foon",
        description="Parse FOON files and retrieve task trees (foon %s)." % foon.__version__,
    )
    p.add_argument("--version", action="version", version=f"foon {foon.__version__}")
    sub = p.add_subparsers(dest="cmd", required=True, metavar="COMMAND")

    def common(sp: argparse.ArgumentParser, motions: bool = True) -> None:
        sp.add_argument("--foon", metavar="FILE", help="FOON file (default: the example)")
        sp.add_argument("--kitchen", metavar="FILE", help="kitchen: JSON list or object blocks")
        if motions:
            sp.add_argument("--motions", metavar="FILE", help="motion success rates")
        sp.add_argument("--utensils", metavar="FILE", help="utensil list (container rule)")
        g = sp.add_mutually_exclusive_group()
        g.add_argument("--goals", metavar="FILE", help="goal file")
        g.add_argument("--goal", metavar="JSON", help="one goal as JSON")
        g.add_argument("--label", metavar="TEXT", help="a goal label that one object has")
        sp.add_argument("--strict", action="store_true", help="turn load warnings into errors")

    pl = sub.add_parser(
        "plan",
        help="retrieve task trees for goals",
        description="Retrieve task trees. With no --foon, plans the embedded example "
        "(its kitchen, motion rates, utensils and default goal).",
    )
    common(pl)
    pl.add_argument("--method", default="ids", choices=foon.METHODS, help="default: ids")
    pl.add_argument("--compat", choices=["course"], default=None,
                    help="reproduce the course code's trees byte for byte")
    pl.add_argument("--count", choices=["nodes", "ingredients"], default="nodes",
                    help="greedy-inputs: count input nodes (default) or ingredient labels")
    pl.add_argument("--default-rate", type=float, metavar="R",
                    help="success rate for motions missing from the table")
    pl.add_argument("--format", choices=["text", "json"], default="text")
    pl.add_argument("--out", metavar="DIR", help="write one file per goal into DIR")
    pl.add_argument("--threads", type=int, metavar="N", help="threads for many goals (default: all cores)")
    pl.add_argument("-q", "--quiet", action="store_true", help="no summary lines on stderr")
    pl.set_defaults(func=cmd_plan)

    cp = sub.add_parser(
        "compare",
        help="compare planning methods on a set of goals",
        description="One row per goal and method: units, height, overall success, distinct "
        "leaf inputs, objects expanded, peak frontier, time; then a summary row per method.",
    )
    common(cp)
    cp.add_argument("--methods", metavar="LIST",
                    help="comma-separated methods (default: " + ",".join(COMPARE_METHODS) + ")")
    cp.add_argument("--compat", choices=["course"], default=None,
                    help="course-compatible ids/greedy methods")
    cp.add_argument("--count", choices=["nodes", "ingredients"], default="nodes")
    cp.add_argument("--default-rate", type=float, metavar="R")
    cp.add_argument("--threads", type=int, metavar="N")
    fmt = cp.add_mutually_exclusive_group()
    fmt.add_argument("--json", action="store_true", help="machine-readable output")
    fmt.add_argument("--csv", action="store_true", help="CSV output")
    cp.set_defaults(func=cmd_compare)

    vp = sub.add_parser(
        "verify",
        help="check a task-tree file",
        description="Checks a task-tree file (course text form) in the order written: every "
        "unit's inputs must be in the kitchen or made by an earlier unit, and the goal made.",
    )
    common(vp, motions=False)
    vp.add_argument("tree", metavar="TREE_FILE")
    vp.add_argument("--json", action="store_true", help="machine-readable output")
    vp.set_defaults(func=cmd_verify)

    ck = sub.add_parser(
        "check",
        help="lint FOON files",
        description="Lists every error, warning and note of FOON files with file:line:column. "
        "Folders are searched for FOON .txt files. Exit code 0 clean, 1 findings, 2 usage.",
    )
    ck.add_argument("paths", nargs="+", metavar="FILE_OR_DIR")
    ck.add_argument("--kitchen", metavar="FILE", help="also report objects nobody produces "
                    "that this kitchen lacks")
    ck.add_argument("--motions", metavar="FILE", help="also report motions without a rate")
    ck.add_argument("--utensils", metavar="FILE", help="utensil list (container rule)")
    ck.add_argument("--json", action="store_true", help="machine-readable output")
    ck.set_defaults(func=cmd_check)

    st = sub.add_parser("stats", help="counts of a FOON file")
    st.add_argument("files", nargs="+", metavar="FILE")
    st.add_argument("--json", action="store_true", help="machine-readable output")
    st.add_argument("--strict", action="store_true", help="turn load warnings into errors")
    st.set_defaults(func=cmd_stats)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    func: Callable[[argparse.Namespace], int] = args.func
    try:
        return func(args)
    except UsageError as e:
        parser.print_usage(sys.stderr)
        print(f"foon: error: {e}", file=sys.stderr)
        return 2
    except foon.FoonError as e:
        print(f"foon: error: {e}", file=sys.stderr)
        return 1
    except OSError as e:
        print(f"foon: error: {e}", file=sys.stderr)
        return 1
    except ValueError as e:
        print(f"foon: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("foon: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 1


