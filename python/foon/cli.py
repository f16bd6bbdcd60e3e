"""The ``foon`` command line: ``foon plan``, ``compare``, ``verify``, ``check``, ``stats``,
``export``, ``draw``, ``index``,
``merge``, ``synth``, ``batch``.

Exit codes: 0 ok, 1 a domain error or a goal that could not be planned (one clear line on
stderr, no traceback), 2 a usage error, 130 interrupted (143 stopped by SIGTERM, which
``foon batch`` meets as Ctrl-C). A closed output pipe (``foon ... | head``) ends the command
quietly with exit code 1, as Python programs do.

This module only builds the argument parser and maps errors to exit codes; each command is
in :mod:`foon._cli_commands`, imported when a command runs. ``foon --version`` imports
nothing else, not even argparse.
"""

from __future__ import annotations

import os
import sys

import foon

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse
    from collections.abc import Callable, Sequence
    from typing import Any

    from _typeshed import SupportsWrite


class UsageError(Exception):
    """A command-line mistake found after parsing (exit code 2, with the command's usage)."""


class CliError(Exception):
    """A failure of the command (exit code 1); the message names what failed."""


def one_line(message: str) -> str:
    """The message on one line: continuation lines are joined with ``; ``."""
    lines = [s.strip() for s in str(message).splitlines() if s.strip()]
    if len(lines) <= 1:
        return lines[0] if lines else ""
    return lines[0] + " " + "; ".join(lines[1:])


def error(message: object) -> None:
    """Prints ``foon: error: MESSAGE`` on one line on stderr."""
    print(f"foon: error: {one_line(str(message))}", file=sys.stderr)


# --- argument types -------------------------------------------------------------------------

#: The largest --threads value that fits the core's integer type; the core caps it further.
_MAX_THREADS = 2**63 - 1


def _threads(text: str) -> int:
    import argparse

    try:
        # Plain ASCII digits only: int() would also take "1_000" and other scripts' digits.
        if not (text.strip().lstrip("+-").isascii() and text.strip().lstrip("+-").isdigit()):
            raise ValueError(text)
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, not {n}")
    if n > _MAX_THREADS:
        raise argparse.ArgumentTypeError(f"too large: {text}")
    return n


def _folder(text: str) -> str:
    import argparse

    if not text:
        raise argparse.ArgumentTypeError("the folder name is empty")
    return text


# --- parser ---------------------------------------------------------------------------------


#: The commands, in the order ``foon --help`` lists them.
COMMANDS = (
    "plan",
    "compare",
    "verify",
    "check",
    "stats",
    "export",
    "draw",
    "index",
    "merge",
    "synth",
    "paths",
    "explain",
    "find",
    "split",
    "batch",
)

#: Commands implemented in their own module (``foon._cli_NAME``: ``cmd_NAME`` and
#: ``add_NAME_options``), imported only when the command runs.
_OWN_MODULE = ("index", "merge", "synth", "paths", "explain", "find", "split", "batch")


