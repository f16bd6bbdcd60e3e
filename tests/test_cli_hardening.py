"""The command line under adversarial use: ``--out`` names and atomicity, failed and missing
goals, closed pipes, FIFOs, bad ``--goal`` JSON, streaming output, start-up imports."""

from __future__ import annotations

import csv
import io
import json
import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import foon
import pytest
from foon._cli_out import file_names, file_stem, name_key
from foon.cli import main
from hypothesis import given, settings
from hypothesis import strategies as st
from workloads import chain_text

Capture = pytest.CaptureFixture[str]


def run(argv: list[str], capsys: Capture) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def run_process(argv: list[str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "foon", *argv],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def obj(label: str, *states: str) -> dict[str, object]:
    return {"label": label, "states": list(states), "ingredients": [], "container": None}


#: Water (raw) is in the kitchen; each goal is made from it by one unit.
def unit(label: str, state: str) -> str:
    return f"O\twater\nS\traw\nM\tfreeze\nO\t{label}\nS\t{state}\n//\n"


def small_world(tmp_path: Path, goals: list[tuple[str, str]]) -> list[str]:
    (tmp_path / "f.txt").write_text("".join(unit(label, s) for label, s in goals))
    (tmp_path / "k.json").write_text(json.dumps([obj("water", "raw")]))
    return [
        "--foon",
        str(tmp_path / "f.txt"),
        "--kitchen",
        str(tmp_path / "k.json"),
        "--goal",
        json.dumps([obj(label, s) for label, s in goals]),
    ]


# --- --out: one file per goal ----------------------------------------------------------------


def test_out_gives_every_goal_its_own_file(tmp_path: Path, capsys: Capture) -> None:
    composed, decomposed = "caf\u00e9", "cafe\u0301"  # two labels, one name on macOS
    goals = [("ice", "a"), ("ice", "b"), ("ice_2", "c"), (composed, "d"), (decomposed, "e")]
    out = tmp_path / "o"
    code, _, err = run(["plan", *small_world(tmp_path, goals), "--out", str(out)], capsys)
    assert code == 0, err
    # ice_2 is another goal's own name, so the second ice gets ice_3.
    names = ["ice.txt", "ice_3.txt", "ice_2.txt", f"{composed}.txt", f"{decomposed}_2.txt"]
    assert sorted(p.name for p in out.iterdir()) == sorted(names)
    f = foon.load(tmp_path / "f.txt")
    k = foon.Kitchen.load(tmp_path / "k.json")
    for name, (label, state) in zip(names, goals, strict=True):
        tree = f.plan(foon.Object(label, (state,)), k)
        assert tree.solved and (out / name).read_text() == tree.to_text(), name


labels = st.lists(
    st.sampled_from(
        [
            "ice",
            "Ice",
            "ICE",
            "ice_2",
            "ice_3",
            "Ice_2",
            "ice 2",
            "a/b",
            "a_b",
            "a:b",
            "",
            ".",
            "_",
            "ice_2_2",
        ]
    ),
    min_size=1,
    max_size=12,
)


@given(labels)
@settings(max_examples=300, deadline=None)
def test_file_names_never_collide(ls: list[str]) -> None:
    names = file_names(ls, ".txt")
    assert len(names) == len(ls)
    keys = [name_key(n) for n in names]
    assert len(set(keys)) == len(keys)  # distinct even on a case-insensitive file system
    assert names == file_names(ls, ".txt")  # deterministic
    seen: set[str] = set()
    for label, name in zip(ls, names, strict=True):
        stem = file_stem(label)
        assert name == stem + ".txt" or name.startswith(stem + "_")
        # The first goal with a name keeps it.
        assert (name == stem + ".txt") == (name_key(stem) not in seen)
        seen.add(name_key(stem))


cli_labels = st.lists(st.sampled_from(["ice", "ice_2", "ice 2", "ice_3", "ice_2_2", "a/b", "a_b",
                                       "a:b", "_", ".", "caf\u00e9", "cafe\u0301"]),
                      min_size=1, max_size=8)  # fmt: skip


@given(cli_labels)
@settings(max_examples=40, deadline=None)
def test_out_writes_one_file_per_goal_for_any_labels(ls: list[str]) -> None:
    import tempfile

    goals = [(label, f"s{i}") for i, label in enumerate(ls)]  # distinct goals, shared labels
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        out = root / "o"
        assert main(["plan", *small_world(root, goals), "--out", str(out), "-q"]) == 0
        names = file_names(ls, ".txt")
        assert sorted(p.name for p in out.iterdir()) == sorted(names)
        f = foon.load(root / "f.txt")
        k = foon.Kitchen.load(root / "k.json")
        for name, (label, state) in zip(names, goals, strict=True):
            assert (out / name).read_text() == f.plan(foon.Object(label, (state,)), k).to_text()


# --- --out: failed goals --------------------------------------------------------------------


@pytest.mark.parametrize("method", ["ids", "bfs"])
def test_out_writes_no_file_for_a_failed_goal(tmp_path: Path, capsys: Capture, method: str) -> None:
    ex = foon.example()
    out = tmp_path / "o"
    code, _, err = run(
        ["plan", "--goals", str(ex.paths["goals"]), "--method", method, "--out", str(out), "-q"],
        capsys,
    )
    assert code == 1
    names = sorted(p.name for p in out.iterdir())
    assert "tea_2.txt" not in names and len(names) == len(ex.goals) - 1
    # Even with -q, the failure is reported, and the summary says no file was written.
    assert "tea (hot) {lemon} in [mug]: FAILED" in err
    assert "1 of 6 goals not solved: no file written for it" in err


# --- --out: every file or none ---------------------------------------------------------------


def test_out_checks_every_destination_before_writing(tmp_path: Path, capsys: Capture) -> None:
    args = small_world(tmp_path, [("ice", "a"), ("tea", "b")])
    out = tmp_path / "o"
    (out / "tea.txt").mkdir(parents=True)  # a folder where the second file would go
    code, _, err = run(["plan", *args, "--out", str(out)], capsys)
    assert code == 1
    assert err == f"foon: error: {out / 'tea.txt'}: is a directory\n"
    assert sorted(p.name for p in out.iterdir()) == ["tea.txt"]  # nothing written, no temp


def test_out_must_be_a_folder(tmp_path: Path, capsys: Capture) -> None:
    args = small_world(tmp_path, [("ice", "a")])
    plain = tmp_path / "file"
    plain.write_text("x")
    for out in (plain, plain / "o"):
        code, _, err = run(["plan", *args, "--out", str(out)], capsys)
        assert code == 1
        assert err == f"foon: error: {plain}: not a directory\n"
    assert plain.read_text() == "x"


def test_out_rejects_a_name_too_long_before_writing(tmp_path: Path, capsys: Capture) -> None:
    long = "x" * 300
    args = small_world(tmp_path, [("ice", "a"), (long, "b")])
    out = tmp_path / "o"
    code, _, err = run(["plan", *args, "--out", str(out)], capsys)
    assert code == 1
    assert err.startswith(f"foon: error: {out / (long + '.txt')}: file name too long")
    assert err.count("\n") == 1 and ".tmp" not in err
    assert not out.exists() or list(out.iterdir()) == []


def test_out_failing_rename_leaves_nothing(
    tmp_path: Path, capsys: Capture, monkeypatch: pytest.MonkeyPatch
) -> None:
    args = small_world(tmp_path, [("ice", "a"), ("tea", "b"), ("jam", "c")])
    out = tmp_path / "o"
    real = os.replace
    calls: list[str] = []

    def replace(src: str, dst: str) -> None:
        calls.append(dst)
        if len(calls) == 2:
            raise PermissionError(13, "Permission denied")
        real(src, dst)

    monkeypatch.setattr(os, "replace", replace)
    code, _, err = run(["plan", *args, "--out", str(out)], capsys)
    assert code == 1
    assert (
        err.splitlines()[-1] == f"foon: error: {out / 'tea.txt'}: cannot write: Permission denied"
    )
    assert not out.exists()  # the file already renamed, the temporary files, the folder


def test_out_failing_rename_puts_replaced_files_back(
    tmp_path: Path, capsys: Capture, monkeypatch: pytest.MonkeyPatch
) -> None:
    args = small_world(tmp_path, [("ice", "a"), ("tea", "b"), ("jam", "c")])
    out = tmp_path / "o"
    out.mkdir()
    (out / "ice.txt").write_text("an earlier tree\n")
    (out / "other.txt").write_text("not ours\n")
    real = os.replace

    def replace(src: str, dst: str) -> None:
        if str(dst).endswith("tea.txt"):
            raise OSError(28, "No space left on device")
        real(src, dst)

    monkeypatch.setattr(os, "replace", replace)
    code, _, err = run(["plan", *args, "--out", str(out)], capsys)
    assert code == 1
    assert err.splitlines()[-1] == (
        f"foon: error: {out / 'tea.txt'}: cannot write: No space left on device"
    )
    assert sorted(p.name for p in out.iterdir()) == ["ice.txt", "other.txt"]
    assert (out / "ice.txt").read_text() == "an earlier tree\n"


@pytest.mark.parametrize("mask", [0o022, 0o002, 0o077])
def test_out_files_have_the_usual_permissions(tmp_path: Path, capsys: Capture, mask: int) -> None:
    args = small_world(tmp_path, [("ice", "a")])
    old = os.umask(mask)
    try:
        code, _, err = run(["plan", *args, "--out", str(tmp_path / "o")], capsys)
    finally:
        os.umask(old)
    assert code == 0, err
    assert stat.S_IMODE((tmp_path / "o" / "ice.txt").stat().st_mode) == 0o666 & ~mask


def test_out_empty_is_a_usage_error(capsys: Capture) -> None:
    assert main(["plan", "--out", ""]) == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: foon plan ") and "--out: the folder name is empty" in err


# --- check: FIFOs and empty folders ----------------------------------------------------------


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_check_skips_fifos_in_a_folder_and_rejects_a_fifo(tmp_path: Path) -> None:
    (tmp_path / "a.txt").write_text("O\tcup\nS\tempty\nM\tfill\nO\tcup\nS\tfull\n//\n")
    os.mkfifo(tmp_path / "pipe.txt")
    p = run_process(["check", str(tmp_path)])  # would hang forever opening the FIFO
    assert p.returncode == 0, p.stderr
    assert p.stderr == "1 file checked: 0 errors, 0 warnings, 0 notes\n"
    p = run_process(["check", str(tmp_path / "pipe.txt")])
    assert p.returncode == 1
    assert p.stderr == f"foon: error: {tmp_path / 'pipe.txt'}: not a regular file\n"


def test_check_on_a_folder_without_foon_files(tmp_path: Path, capsys: Capture) -> None:
    (tmp_path / "notes.txt").write_text("hello\n")
    code, out, err = run(["check", str(tmp_path)], capsys)
    assert code == 1 and out == ""
    assert err.startswith(f"foon: error: {tmp_path}: no FOON file in this folder")


# --- a closed output pipe --------------------------------------------------------------------


def _big_outputs(tmp_path: Path) -> dict[str, list[str]]:
    n = 400
    (tmp_path / "chain.txt").write_text(chain_text(n))
    (tmp_path / "k.json").write_text(json.dumps([obj("item", "s0")]))
    (tmp_path / "g.json").write_text(json.dumps([obj("item", f"s{i}") for i in range(n + 1)]))
    dup = "O\tcup\nS\tempty\nM\tfill\nO\tcup\nS\tfull\n//\n" * 5000
    (tmp_path / "dup.txt").write_text(dup)
    world = [
        "--foon",
        str(tmp_path / "chain.txt"),
        "--kitchen",
        str(tmp_path / "k.json"),
        "--goals",
        str(tmp_path / "g.json"),
    ]
    example = str(foon.example().paths["foon"])
    return {
        "plan": ["plan", *world, "-q"],
        "check": ["check", str(tmp_path / "dup.txt")],
        "stats": ["stats", *[example] * 3000],
        # Four methods: the table (written at once) must be larger than what a pipe holds.
        "compare": ["compare", *world, "--methods", "ids,bfs,greedy-inputs,optimal-units"],
    }


@pytest.mark.parametrize("command", ["plan", "check", "stats", "compare"])
def test_closed_pipe_is_quiet(tmp_path: Path, command: str) -> None:
    argv = _big_outputs(tmp_path)[command]
    p = subprocess.Popen(
        [sys.executable, "-m", "foon", *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    assert p.stdout is not None and p.stderr is not None
    first = p.stdout.readline()
    assert first  # the output had begun
    p.stdout.close()  # as `| head -1` does
    err = p.stderr.read().decode()
    code = p.wait(timeout=120)
    p.stderr.close()
    assert "Broken pipe" not in err and "Traceback" not in err and "Exception" not in err
    if command == "check":
        assert "foon: error" not in err
    assert code == 1


# --- goals: empty lists, bad JSON, --threads -------------------------------------------------


@pytest.mark.parametrize("command", ["plan", "compare"])
def test_empty_goal_list_is_an_error(tmp_path: Path, capsys: Capture, command: str) -> None:
    code, out, err = run([command, "--goal", "[]"], capsys)
    assert (code, out) == (1, "")
    assert err == "foon: error: --goal: the goal list is empty\n"
    empty = tmp_path / "goals.json"
    empty.write_text("[]")
    code, out, err = run([command, "--goals", str(empty)], capsys)
    assert (code, out) == (1, "")
    assert err == f"foon: error: {empty}: the goal list is empty\n"


BAD_GOALS = [
    '{"label": "ice", "container": 5}',
    '{"label": "ice", "states": [1]}',
    '{"label": "ice", "states": [NaN]}',
    "[" * 50_000 + "]" * 50_000,
    '{"label": "ice", "states": 5}',
    "[1, 2]",
]


@pytest.mark.parametrize("command", ["plan", "compare", "verify"])
@pytest.mark.parametrize("text", BAD_GOALS, ids=range(len(BAD_GOALS)))
def test_bad_goal_json_is_one_line(tmp_path: Path, command: str, text: str) -> None:
    tree = tmp_path / "t.txt"
    tree.write_text("//\n")
    extra = [str(tree)] if command == "verify" else []
    p = run_process([command, "--goal", text, *extra])
    assert p.returncode == 1 and p.stdout == ""
    assert p.stderr.startswith("foon: error: --goal:1:") and p.stderr.count("\n") == 1, p.stderr


@pytest.mark.parametrize(
    "value", ["99999999999999999999", "0", "-3", "two", "1e3", "1_000", "\u0663"]
)
@pytest.mark.parametrize("command", ["plan", "compare"])
def test_threads_is_checked_by_the_parser(value: str, command: str) -> None:
    p = run_process([command, "--threads", value])
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert p.stderr.startswith(f"usage: foon {command} ")
    assert f"foon {command}: error: argument --threads: " in p.stderr


# --- goals missing from the FOON -------------------------------------------------------------


def _with_a_missing_goal() -> list[dict[str, object]]:
    ex = foon.example()
    return [ex.goals[0].to_dict(), obj("unicorn", "magic"), ex.goals[1].to_dict()]


# The example has no unicorn: the message names the nearest objects (METHODS.md, "Finding
# objects by text").
UNICORN_NOT_FOUND = (
    "The goal node does not exist: unicorn (magic); nearest: salad fork; ice tray (empty); "
    "onion (whole)"
)


def test_plan_goes_on_after_a_missing_goal(capsys: Capture) -> None:
    ex = foon.example()
    goals = json.dumps(_with_a_missing_goal())
    code, out, err = run(["plan", "--goal", goals], capsys)
    assert code == 1
    trees = [
        ex.foon.plan(g, ex.kitchen, motions=ex.motions, utensils=ex.utensils).to_text()
        for g in ex.goals[:2]
    ]
    assert out == (
        f"# goal: {ex.goals[0]}\n{trees[0]}# goal: unicorn (magic)\n"
        f"# goal: {ex.goals[1]}\n{trees[1]}"
    )
    lines = err.splitlines()
    assert len(lines) == 3
    assert lines[1] == f"unicorn (magic): FAILED: {UNICORN_NOT_FOUND}"
    code, out, err = run(["plan", "--goal", goals, "--format", "json"], capsys)
    assert code == 1
    items = json.loads(out)
    assert [d["solved"] for d in items] == [True, False, True]
    assert items[1] == {
        "goal": obj("unicorn", "magic"),
        "method": "ids",
        "solved": False,
        "error": UNICORN_NOT_FOUND,
    }


def test_compare_goes_on_after_a_missing_goal(capsys: Capture) -> None:
    code, out, err = run(
        [
            "compare",
            "--goal",
            json.dumps(_with_a_missing_goal()),
            "--json",
            "--methods",
            "ids,greedy-success",
        ],
        capsys,
    )
    assert code == 1
    d = json.loads(out)
    assert [(r["method"], r["solved"], r["error"] is not None) for r in d["rows"]] == [
        (m, s, e)
        for m in ("ids", "greedy-success")
        for s, e in ((True, False), (False, True), (True, False))
    ]
    assert [(s["solved_count"], s["goals"]) for s in d["summary"]] == [(2, 3), (2, 3)]
    assert err == f"foon: error: unicorn (magic): FAILED: {UNICORN_NOT_FOUND}\n"


def test_compare_without_rates_skips_the_methods_that_need_them(capsys: Capture) -> None:
    ex = foon.example()
    need_rates = set()
    for m in foon.METHODS:
        try:
            ex.foon.plan_many(ex.goals, ex.kitchen, m, utensils=ex.utensils)
        except foon.MissingRateError:
            need_rates.add(m)
    assert need_rates  # the example has methods that need rates
    code, out, err = run(
        [
            "compare",
            "--foon",
            str(ex.paths["foon"]),
            "--kitchen",
            str(ex.paths["kitchen"]),
            "--utensils",
            str(ex.paths["utensils"]),
            "--goals",
            str(ex.paths["goals"]),
            "--json",
        ],
        capsys,
    )
    assert code == 0, err
    ran = [s["method"].removesuffix(" (course)") for s in json.loads(out)["summary"]]
    assert ran == [m for m in foon.METHODS if m not in need_rates]
    notes = err.splitlines()
    assert [n.split()[2] for n in notes] == [m for m in foon.METHODS if m in need_rates]
    assert all(n.startswith("foon: note: ") and "--motions FILE" in n for n in notes)


# --- smaller ones ----------------------------------------------------------------------------


def test_compare_csv_summary_rows_have_their_own_columns(capsys: Capture) -> None:
    assert main(["compare", "--csv", "--methods", "ids,bfs,ids"]) == 0
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    goals = len(foon.example().goals)
    assert len(rows) == 2 * goals + 2  # ids once: the repeated method is dropped
    per_goal, summary = rows[: 2 * goals], rows[2 * goals :]
    assert [r["method"] for r in summary] == ["ids", "bfs (course)"]
    assert {r["solved"] for r in per_goal} == {"True", "False"}
    for s in summary:
        assert s["goal"] == "(all)" and s["solved"] == "" and s["seconds"] == ""
        mine = [r for r in per_goal if r["method"] == s["method"]]
        assert int(s["solved_count"]) == sum(r["solved"] == "True" for r in mine)
        assert int(s["goals"]) == len(mine)
        assert float(s["seconds_total"]) == pytest.approx(sum(float(r["seconds"]) for r in mine))
    for r in per_goal:
        assert r["solved_count"] == r["goals"] == r["seconds_total"] == ""


def test_compare_usage_errors_show_the_compare_usage(capsys: Capture) -> None:
    assert main(["compare", "--methods", "ids,astar"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: foon compare ") and "unknown method 'astar'" in err


@pytest.mark.parametrize(
    "argv",
    [["plan", "--default-rate", "2"], ["plan", "--method", "optimal-units", "--compat", "course"]],
)
def test_option_values_the_core_rejects_are_usage_errors(capsys: Capture, argv: list[str]) -> None:
    code, out, err = run(argv, capsys)
    assert code == 2 and out == ""
    usage, _, message = err.partition("\nfoon: error: ")
    assert usage.startswith("usage: foon plan ") and message.count("\n") == 1


@pytest.mark.parametrize("command", ["plan", "verify"])
def test_ambiguous_label_is_one_line(tmp_path: Path, capsys: Capture, command: str) -> None:
    tree = tmp_path / "t.txt"
    tree.write_text("//\n")
    extra = [str(tree)] if command == "verify" else []
    code, out, err = run([command, "--label", "onion", *extra], capsys)
    assert code == 1 and out == ""
    assert err.count("\n") == 1 and "matches 4 objects" in err and "onion (peeled)" in err


def test_verify_tree_warnings_are_one_line_and_strict(tmp_path: Path) -> None:
    ex = foon.example()
    tree = tmp_path / "t.txt"
    text = ex.foon.plan(ex.goals[0], ex.kitchen, utensils=ex.utensils).to_text()
    tree.write_text(text.removesuffix("//\n"))  # no final //: a warning
    goal = json.dumps(ex.goals[0].to_dict())
    p = run_process(["verify", "--goal", goal, str(tree)])
    assert p.returncode == 0, p.stderr
    assert p.stderr.startswith(f"foon: warning: {tree}:") and p.stderr.count("\n") == 1
    assert "FoonWarning" not in p.stderr
    p = run_process(["verify", "--goal", goal, "--strict", str(tree)])
    assert p.returncode == 1 and p.stdout == ""
    assert p.stderr.startswith(f"foon: error: {tree}:") and p.stderr.count("\n") == 1


# --- streaming output ------------------------------------------------------------------------


@pytest.mark.parametrize("fmt", ["json", "text"])
def test_output_is_the_same_in_chunks(
    capsys: Capture, monkeypatch: pytest.MonkeyPatch, fmt: str
) -> None:
    ex = foon.example()
    argv = ["plan", "--goals", str(ex.paths["goals"]), "--format", fmt, "-q"]
    assert main(argv) == 1
    whole = capsys.readouterr()
    from foon import _cli_commands

    monkeypatch.setattr(_cli_commands, "CHUNK", 4)  # 6 goals: two chunks
    assert main(argv) == 1
    chunked = capsys.readouterr()
    assert chunked.err == whole.err
    if fmt == "text":
        assert chunked.out == whole.out
        return
    a, b = json.loads(whole.out), json.loads(chunked.out)
    for d in (*a, *b):
        d.pop("seconds")
    assert a == b

    # The list written item by item is laid out as json.dumps(indent=2) lays out the whole
    # list: the same lines with the same indentation (numbers are written the shortest way,
    # which may differ from Python's float repr, e.g. 1e-5 for 1e-05).
    def layout(text: str) -> list[tuple[int, str]]:
        return [(len(ln) - len(ln.lstrip(" ")), ln.strip()[:1]) for ln in text.splitlines()]

    assert layout(chunked.out) == layout(json.dumps(json.loads(chunked.out), indent=2))
    want = [
        t.to_dict()
        for t in ex.foon.plan_many(ex.goals, ex.kitchen, motions=ex.motions, utensils=ex.utensils)
    ]
    for d in want:
        d.pop("seconds")
    assert a == want


# --- start-up --------------------------------------------------------------------------------

_IMPORTS = """
import sys
import foon
def fail(*a, **k):
    raise AssertionError("the example was loaded")
foon.example = fail
# What a command may need but --version must not import (foon itself may have loaded some:
# they are forgotten and blocked, so that an import of them in foon.cli fails).
BLOCKED = ("json", "csv", "tempfile", "pathlib", "dataclasses", "importlib.resources",
           "unicodedata", "typing", "collections.abc", "argparse", "re")
def blocked(name):
    return name in BLOCKED or name.startswith(tuple(b + "." for b in BLOCKED))
for name in list(sys.modules):
    if blocked(name):
        del sys.modules[name]
class Block:
    def find_spec(self, name, path=None, target=None):
        if blocked(name):
            raise ImportError(f"{name} imported")
sys.meta_path.insert(0, Block())
before = set(sys.modules)
import foon.cli
assert foon.cli.main(["--version"]) == 0
print("imported:", *sorted(set(sys.modules) - before))
"""


def test_version_imports_nothing_more() -> None:
    p = subprocess.run(
        [sys.executable, "-c", _IMPORTS], capture_output=True, text=True, timeout=60, check=True
    )
    assert p.stdout.splitlines()[-1].split() == ["imported:", "foon.cli"]


json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(), inner, max_size=4),
    max_leaves=30,
)


def test_compare_with_no_method_left_is_an_error(capsys: Capture) -> None:
    ex = foon.example()
    code, out, err = run(["compare", "--foon", str(ex.paths["foon"]), "--kitchen",
                          str(ex.paths["kitchen"]), "--goals", str(ex.paths["goals"]),
                          "--methods", "greedy-success"], capsys)  # fmt: skip
    assert code == 1 and out == ""
    assert err.splitlines()[0].startswith("foon: note: greedy-success skipped: ")
    assert err.splitlines()[1:] == ["foon: error: no method could run"]


def test_the_foon_command_imports_only_the_command_line() -> None:
    """The installed ``foon`` script is the package's own launcher: ``foon --version`` imports
    ``foon``, ``foon.cli`` and nothing that Python itself does not (pip's generated launchers
    import ``re`` first, which alone costs as much as starting Python)."""
    script = shutil.which("foon", path=os.path.dirname(sys.executable))
    if script is None:
        if os.environ.get("FOON_REQUIRE_DATA"):
            pytest.fail("the foon command is not installed beside this Python")
        pytest.skip("the foon command is not installed beside this Python (maturin develop)")
    env = {**os.environ, "PYTHONPROFILEIMPORTTIME": "1"}
    p = subprocess.run([script, "--version"], capture_output=True, text=True, env=env,
                       timeout=60, check=True)  # fmt: skip
    assert p.stdout == f"foon {foon.__version__}\n"
    imported = {line.rsplit("|", 1)[-1].strip() for line in p.stderr.splitlines()
                if line.startswith("import time:")}  # fmt: skip
    base = subprocess.run([sys.executable, "-c", "pass"], capture_output=True, text=True,
                          env=env, timeout=60, check=True).stderr  # fmt: skip
    python_own = {line.rsplit("|", 1)[-1].strip() for line in base.splitlines()
                  if line.startswith("import time:")}  # fmt: skip
    allowed = {"__future__", "foon", "foon._foon", "foon.cli"}
    assert imported - python_own <= allowed, imported - python_own
    assert "re" not in imported and "argparse" not in imported


def test_a_goal_whose_search_meets_an_unrated_motion_is_its_own_failure(
    tmp_path: Path, capsys: Capture
) -> None:
    """A motion without a rate stops only the goals whose search meets it: the others are
    planned and the output stays whole (one parseable JSON list, an entry per goal)."""
    fp = tmp_path / "f.txt"
    fp.write_text(
        "O\ta\nS\traw\nM\tcut\nO\ta\nS\tcut\n//\nO\tb\nS\traw\nM\tboil\nO\tb\nS\thot\n//\n"
    )
    kitchen = tmp_path / "k.json"
    kitchen.write_text(
        json.dumps([{"label": "a", "states": ["raw"]}, {"label": "b", "states": ["raw"]}])
    )
    rates = tmp_path / "m.txt"
    rates.write_text("cut\t0.5\n")
    goals = tmp_path / "g.json"
    goals.write_text(
        json.dumps([{"label": "b", "states": ["hot"]}, {"label": "a", "states": ["cut"]}])
    )
    base = ["plan", "--foon", str(fp), "--kitchen", str(kitchen), "--motions", str(rates),
            "--goals", str(goals), "--method", "greedy-success"]  # fmt: skip
    code, out, err = run([*base, "--format", "json"], capsys)
    assert code == 1
    items = json.loads(out)
    assert [i["solved"] for i in items] == [False, True]
    assert "boil" in items[0]["error"] and items[1]["units"] == [0]
    assert "b (hot): FAILED:" in err and "boil" in err
    code, out, err = run(base, capsys)
    assert code == 1 and out.count("# goal:") == 2 and "M\tcut" in out


@pytest.mark.parametrize(
    "argv", [["--version"], ["--help"], ["plan", "--help"], ["stats", "--help"]]
)
def test_version_and_help_on_a_full_disk_or_a_closed_pipe(argv: list[str]) -> None:
    """Output that cannot be written is an error (exit 1), never a traceback nor a silent
    success."""
    full = Path("/dev/full")
    if full.exists():
        with full.open("w") as out:
            p = subprocess.run([sys.executable, "-m", "foon", *argv], check=False, stdout=out,
                               stderr=subprocess.PIPE, text=True, timeout=60)  # fmt: skip
        assert p.returncode == 1 and "Traceback" not in p.stderr
        assert p.stderr.startswith("foon: error: ") and p.stderr.count("\n") == 1
    with subprocess.Popen([sys.executable, "-m", "foon", *argv], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True) as q:  # fmt: skip
        assert q.stdout is not None and q.stderr is not None
        q.stdout.close()
        err = q.stderr.read()
        code = q.wait(timeout=60)
    assert code == 1 and err == ""


def test_check_finds_foon_files_with_a_byte_order_mark_and_skips_look_alikes(
    tmp_path: Path, capsys: Capture
) -> None:
    (tmp_path / "bom.txt").write_bytes(
        b"\xef\xbb\xbfO\tonion\nS\twhole\nM\tchop\nO\tonion\nS\tchopped\n//\n"
    )
    (tmp_path / "notes.txt").write_text("Oops\tnot a FOON file\n")
    code, _, err = run(["check", str(tmp_path)], capsys)
    assert code == 0
    assert err == "1 file checked (1 non-FOON .txt file skipped): 0 errors, 0 warnings, 0 notes\n"


@pytest.mark.parametrize("spelling", ["trees/", "trees//", "deep/er/trees/"])
def test_out_folder_with_a_trailing_separator_is_created(
    tmp_path: Path, capsys: Capture, spelling: str
) -> None:
    ex = foon.example()
    _, _, err = run(
        ["plan", "--goals", str(ex.paths["goals"]), "--out", str(tmp_path) + "/" + spelling],
        capsys,
    )
    assert "error" not in err, err
    made = sorted(p.name for p in (tmp_path / spelling.rstrip("/")).iterdir())
    assert made and all(name.endswith(".txt") for name in made)
