"""Start-up of the ``foon`` command: whole processes side by side in one run.

    python benchmarks/startup.py [--data ../shared/data/foon] [--runs 30] [--before OLD_CLI_PY]

Times ``python -c pass``, ``python -c "import foon"``, ``foon --version``, ``foon stats
FOON.txt`` and ``foon plan`` on the 25 course goals with a loop of ``subprocess.run`` calls
that takes the commands in turn (so that a machine whose speed drifts slows every command
alike), or with hyperfine (``--hyperfine``: ``--shell=none``, each command's runs in a row);
prints a Markdown table (medians, and the ratio to ``python -c pass`` of the same run), then
the slowest imports of ``import foon`` and what ``import foon.cli`` adds (``-X importtime``,
the best of 5).

The commands run with bytecode caching on, as an installed package has it:
``PYTHONDONTWRITEBYTECODE`` is removed from their environment (with it, every run compiles
``foon``'s own modules again, about 20 ms), and the warm-up runs write the caches.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


#: What the launcher script does, less its own ``import re``.
MAIN = "import sys; from foon.cli import main; sys.argv[0] = 'foon'; sys.exit(main())"


def commands(data: Path, before: Path | None = None) -> list[tuple[str, list[str]]]:
    """The commands to time; with ``before`` (a copy of an earlier ``foon/cli.py``), the
    three ``foon`` commands also run through that CLI, on the same ``foon`` package."""
    py = sys.executable
    script = shutil.which("foon", path=os.path.dirname(py)) or shutil.which("foon")
    if script is None:
        sys.exit("the foon command is not installed beside this Python")
    d = str(data)
    plan = ["plan", "--foon", f"{d}/FOON.txt", "--kitchen", f"{d}/kitchen.json",
            "--motions", f"{d}/motion.txt", "--utensils", f"{d}/utensils.txt",
            "--goals", f"{d}/goal_nodes_25.json", "-q"]  # fmt: skip
    out = [
        ("python -c pass", [py, "-c", "pass"]),
        ('python -c "import foon"', [py, "-c", "import foon"]),
        ("foon --version", [script, "--version"]),
        # The same without the installer's launcher script, which imports re for itself.
        ("foon --version, no launcher", [py, "-c", MAIN, "--version"]),
        ('python -c "import re"', [py, "-c", "import re"]),
        ("foon stats FOON.txt", [script, "stats", f"{d}/FOON.txt"]),
        ("foon plan (25 course goals)", [script, *plan]),
    ]
    if before is not None:
        # What the installed script does (import the CLI, call main), with the old CLI.
        run = ("import sys, importlib.util as u; s = u.spec_from_file_location('cli', "
               f"{str(before)!r}); m = u.module_from_spec(s); s.loader.exec_module(m); "
               "sys.argv[0] = 'foon'; sys.exit(m.main())")  # fmt: skip
        out += [
            ("before: foon --version", [py, "-c", run, "--version"]),
            ("before: foon stats FOON.txt", [py, "-c", run, "stats", f"{d}/FOON.txt"]),
            ("before: foon plan (25 course goals)", [py, "-c", run, *plan]),
        ]
    return out


def check_outputs(cmds: list[tuple[str, list[str]]]) -> None:
    """Each command runs and succeeds once before it is timed."""
    for name, argv in cmds:
        p = subprocess.run(argv, capture_output=True, text=True, check=False)
        # The 25 course goals include two that cannot be made: plan exits 1 by design.
        ok = p.returncode == 0 or ("foon plan" in name and p.returncode == 1)
        if not ok:
            sys.exit(f"{name} failed ({p.returncode}): {p.stderr.strip()}")


def with_hyperfine(cmds: list[tuple[str, list[str]]], runs: int) -> dict[str, float]:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "h.json"
        argv = ["hyperfine", "--shell=none", "--warmup", "3", "--runs", str(runs), "-i",
                "--style", "none", "--export-json", str(out)]  # fmt: skip
        for name, cmd in cmds:
            argv += ["--command-name", name, " ".join(_quote(a) for a in cmd)]
        subprocess.run(argv, check=True, stdout=subprocess.DEVNULL)
        results = json.loads(out.read_text())["results"]
    return {r["command"]: statistics.median(r["times"]) for r in results}


def _quote(a: str) -> str:
    # hyperfine --shell=none splits the command line like a shell does (quotes, no globs).
    return "'" + a.replace("'", "'\"'\"'") + "'" if any(c in a for c in " \"'") else a


def with_loop(cmds: list[tuple[str, list[str]]], runs: int) -> dict[str, float]:
    times: dict[str, list[float]] = {name: [] for name, _ in cmds}
    for _ in range(3):  # warm-up
        for _, argv in cmds:
            subprocess.run(argv, capture_output=True, check=False)
    for _ in range(runs):  # interleaved, so that drift hits every command alike
        for name, argv in cmds:
            t = time.perf_counter()
            subprocess.run(argv, capture_output=True, check=False)
            times[name].append(time.perf_counter() - t)
    return {name: statistics.median(ts) for name, ts in times.items()}


def importtime(code: str) -> list[tuple[int, int, str]]:
    """(self µs, cumulative µs, module) of every import ``code`` makes (``-X importtime``)."""
    p = subprocess.run([sys.executable, "-X", "importtime", "-c", code],
                       capture_output=True, text=True, check=True)  # fmt: skip
    rows = []
    for line in p.stderr.splitlines():
        if not line.startswith("import time:") or "self [us]" in line:
            continue
        self_us, cum_us, name = line.removeprefix("import time:").split("|")
        rows.append((int(self_us), int(cum_us), name.rstrip()))
    return rows


def slowest_imports(n: int = 8) -> list[tuple[int, int, str]]:
    """The slowest imports of ``import foon``, each module's best of 5 runs (the row of
    ``foon`` itself has the whole import as its cumulative time)."""
    best: dict[str, tuple[int, int, str]] = {}
    for _ in range(5):
        for self_us, cum_us, name in importtime("import foon"):
            old = best.get(name)
            best[name] = (self_us, cum_us, name) if old is None else (
                min(old[0], self_us), min(old[1], cum_us), name)  # fmt: skip
    return sorted(best.values(), key=lambda r: -r[0])[:n]


def cli_import_us() -> int:
    """What ``import foon.cli`` adds to ``import foon`` (cumulative µs, the best of 5)."""
    return min(
        next(
            c
            for _, c, name in importtime("import foon; import foon.cli")
            if name.strip() == "foon.cli"
        )
        for _ in range(5)
    )


#: Times ``foon.cli.main(argv)`` in one process once everything is imported and warm: the
#: work of a command (parsing its arguments and files, planning, writing), without start-up.
_WORK = """
import contextlib, io, json, statistics, sys, time
from foon.cli import main
argv, runs = json.loads(sys.argv[1]), int(sys.argv[2])
times = []
for i in range(runs + 1):
    out, err = io.StringIO(), io.StringIO()
    t = time.perf_counter()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        main(argv)
    if i:
        times.append(time.perf_counter() - t)
