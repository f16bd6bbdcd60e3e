"""The commands of the ``foon`` command line (the parser and the exit codes are in
:mod:`foon.cli`).

Plans are made ``CHUNK`` goals per core call and written as soon as they are made (text,
a JSON list written item by item, or temporary files for ``--out``), so the memory a run
needs does not grow with the number of goals.
"""

from __future__ import annotations

import sys
import warnings

import foon
from foon import _foon
from foon._cli_out import OutDir, OutError, file_names, is_stream
from foon.cli import CliError, UsageError, error, one_line

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse
    from collections.abc import Iterator, Sequence
    from typing import Any, Literal, TypeAlias, TypedDict

    class SharedOptions(TypedDict, total=False):
        """The options of ``optimal-shared`` given on the command line."""

        objective: Literal["units", "success"]
        node_limit: int
        time_limit: float

    Goal: TypeAlias = foon.Object | str
    Raw: TypeAlias = tuple[str, list[str], list[str], str | None]

#: Goals planned per core call: what a run holds at once.
CHUNK = 4096


# --- loading --------------------------------------------------------------------------------


def load_foon(path: str, strict: bool) -> foon.Foon:
    """Loads a FOON and prints its warnings on stderr, one line each (and, on a terminal, a
    progress bar while a large file is parsed)."""
    from foon._progress import wanted

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", foon.FoonWarning)
        f = foon.load(path, strict=strict, progress=wanted())
    for w in caught:
        print(f"foon: warning: {one_line(str(w.message))}", file=sys.stderr)
    return f


def _object(t: Raw) -> foon.Object:
    return foon.Object(t[0], tuple(t[1]), tuple(t[2]), t[3])


def as_goal(g: Raw | Goal) -> Goal:
    """A goal as the API takes it (an object, or a label)."""
    return _object(g) if isinstance(g, tuple) else g


def read_raw_goals(args: argparse.Namespace, ex: foon.Example | None) -> Sequence[Raw | Goal]:
    """The goals of a command, as the core's loader gives them: ``--goals FILE`` and
    ``--goal JSON`` go through it (the same rules and messages as every other object file).
    They become objects a chunk at a time (:func:`as_goal`)."""
    raw: Sequence[Raw | Goal]
    if args.goals is not None:
        raw = _foon.load_objects(args.goals, "goal")
        if not raw:
            raise CliError(f"{args.goals}: the goal list is empty")
        return raw
    if args.goal is not None:
        raw = _foon.parse_objects(args.goal, "goal", path="--goal")
        if not raw:
            raise CliError("--goal: the goal list is empty")
        return raw
    if args.label is not None:
        return [args.label]
    if ex is not None:
        return [ex.goals[0]]
    raise UsageError("give the goal with --goals FILE, --goal JSON or --label TEXT")


def read_goals(args: argparse.Namespace, ex: foon.Example | None) -> list[Goal]:
    """The goals of a command (see :func:`read_raw_goals`)."""
    return [as_goal(g) for g in read_raw_goals(args, ex)]


def inputs(
    args: argparse.Namespace,
) -> tuple[foon.Foon, foon.Kitchen, foon.MotionRates | None, list[str], foon.Example | None]:
    """The FOON, kitchen, rates and utensils of a command (the example's by default)."""
    ex = foon.example() if args.foon is None else None
    f = ex.foon if ex is not None else load_foon(args.foon, args.strict)
    kitchen = (
        foon.Kitchen.load(args.kitchen) if args.kitchen else ex.kitchen if ex else foon.Kitchen()
    )
    motions = (
        foon.MotionRates.load(args.motions)
        if getattr(args, "motions", None)
        else ex.motions
        if ex
        else None
    )
    utensils = foon.load_utensils(args.utensils) if args.utensils else ex.utensils if ex else []
    return f, kitchen, motions, utensils, ex


# --- planning -------------------------------------------------------------------------------