def _columns() -> int:
    """The terminal width as ``shutil.get_terminal_size`` gives it (``COLUMNS``, else the
    terminal of stdout, else 80), without importing shutil (and the compression modules it
    brings) on every start."""
    try:
        return int(os.environ["COLUMNS"])
    except (KeyError, ValueError):
        pass
    try:
        return os.get_terminal_size(sys.__stdout__.fileno()).columns  # type: ignore[union-attr]
    except (AttributeError, ValueError, OSError):
        return 80


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The argument parser. With ``only`` (a command name, or ``""`` for none), only that
    command's options are set up and the others are listed by name and help: that is all
    that parsing one command line needs, and every start is shorter for it."""
    import argparse

    class Formatter(argparse.HelpFormatter):
        def __init__(
            self,
            prog: str,
            indent_increment: int = 2,
            max_help_position: int = 24,
            width: int | None = None,
        ) -> None:
            width = _columns() - 2 if width is None else width
            super().__init__(prog, indent_increment, max_help_position, width)

    class Parser(argparse.ArgumentParser):
        """argparse's parser, except that a help or usage text that cannot be written (a
        closed pipe, a full disk) is an error rather than silently lost."""

        def __init__(self, *args: Any, **kwargs: Any) -> None:
            kwargs.setdefault("formatter_class", Formatter)
            super().__init__(*args, **kwargs)

        def _print_message(self, message: str, file: SupportsWrite[str] | None = None) -> None:
            if message:
                (file or sys.stderr).write(message)

    p = Parser(
        prog="foon",
        description=f"Parse FOON files and retrieve task trees (foon {foon.__version__}).",
    )
    p.add_argument("--version", action="version", version=f"foon {foon.__version__}")
    sub = p.add_subparsers(dest="cmd", required=True, metavar="COMMAND")
    about = {
        "plan": (
            "retrieve task trees for goals",
            (
                "Retrieve task trees. With no --foon, plans the embedded example (its kitchen, "
                "motion rates, utensils and default goal)."
            ),
        ),
        "compare": (
            "compare planning methods on a set of goals",
            (
                "One row per goal and method: units, height, overall success, distinct leaf "
                "inputs, objects expanded, peak frontier, time; then a summary row per method."
            ),
        ),
        "verify": (
            "check a task-tree file",
            (
                "Checks a task-tree file (course text form) in the order written: every unit's "
                "inputs must be in the kitchen or made by an earlier unit, and the goal made."
            ),
        ),
        "check": (
            "lint FOON files",
            (
                "Lists every error, warning and note of FOON files with file:line:column. Folders "
                "are searched for FOON .txt files (regular files only). Exit code 0 clean, 1 "
                "findings (or no FOON file found), 2 usage."
            ),
        ),
        "stats": (
            "counts of FOON files",
            "Counts of each FOON file (--json: a list, one object per file).",
        ),
        "export": (
            "write a FOON in another format",
            (
                "Writes a FOON (all of it, or with --goal and --depth the units around one "
                "object) as JSON, GraphML, DOT, a picture, course text, or (with --goal and "
                "--kitchen) a PDDL domain and problem."
            ),
        ),
        "index": (
            "build a .foonidx index file",
            (
                "Builds one .foonidx index from FOON files (any dialect, in order; a folder "
                "gives its FOON files, sorted), keeping every unit's source and line; written "
                "atomically, never over an input. Every command and foon.load open it with a "
                "memory map."
            ),
        ),
        "merge": (
            "merge FOON files and folders into one, with provenance and support",
            (
                "Merges FOON files (any dialect; a folder stands for its .txt and .json files, "
                "sorted) into one FOON: a unit that repeats an earlier one at --level is "
                "dropped, the first copy is kept with every file and line it was found at. "
                "Writes course-form text with '#' provenance lines (every FOON reader skips "
                "them)."
            ),
        ),
        "synth": (
            "generate a synthetic merged FOON",
            (
                "Writes a realistic merged FOON of exactly --units units (course dialect), "
                "deterministic for --seed, with its kitchen, goals and motion table on request."
            ),
        ),
        "paths": (
            "stream every valid tree of a goal up to limits",
            (
                "Every valid tree of a goal (fewest units first), each once, lazily; "
                "--max-trees N, --max-height H; never prompts."
            ),
        ),
        "explain": (
            "explain why a goal can or cannot be made from a kitchen",
            (
                "Whether the goal is in the kitchen, derivable (its rank and best tree) or "
                "blocked: the shopping list, what blocks each producer, the blocking cycle as a "
                "chain and what would unblock it. --json for programs."
            ),
        ),
        "find": (
            "objects most similar to a free-text query",
            (
                "Ranks the FOON's objects by similarity of label, states and container to a "
                'free-text query such as "chopped onion in bowl". --json for programs.'
            ),
        ),
        "split": (
            "split each goal's tree between a robot and a human",
            (
                "For each budget m = 0..--max-human, the tree and the assignment of at most m "
                "of its steps to the human that maximise the tree's success over all valid "
                "trees (--profile robot=FILE, --profile human=FILE; the human's rates are 1 by "
                "default). Prints the front of success against human steps."
            ),
        ),
        "batch": (
            "plan a file of (kitchen, goal, method) queries into Parquet",
            (
                "Plans every query of a Parquet, CSV or JSON-lines table (query_id, "
                "kitchen_id, goal, method, options) over a .foonidx with a set of named "
                "kitchens, locally or on a Dask cluster, into Parquet partitions written "
                "atomically; a rerun with the same inputs resumes. Prints a summary."
            ),
        ),
        "draw": (
            "draw a FOON or the neighbourhood of one object",
            (
                "Draws a FOON in the FOON visual language (motions red squares, objects green "
                "circles, the goal purple): all of it, or with --goal the units within --depth "
                "steps of the goal. Pictures other than dot run Graphviz's dot."
            ),
        ),
    }
    for name in COMMANDS:
        brief, description = about[name]
        sp = sub.add_parser(name, help=brief, description=description)
        sp.set_defaults(parser=sp)
        if only is None or only == name:
            _options(name)(sp)
    return p


def _common(sp: argparse.ArgumentParser, motions: bool = True) -> None:
    sp.add_argument("--foon", metavar="FILE", help="FOON file (default: the example)")
    sp.add_argument("--kitchen", metavar="FILE", help="kitchen: JSON list or object blocks")
    if motions:
        sp.add_argument("--motions", metavar="FILE", help="motion success rates")
    sp.add_argument("--utensils", metavar="FILE", help="utensil list (container rule)")
    g = sp.add_mutually_exclusive_group()
    g.add_argument("--goals", metavar="FILE", help="goal file")
    g.add_argument("--goal", metavar="JSON", help="one goal (or a list of goals) as JSON")
    g.add_argument("--label", metavar="TEXT", help="a goal label that one object has")
    sp.add_argument("--strict", action="store_true", help="turn load warnings into errors")


def _plan_options(pl: argparse.ArgumentParser) -> None:
    _common(pl)
    pl.add_argument("--method", default="ids", choices=foon.METHODS, help="default: ids")
    pl.add_argument(
        "--compat",
        choices=["course"],
        default=None,
        help="reproduce the course code's trees byte for byte",
    )
    pl.add_argument(
        "--count",
        choices=["nodes", "ingredients"],
        default="nodes",
        help="greedy-inputs: count input nodes (default) or ingredient labels",
    )
    pl.add_argument(
        "--default-rate",
        type=float,
        metavar="R",
        help="success rate for motions missing from the table",
    )
    pl.add_argument(
        "--format",
        choices=_formats(1),
        default="text",
        help="output format (default: text, the course form)",
    )
    pl.add_argument(
        "--out",
        type=_folder,
        metavar="DIR",
        help="write one file per solved goal into DIR (all files or none)",
    )
    _picture_options(pl)
    pl.add_argument(
        "--threads", type=_threads, metavar="N", help="threads for many goals (default: all cores)"
    )
    pl.add_argument(
        "--level",
        type=int,
        choices=[1, 2, 3],
        default=3,
        help="identity level for matching the kitchen and goals: 3 full (default), "
        "2 ingredients ignored, 1 labels only",
    )
    pl.add_argument(
        "--objective",
        choices=["units", "success"],
        help="optimal-shared: fewest distinct units, or best success over them (default: units)",
    )
    pl.add_argument(
        "--node-limit",
        type=int,
        metavar="N",
        help="optimal-shared: stop after N search nodes (deterministic)",
    )
    pl.add_argument(
        "--time-limit",
        type=float,
        metavar="S",
        help="optimal-shared: stop after S seconds (the best tree so far, its bound and gap)",
    )
    pl.add_argument("--k", type=int, metavar="K", help="optimal-*: the K best trees, in cost order")
    pl.add_argument("--diverse", action="store_true", help="--k: penalise units of earlier trees")
    pl.add_argument(
        "-q", "--quiet", action="store_true", help="no summary lines for solved goals on stderr"
    )


def _compare_options(cp: argparse.ArgumentParser) -> None:
    _common(cp)
    cp.add_argument(
        "--methods",
        metavar="LIST",
        help="comma-separated methods (default: " + ",".join(foon.METHODS) + ")",
    )
    cp.add_argument(
        "--compat", choices=["course"], default=None, help="course-compatible ids/greedy methods"
    )
    cp.add_argument("--count", choices=["nodes", "ingredients"], default="nodes")
    cp.add_argument("--default-rate", type=float, metavar="R")
    cp.add_argument("--threads", type=_threads, metavar="N")
    cp.add_argument(
        "--level",
        type=int,
        choices=[1, 2, 3],
        default=3,
        help="identity level for matching the kitchen and goals (as for plan)",
    )
    cp.add_argument(
        "--split",
        type=_count_arg,
        metavar="M",
        help="also the robot/human split and the lab's fixed tree with M human steps",
    )
    fmt = cp.add_mutually_exclusive_group()
    fmt.add_argument("--format", choices=_formats(3), default=None, help="default: text")
    fmt.add_argument("--json", action="store_true", help="the same as --format json")
    fmt.add_argument("--csv", action="store_true", help="the same as --format csv")


def _verify_options(vp: argparse.ArgumentParser) -> None:
    _common(vp, motions=False)
    vp.add_argument("tree", metavar="TREE_FILE")
    vp.add_argument("--json", action="store_true", help="machine-readable output")


def _check_options(ck: argparse.ArgumentParser) -> None:
    ck.add_argument("paths", nargs="+", metavar="FILE_OR_DIR")
    ck.add_argument(
        "--kitchen",
        metavar="FILE",
        help="also report objects nobody produces that this kitchen lacks",
    )
    ck.add_argument("--motions", metavar="FILE", help="also report motions without a rate")
    ck.add_argument("--utensils", metavar="FILE", help="utensil list (container rule)")
    ck.add_argument("--json", action="store_true", help="machine-readable output")


def _stats_options(st: argparse.ArgumentParser) -> None:
    st.add_argument("files", nargs="+", metavar="FILE")
    st.add_argument("--json", action="store_true", help="machine-readable output")
    st.add_argument(
        "--provenance",
        action="store_true",
        help=(
            "also list, for every unit, its support and each file and line it was found at "
            "(the '#' lines of a merged FOON)"
        ),
    )
    st.add_argument("--strict", action="store_true", help="turn load warnings into errors")


def _formats(kind: int) -> list[str]:
    """The formats that write a task tree (1), a FOON (2) or a comparison (3)."""
    return [name for name, f in foon.FORMATS.items() if f[3 + kind]]


#: The largest --depth and --cost-scale the core takes (32-bit); --max-nodes takes 64 bits.
_MAX_U32 = 2**32 - 1
_MAX_U64 = 2**64 - 1


def _count_arg(text: str, limit: int = _MAX_U32) -> int:
    import argparse

    if not (text.isascii() and text.isdigit()):
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}")
    n = int(text)
    if n > limit:
        raise argparse.ArgumentTypeError(f"too large: {text} (at most {limit:,})")
    return n


def _nodes_arg(text: str) -> int:
    return _count_arg(text, _MAX_U64)


def _picture_options(sp: argparse.ArgumentParser) -> None:
    sp.add_argument(
        "--max-nodes",
        type=_nodes_arg,
        metavar="N",
        help=f"largest picture drawn, in nodes (default: {foon.MAX_PICTURE_NODES:,})",
    )
    sp.add_argument(
        "--cost-scale",
        type=_count_arg,
        metavar="N",
        help="pddl: action cost = round(-ln(rate) * N) (default: 1000)",
    )


def _export_options(sp: argparse.ArgumentParser, draw: bool = False) -> None:
    sp.add_argument("file", metavar="FILE", help="FOON file")
    pictures = ["svg", "png", "pdf", "dot"]
    sp.add_argument(
        "--format",
        choices=pictures if draw else _formats(2),
        default="svg" if draw else None,
        required=not draw,
        help="default: svg" if draw else "output format",
    )
    g = sp.add_mutually_exclusive_group()
    g.add_argument("--goal", metavar="JSON", help="the object in focus (the goal), as JSON")
    g.add_argument("--label", metavar="TEXT", help="the object in focus, by a label one has")
    sp.add_argument(
        "--depth",
        type=_count_arg,
        metavar="N",
        default=None,
        help="only the units within N steps of the goal (0: those that make or use it)"
        + ("; default: 1 with a goal" if draw else ""),
    )
    sp.add_argument("--kitchen", metavar="FILE", help="kitchen (marked; PDDL's initial state)")
    sp.add_argument("--utensils", metavar="FILE", help="utensil list (container rule)")
    sp.add_argument("--motions", metavar="FILE", help="motion success rates (GraphML, PDDL)")
    sp.add_argument("-o", "--out", metavar="PATH", help="write to PATH (default: stdout)")
    sp.add_argument("--strict", action="store_true", help="turn load warnings into errors")
    _picture_options(sp)


def _draw_options(sp: argparse.ArgumentParser) -> None:
    _export_options(sp, draw=True)


def _command_module(name: str) -> Any:
    """The module that implements command ``name``."""
    import importlib

    if name in _OWN_MODULE:
        return importlib.import_module(f"foon._cli_{name}")
    return importlib.import_module("foon._cli_commands")


def _options(name: str) -> Callable[[argparse.ArgumentParser], None]:
    if name in _OWN_MODULE:
        fn: Callable[[argparse.ArgumentParser], None] = getattr(
            _command_module(name), f"add_{name}_options"
        )
        return fn
    return _OPTIONS[name]


_OPTIONS: dict[str, Callable[[argparse.ArgumentParser], None]] = {
    "plan": _plan_options,
    "compare": _compare_options,
    "verify": _verify_options,
    "check": _check_options,
    "stats": _stats_options,
    "export": _export_options,
    "draw": _draw_options,
}


def _quiet_closed_pipe() -> None:
    """The Python convention for a closed stdout: send what is still buffered to devnull so
    that the interpreter's final flush does not fail again (see the ``signal`` docs, "Note
    on SIGPIPE")."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        pass