print(statistics.median(times))
"""


def work_seconds(argv: list[str], runs: int) -> float:
    """The median in-process time of ``foon ARGV`` (see ``_WORK``)."""
    p = subprocess.run([sys.executable, "-c", _WORK, json.dumps(argv), str(runs)],
                       capture_output=True, text=True, check=True)  # fmt: skip
    return float(p.stdout)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=HERE.parent.parent / "shared/data/foon")
    ap.add_argument("--runs", type=int, default=30)
    ap.add_argument("--hyperfine", action="store_true", help="time with hyperfine")
    ap.add_argument("--before", type=Path, metavar="CLI_PY",
                    help="also time the foon commands through this earlier foon/cli.py")  # fmt: skip
    args = ap.parse_args()
    os.environ.pop("PYTHONDONTWRITEBYTECODE", None)  # the children inherit os.environ
    cmds = commands(args.data, args.before)
    check_outputs(cmds)
    use_hf = args.hyperfine
    if use_hf and shutil.which("hyperfine") is None:
        sys.exit("hyperfine is not installed")
    medians = (with_hyperfine if use_hf else with_loop)(cmds, args.runs)
    base = medians["python -c pass"]
    how = "hyperfine --shell=none" if use_hf else "subprocess.run, the commands in turn"
    print(f"\n### Start-up (median of {args.runs} runs, {how})\n")
    print("| command | median | / `python -c pass` |")
    print("|---|---:|---:|")
    for name, _ in cmds:
        print(f"| `{name}` | {1000 * medians[name]:.1f} ms | {medians[name] / base:.2f} |")
    print("\n### The slowest imports of `import foon` (`python -X importtime`)\n")
    print("| module | self | cumulative |")
    print("|---|---:|---:|")
    for self_us, cum_us, name in slowest_imports():
        print(f"| `{name.strip()}` | {self_us / 1000:.1f} ms | {cum_us / 1000:.1f} ms |")
    print(f"\n`import foon.cli` adds {cli_import_us() / 1000:.1f} ms to `import foon`.")
    print("\n### Start-up over the work itself\n")
    print(
        "| command | median | work (in-process) | start-up = median - work | / `python -c pass` |"
    )
    print("|---|---:|---:|---:|---:|")
    for name, argv in cmds:
        if name in ("foon stats FOON.txt", "foon plan (25 course goals)"):
            work = work_seconds(argv[1:], args.runs)
            over = medians[name] - work
            print(f"| `{name}` | {1000 * medians[name]:.1f} ms | {1000 * work:.1f} ms | "
                  f"{1000 * over:.1f} ms | {over / base:.2f} |")  # fmt: skip


if __name__ == "__main__":
    main()