class NotFound:
    """A goal that could not be planned on its own: not an object of the FOON, a label
    several objects have, or a motion without a rate that its search met. It gets its own
    ``FAILED`` line (and JSON entry); the other goals go on."""

    __slots__ = ("goal", "message")

    def __init__(self, goal: Goal, message: str) -> None:
        self.goal = goal
        self.message = message

    def goal_dict(self) -> dict[str, Any]:
        return {"label": self.goal} if isinstance(self.goal, str) else self.goal.to_dict()


def resolve(
    f: foon.Foon, goals: Sequence[Goal], planner: foon.Planner | None = None
) -> list[int | NotFound]:
    """Each goal's object id (at the planner's identity level, if given), or why it has
    none."""
    goal_id = f.goal_id if planner is None else planner.goal_id
    out: list[int | NotFound] = []
    for g in goals:
        try:
            out.append(goal_id(g))
        except foon.GoalNotFoundError as e:
            out.append(NotFound(g, one_line(str(e))))
    return out


def plan_chunks(
    f: foon.Foon,
    planner: foon.Planner,
    goals: Sequence[Raw | Goal],
    method: str,
    compat: Literal["course"] | None,
    count: Literal["nodes", "ingredients"],
    threads: int | None,
    shared: SharedOptions | None = None,
) -> Iterator[list[foon.TaskTree | NotFound]]:
    """The plans of the goals in goal order, ``CHUNK`` goals at a time (a goal that is not
    in the FOON is a :class:`NotFound`)."""
    for start in range(0, len(goals), CHUNK):
        chunk = resolve(f, [as_goal(g) for g in goals[start : start + CHUNK]], planner)
        ids = [r for r in chunk if isinstance(r, int)]
        try:
            planned: list[foon.TaskTree | NotFound] = list(
                planner.plan_many(
                    ids, method, compat=compat, count=count, threads=threads, **(shared or {})
                )
                if ids
                else []
            )
        except foon.MissingRateError:
            # Only some goals meet the motion: plan this chunk goal by goal, so that each of
            # them gets its own result and the output stays whole.
            planned = [_plan_one(f, planner, g, method, compat, count, shared) for g in ids]
        trees = iter(planned)
        yield [next(trees) if isinstance(r, int) else r for r in chunk]


def shared_options(args: argparse.Namespace) -> SharedOptions:
    """``--objective``, ``--node-limit`` and ``--time-limit``, as given (the core refuses
    them with another method)."""
    opts: SharedOptions = {}
    if args.objective is not None:
        opts["objective"] = args.objective
    if args.node_limit is not None:
        opts["node_limit"] = args.node_limit
    if args.time_limit is not None:
        opts["time_limit"] = args.time_limit
    return opts


def _plan_one(
    f: foon.Foon,
    planner: foon.Planner,
    goal: int,
    method: str,
    compat: Literal["course"] | None,
    count: Literal["nodes", "ingredients"],
    shared: SharedOptions | None = None,
) -> foon.TaskTree | NotFound:
    try:
        return planner.plan(goal, method, compat=compat, count=count, **(shared or {}))
    except foon.MissingRateError as e:
        return NotFound(f.object(goal), one_line(str(e)))


def summary(t: foon.TaskTree | NotFound) -> str:
    if isinstance(t, NotFound):
        return f"{t.goal}: FAILED: {t.message}"
    head = f"{t.goal}: "
    if not t.solved:
        return head + f"FAILED ({t.method}): {one_line(t.explanation())}"
    parts = [foon._count(t.fu_count, "unit")]
    parts.append(f"height {t.height}" if t.height is not None else "not executable as listed")
    if t.success is not None:
        parts.append(f"success {100 * t.success:.2f}%")
    compat = ", course" if t.compat == "course" else ""
    return head + ", ".join(parts) + f" ({t.method}{compat}, {1000 * t.seconds:.2f} ms)"