def _guard_closed_stdout() -> None:
    """Started with stdout closed (``>&-``, Python then has no ``sys.stdout``): fd 1 is
    reopened read-only on devnull, so that no file the command opens takes its place, and
    writing output fails (EBADF) with a one-line error as for any program; a command that
    writes only files (``--out``, ``-o``) runs as usual."""
    if sys.stdout is not None:
        return
    try:
        fd = os.open(os.devnull, os.O_RDONLY)
        if fd != 1:
            os.dup2(fd, 1)
            os.close(fd)
        sys.stdout = open(1, "w", encoding="utf-8", closefd=False)  # noqa: SIM115
    except OSError:
        pass


class Terminated(KeyboardInterrupt):
    """SIGTERM, met as Ctrl-C is (by the commands that ask for it, :class:`SigtermStops`):
    work stops where it is, and what it leaves is whole."""


def _on_sigterm(signum: int, frame: object) -> None:
    raise Terminated


class SigtermStops:
    """While in (``with SigtermStops(): ...``), SIGTERM (``kill``, a job scheduler's time
    limit) stops the command as Ctrl-C does, with exit status 143 (``foon batch``: its
    manifest then lists every partition written); the default is put back on the way out.
    Not when SIGTERM is ignored or handled already (a parent's choice), nor off the main
    thread."""

    def __enter__(self) -> None:
        import signal

        self.caught = False
        try:
            if signal.getsignal(signal.SIGTERM) == signal.SIG_DFL:
                signal.signal(signal.SIGTERM, _on_sigterm)
                self.caught = True
        except ValueError:  # not the main thread
            pass

    def __exit__(self, *exc: object) -> None:
        if self.caught:
            import signal

            signal.signal(signal.SIGTERM, signal.SIG_DFL)