def _solved(t: foon.TaskTree | NotFound) -> bool:
    return not isinstance(t, NotFound) and t.solved


class _Stdout:
    """Writes a writer's output (UTF-8 text, or the bytes of png and pdf, which are refused
    on a terminal) to stdout."""

    def __init__(self, format: str) -> None:
        if foon.FORMATS[format][2] and sys.stdout.isatty():
            raise UsageError(
                f"{format} is binary: redirect the output to a file (> FILE) or give --out"
            )

    def __call__(self, data: bytes) -> None:
        """Writes ``data`` a piece at a time, so that a reader that goes away (``| head``)
        stops the command at the next piece."""
        sys.stdout.flush()
        out = sys.stdout.buffer
        for i in range(0, len(data), 1 << 16):
            out.write(data[i : i + (1 << 16)])
            out.flush()


def _writer_options(args: argparse.Namespace) -> dict[str, Any]:
    return {
        "max_nodes": getattr(args, "max_nodes", None),
        "cost_scale": getattr(args, "cost_scale", None),
    }


def _goal_tuple(g: Goal) -> tuple[tuple[str, list[str], list[str], str | None], bool]:
    """A goal as the core takes it, and whether only its label was given."""
    if isinstance(g, str):
        return (g, [], [], None), True
    return g._tuple(), False


def cmd_plan(args: argparse.Namespace) -> int:
    if getattr(args, "k", None) is not None:
        from foon._cli_paths import plan_k

        return plan_k(args)
    f, kitchen, motions, utensils, ex = inputs(args)
    goals = read_raw_goals(args, ex)
    fmt = args.format
    opts = _writer_options(args)
    out: OutDir | None = None
    if args.out is not None:
        labels = [
            g if isinstance(g, str) else g[0] if isinstance(g, tuple) else g.label for g in goals
        ]
        names = file_names(labels, foon.FORMATS[fmt][0])
        try:
            out = OutDir(
                args.out, names, [args.foon, args.kitchen, args.motions, args.utensils, args.goals]
            )
        except OutError as e:
            raise CliError(str(e)) from None
    planner = f.planner(
        kitchen,
        motions=motions,
        utensils=utensils,
        default_rate=args.default_rate,
        level=args.level,
    )
    stream: _foon.TreeWriter | None = None
    emit: _Stdout | None = None
    many = fmt == "json" or len(goals) > 1
    if out is None:
        # A JSON list even for one goal; the other formats hold one tree as their own
        # document (written only when the goal is solved: no picture of nothing), and
        # several as one (clusters, sections, `# goal:` lines).
        stream = _foon.TreeWriter(fmt, many, **opts)
        emit = _Stdout(fmt)
        if many:
            emit(stream.begin())
    failed = 0
    i = 0
    try:
        for chunk in plan_chunks(
            f,
            planner,
            goals,
            args.method,
            args.compat,
            args.count,
            args.threads,
            shared_options(args),
        ):
            notes = []
            for t in chunk:
                ok = _solved(t)
                failed += not ok
                if out is not None:
                    if ok:
                        assert not isinstance(t, NotFound)
                        w = _foon.TreeWriter(fmt, False, **opts)
                        out.write(i, w.begin() + w.tree(planner._native, t._plan) + w.end())
                elif not many:
                    assert stream is not None and emit is not None
                    if ok:
                        assert not isinstance(t, NotFound)
                        doc = stream.begin() + stream.tree(planner._native, t._plan)
                        emit(doc + stream.end())
                elif isinstance(t, NotFound):
                    assert stream is not None and emit is not None
                    goal, label_only = _goal_tuple(t.goal)
                    emit(stream.failed(goal, label_only, args.method, t.message))
                else:
                    assert stream is not None and emit is not None
                    emit(stream.tree(planner._native, t._plan))
                if not ok or not args.quiet:
                    notes.append(summary(t) + "\n")
                i += 1
            sys.stderr.write("".join(notes))
        if stream is not None and emit is not None and many:
            emit(stream.end())
        if out is not None:
            out.commit()
    except OutError as e:
        raise CliError(str(e)) from None
    finally:
        if out is not None:
            out.abort()
    if out is not None and failed:
        print(
            f"foon: {failed} of {len(goals)} goals not solved: no file written for "
            f"{'it' if failed == 1 else 'them'}",
            file=sys.stderr,
        )
    return 1 if failed else 0


# --- compare --------------------------------------------------------------------------------


def _methods(text: str | None) -> list[str]:
    """The methods of ``--methods``, in the order given, each once (the core's order and
    list by default)."""
    if text is None:
        return list(foon.METHODS)
    methods = list(dict.fromkeys(m.strip() for m in text.split(",")))
    for m in methods:
        if m not in foon.METHODS:
            raise UsageError(f"unknown method '{m}' (choose from {', '.join(foon.METHODS)})")
    return methods


def _split_columns(rows: list[Any]) -> dict[int, tuple[float | None, float | None]]:
    """Each goal's (split success, fixed-tree success) from the ``split M=..`` and
    ``fixed-tree M=..`` rows of ``compare_rows`` (figure rows: method, goal id, solved,
    units, success, expanded, seconds), for the split columns of every row of that goal."""
    split: dict[int, float | None] = {}
    fixed: dict[int, float | None] = {}
    for r in rows:
        if len(r) != 7:
            continue  # a goal that was not found
        name, goal, solved, _units, success = r[:5]
        (split if name.startswith("split") else fixed)[goal] = success if solved else None
    return {g: (split.get(g), fixed.get(g)) for g in split.keys() | fixed.keys()}


def cmd_compare(args: argparse.Namespace) -> int:
    methods = _methods(args.methods)
    f, kitchen, motions, utensils, ex = inputs(args)
    if args.goals is None and args.goal is None and args.label is None:
        if ex is None:
            raise UsageError("give the goals with --goals FILE, --goal JSON or --label TEXT")
        goals: list[Goal] = list(ex.goals)
    else:
        goals = read_goals(args, ex)
    resolved = resolve(f, goals)
    lost = [r for r in resolved if isinstance(r, NotFound)]
    for nf in lost:
        error(summary(nf))
    ids = [r for r in resolved if isinstance(r, int)]
    level: Literal[1, 2, 3] = getattr(args, "level", 3)
    planner = f.planner(
        kitchen, motions=motions, utensils=utensils, default_rate=args.default_rate, level=level
    )
    rows: list[Any] = []
    skipped: list[tuple[str, str]] = []
    for m in methods:
        course = (m == "bfs" or args.compat == "course") and not m.startswith("optimal")
        compat: Literal["course"] | None = "course" if course else None
        name = m + (" (course)" if compat else "")
        try:
            trees = iter(
                planner.plan_many(ids, m, compat=compat, count=args.count, threads=args.threads)
                if ids
                else []
            )
        except foon.MissingRateError as e:
            if motions is not None or args.default_rate is not None:
                raise
            skipped.append((m, one_line(str(e))))
            continue
        for r in resolved:
            if isinstance(r, NotFound):
                rows.append((name, str(r.goal), r.message))
            else:
                rows.append((name, next(trees)._plan))
    split: tuple[int, dict[int, tuple[float | None, float | None]]] | None = None
    if args.split is not None:
        from foon._cli_split import compare_rows

        extra = compare_rows(planner, resolved, args.split, motions, args.default_rate)
        rows += extra
        split = (args.split, _split_columns(extra))
    for m, why in skipped:
        print(
            f"foon: note: {m} skipped: it needs a success rate for every motion "
            f"(give --motions FILE or --default-rate R): {why}",
            file=sys.stderr,
        )
    fmt = args.format or ("json" if args.json else "csv" if args.csv else "text")
    emit = _Stdout(fmt)
    emit(_foon.write_comparison(f._native, rows, fmt, level=planner.level, split=split))
    if not rows:
        error("no method could run")
    return 1 if lost or not rows else 0