def main(argv: Sequence[str] | None = None) -> int:
    _guard_closed_stdout()
    try:
        return _run(list(sys.argv[1:] if argv is None else argv))
    except BrokenPipeError:
        _quiet_closed_pipe()
        return 1
    except Terminated:
        print("foon: terminated", file=sys.stderr)
        return 143
    except KeyboardInterrupt:
        print("foon: interrupted", file=sys.stderr)
        return 130


def _flush_or_quiet() -> None:
    """Flushes stdout; when it cannot be written (a full disk, a closed pipe), drops what is
    left so that the interpreter's last flush does not fail again with a traceback."""
    try:
        sys.stdout.flush()
    except OSError:
        _quiet_closed_pipe()


def _run(argv: list[str]) -> int:
    if argv == ["--version"]:
        # What the parser would print, without importing argparse (and re) to print it.
        try:
            print(f"foon {foon.__version__}")
            sys.stdout.flush()
        except BrokenPipeError:
            raise
        except OSError as e:
            _quiet_closed_pipe()
            error(e)
            return 1
        return 0
    parser = build_parser(argv[0] if argv and argv[0] in COMMANDS else "")
    try:
        try:
            args, extra = parser.parse_known_args(argv)
        except SystemExit as e:  # --help, or a usage error (argparse printed it)
            sys.stdout.flush()
            return e.code if isinstance(e.code, int) else 2
    except BrokenPipeError:
        raise
    except OSError as err:  # the help text could not be written
        _quiet_closed_pipe()
        error(err)
        return 1
    sub: argparse.ArgumentParser = args.parser
    if extra:
        # Reported by the command's own parser, with the command's usage line.
        try:
            sub.error(f"unrecognized arguments: {' '.join(extra)}")
        except SystemExit as e:
            return e.code if isinstance(e.code, int) else 2
    try:
        code: int = getattr(_command_module(args.cmd), "cmd_" + args.cmd)(args)
        sys.stdout.flush()
        return code
    except BrokenPipeError:
        raise
    except (CliError, foon.FoonError, OSError) as e:
        _flush_or_quiet()
        error(e)
        return 1
    except (UsageError, ValueError) as e:  # an option value the core rejects is one too
        _flush_or_quiet()
        sub.print_usage(sys.stderr)
        error(e)
        return 2