# --- verify ---------------------------------------------------------------------------------


def cmd_verify(args: argparse.Namespace) -> int:
    f, kitchen, _, utensils, ex = inputs(args)
    goals = read_goals(args, ex)
    if len(goals) != 1:
        raise UsageError("verify takes exactly one goal")
    goal = goals[0]
    if isinstance(goal, str):
        goal = f.object(f.goal_id(goal))
    tree = load_foon(args.tree, args.strict)
    if args.json:
        import json

        report = _foon.verify_json(
            f._native, tree._native, kitchen._native, list(utensils), goal._tuple()
        )
        sys.stdout.write(report)
        return 0 if json.loads(report)["valid"] else 1
    r = f.verify(tree, goal, kitchen, utensils)
    if r.blocked is not None:
        b = r.blocked
        print(
            f"{args.tree}:{b.line}: unit {b.position + 1} cannot run: needs "
            + "; ".join(str(o) for o in b.missing)
            + " (neither in the kitchen nor made by an earlier unit)"
        )
    if not r.goal_made:
        what = "is not an object of the tree" if r.goal_absent else "is never made"
        print(f"{args.tree}: the goal {goal} {what}")
    for pos, line in r.foreign_units:
        print(f"{args.tree}:{line}: note: unit {pos + 1} is not a unit of the FOON")
    if r.valid:
        print(f"{args.tree}: valid: {foon._count(r.units, 'unit')} make {goal}")
    return 0 if r.valid else 1


# --- check ----------------------------------------------------------------------------------


def _looks_like_foon(path: str) -> bool:
    """A text file whose first meaningful line (after a UTF-8 byte-order mark) is an ``O``,
    ``S`` or ``M`` line (the letter, optional digits, then a TAB) or ``//``."""
    try:
        with open(path, "rb") as fh:
            for i, raw in enumerate(fh):
                text = raw.removeprefix(b"\xef\xbb\xbf") if i == 0 else raw
                line = text.strip()
                if not line or line.startswith(b"#"):
                    continue
                if line.startswith(b"//"):
                    return True
                kind = line.split(b"\t", 1)[0].strip()
                return kind[:1] in (b"O", b"S", b"M") and (kind[1:] == b"" or kind[1:].isdigit())
    except OSError:
        return True  # let the checker report it
    return False


def cmd_check(args: argparse.Namespace) -> int:
    import os
    from pathlib import Path

    files: list[str] = []
    skipped = 0
    problem = False
    for name in args.paths:
        if os.path.isdir(name):
            found = 0
            # Only regular files are read: a FIFO or a device named *.txt is never opened.
            for q in sorted(p for p in Path(name).rglob("*.txt") if p.is_file()):
                if _looks_like_foon(str(q)):
                    files.append(str(q))
                    found += 1
                else:
                    skipped += 1
            if not found:
                error(
                    f"{name}: no FOON file in this folder (FOON files are .txt files "
                    "whose first line is an O, S, M or // line)"
                )
                problem = True
        elif os.path.exists(name) and not os.path.isfile(name):
            error(f"{name}: not a regular file")
            problem = True
        else:
            files.append(name)
    if not files:
        return 1
    kitchen = foon.Kitchen.load(args.kitchen) if args.kitchen else None
    motions = args.motions or None  # read by the linter: its faults are findings
    utensils = foon.load_utensils(args.utensils) if args.utensils else None
    findings = foon.check(files, kitchen=kitchen, motions=motions, utensils=utensils)
    if args.json:
        rows = [(f.path, f.line, f.column, f.severity, f.code, f.message) for f in findings]
        sys.stdout.write(_foon.check_json(rows))
    else:
        for f in findings:
            print(f)
        counts = {s: sum(f.severity == s for f in findings) for s in ("error", "warning", "note")}
        note = f" ({foon._count(skipped, 'non-FOON .txt file')} skipped)" if skipped else ""
        print(
            f"{foon._count(len(files), 'file')} checked{note}: "
            f"{foon._count(counts['error'], 'error')}, {foon._count(counts['warning'], 'warning')}, "
            f"{foon._count(counts['note'], 'note')}",
            file=sys.stderr,
        )
    return 1 if findings or problem else 0


# --- stats ----------------------------------------------------------------------------------


def cmd_stats(args: argparse.Namespace) -> int:
    if args.provenance:
        from foon import _merge

        loaded = [(path, _merge.load_merged(path, strict=args.strict)) for path in args.files]
    else:
        loaded = [(path, load_foon(path, args.strict)) for path in args.files]
    if args.json:
        text = _foon.stats_json([(path, f._native) for path, f in loaded])
        if args.provenance:
            import json

            rows = json.loads(text)
            for row, (_, f) in zip(rows, loaded, strict=True):
                row["provenance"] = [
                    {"unit": i, "support": f.support(i), "sources": f.sources(i)}
                    for i in range(f.fu_count)
                ]
            text = json.dumps(rows, indent=2) + "\n"
        sys.stdout.write(text)
        return 0
    for path, f in loaded:
        print(path)
        for k, v in f.stats().items():
            print(f"  {k.replace('_', ' '):<20} {v:>10,}")
        if args.provenance:
            from foon import _merge

            sys.stdout.write(_merge.provenance_lines(f))
    return 0


# --- export and draw ------------------------------------------------------------------------


def _focus(f: foon.Foon, args: argparse.Namespace) -> int | None:
    """The object in focus (``--goal JSON`` or ``--label TEXT``), as an object id."""
    if args.goal is not None:
        raw = _foon.parse_objects(args.goal, "goal", path="--goal")
        if len(raw) != 1:
            raise UsageError("--goal: give exactly one object")
        return f.goal_id(as_goal(raw[0]))
    if args.label is not None:
        return f.goal_id(args.label)
    return None


def cmd_export(args: argparse.Namespace) -> int:
    f = load_foon(args.file, args.strict)
    focus = _focus(f, args)
    depth = args.depth
    if args.cmd == "draw" and focus is not None and depth is None:
        depth = 1
    if depth is not None and focus is None:
        raise UsageError("--depth needs --goal or --label")
    kitchen = foon.Kitchen.load(args.kitchen) if args.kitchen else None
    utensils = foon.load_utensils(args.utensils) if args.utensils else None
    motions = foon.MotionRates.load(args.motions) if args.motions else None
    planner = None
    if kitchen is not None or utensils is not None or motions is not None:
        planner = f.planner(kitchen, utensils=utensils, motions=motions)._native
    # Written in full before anything reaches the destination: an error leaves no file.
    data = _foon.write_foon(
        f._native,
        args.format,
        focus=focus,
        depth=depth,
        planner=planner,
        **_writer_options(args),
    )
    if args.out is None:
        _Stdout(args.format)(data)
        return 0
    import os

    folder, name = os.path.split(args.out)
    if not name:
        raise UsageError(f"--out: {args.out!r} names a folder, not a file")
    if is_stream(args.out):
        # -o /dev/stdout, /dev/null, a FIFO: written into (the document is complete
        # already), never replaced by a file.
        try:
            with open(args.out, "wb") as fh:
                fh.write(data)
        except OSError as e:
            raise CliError(f"{args.out}: cannot write: {e.strerror or e}") from None
        return 0
    try:
        out = OutDir(folder or ".", [name], [args.file, args.kitchen, args.utensils, args.motions])
        try:
            out.write(0, data)
            out.commit()
        finally:
            out.abort()
    except OutError as e:
        raise CliError(str(e)) from None
    return 0


cmd_draw = cmd_export
